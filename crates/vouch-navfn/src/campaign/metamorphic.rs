//! Metamorphic relations between a run on a map and a run on its transform (docs/navfn-campaign.md
//! states them precisely). Approximate relations ([`RelationKind::exact`] false, named
//! `approx_*`): a violation is a *finding* about NavFn (it is not symmetric), not a failure.
//!
//! Exact relations (must hold on every case):
//! * `reachability@T` — if the transformed run did not stop at its cycle limit and the NavFn goal
//!   is traversable, the NavFn start has a finite potential ⇔ start and goal are 4-connected
//!   (connectivity is invariant under every transform, and NavFn's queues reach the whole
//!   component of the goal when nothing cuts them short);
//! * `properties@T` — every search-trace and final-state property holds on the transformed run;
//! * `embed_potential@embedP` — if the original run ended before its cycle limit, the run on the
//!   map embedded in a frame of P obstacle cells ends the same way after the same number of
//!   cycles, its potentials on the embedded cells are bit-identical and all others are 1e10
//!   (NavFn's update reads only relative neighbours; the frame is never queued);
//! * `embed_path@embedP` — under the same condition, if the original path was found and neither
//!   run's oscillation test fired, the embedded path has the same number of points and each point
//!   equals the shifted original within rounding: `|p' − (p + P)| ≤ 2·ε·max(W', H')` per
//!   coordinate, ε = 2⁻²³ (the point is `f32(x) ⊕ dx`, rounded at a larger magnitude).
//!
//! Approximate relations (rotations and mirrors; NavFn's fixed neighbour order breaks symmetry):
//! * `approx_start_potential@T` — both starts reached: potentials within [`APPROX_REL`] relative;
//! * `approx_path_cost@T` — both paths found (start ≠ goal): campaign-model costs within
//!   [`APPROX_REL`] relative.

use crate::campaign::names::{Relation, RelationKind};
use crate::campaign::transform::Transform;
use crate::core::{POT_HIGH, PropagationEnd};

/// Relative tolerance of the approximate relations.
pub const APPROX_REL: f64 = 0.25;

/// What a relation needs to know about one run.
#[derive(Clone, Debug)]
pub struct RunDigest {
    pub end: Option<(PropagationEnd, usize)>,
    pub len: usize,
    /// Potential of the NavFn start cell after propagation.
    pub start_pot: f32,
    /// NavFn's oscillation test fired on a recorded point.
    pub oscillated: bool,
    /// The path (first `len` points).
    pub path: Vec<[f32; 2]>,
    /// Campaign-model cost of the path (found paths only).
    pub cost: Option<f64>,
    /// No property violation on this run.
    pub properties_ok: bool,
}

impl RunDigest {
    fn cycle_limited(&self) -> bool {
        matches!(self.end, Some((PropagationEnd::CycleLimit, _)))
    }
    fn reached(&self) -> bool {
        self.start_pot < POT_HIGH
    }
}

/// One evaluated relation.
#[derive(Clone, Debug, PartialEq)]
pub struct RelationResult {
    /// The relation.
    pub relation: Relation,
    /// Whether it held.
    pub held: bool,
    /// Why not (empty when it held).
    pub detail: String,
}

/// Builds the results of one transform's relations.
struct Results {
    transform: Transform,
    out: Vec<RelationResult>,
}

impl Results {
    fn push(&mut self, kind: RelationKind, held: bool, detail: impl FnOnce() -> String) {
        let relation = Relation { kind, transform: self.transform };
        let detail = if held { String::new() } else { detail() };
        self.out.push(RelationResult { relation, held, detail });
    }
}

/// Inputs describing the original map for the relations.
pub struct OriginalCtx<'a> {
    pub width: u32,
    pub height: u32,
    /// Potential of the original run (for the embedding relation).
    pub potential: &'a [f32],
    /// Start and goal 4-connected (and the goal traversable): `Some(connected)`; `None` when the
    /// NavFn goal is an obstacle (reachability is then not defined by components).
    pub connected: Option<bool>,
}

/// Evaluate all relations of transform `t` between the original run `o` and the transformed `r`.
pub fn evaluate(
    t: Transform,
    ctx: &OriginalCtx<'_>,
    o: &RunDigest,
    r: &RunDigest,
    r_potential: &[f32],
) -> Vec<RelationResult> {
    let mut out = Results { transform: t, out: Vec::new() };
    if let (false, Some(conn)) = (r.cycle_limited(), ctx.connected) {
        out.push(RelationKind::Reachability, r.reached() == conn, || {
            format!("start reached = {}, but start and goal connected = {conn}", r.reached())
        });
    }
    out.push(RelationKind::Properties, r.properties_ok, || {
        "a property failed on the transformed map".into()
    });
    match t {
        Transform::Embed { pad } => {
            if !o.cycle_limited() {
                let (w, h) = (ctx.width as usize, ctx.height as usize);
                let w2 = w + 2 * pad as usize;
                let mut bad: Option<String> = None;
                if r.end != o.end {
                    bad = Some(format!("end {:?} vs original {:?}", r.end, o.end));
                }
                if bad.is_none() {
                    'cells: for (i, v) in r_potential.iter().enumerate() {
                        let (x, y) = (i % w2, i / w2);
                        let inner = x >= pad as usize
                            && y >= pad as usize
                            && x < w + pad as usize
                            && y < h + pad as usize;
                        let want = if inner {
                            ctx.potential[(y - pad as usize) * w + (x - pad as usize)]
                        } else {
                            POT_HIGH
                        };
                        if v.to_bits() != want.to_bits() {
                            bad = Some(format!("potential at ({x}, {y}) is {v}, expected {want}"));
                            break 'cells;
                        }
                    }
                }
                out.push(RelationKind::EmbedPotential, bad.is_none(), || {
                    bad.clone().unwrap_or_default()
                });
                if o.len > 0 && !o.oscillated && !r.oscillated {
                    let tol = 2.0
                        * f64::from(f32::EPSILON)
                        * f64::from((ctx.width + 2 * pad).max(ctx.height + 2 * pad));
                    let mut why = None;
                    if r.len != o.len {
                        why = Some(format!("{} points vs {} in the original", r.len, o.len));
                    } else {
                        for (k, (p, q)) in o.path.iter().zip(&r.path).enumerate() {
                            let (sx, sy) = t.point_f(ctx.width, ctx.height, (p[0], p[1]));
                            if (f64::from(q[0]) - sx).abs() > tol
                                || (f64::from(q[1]) - sy).abs() > tol
                            {
                                why = Some(format!(
                                    "point {k}: ({}, {}) vs shifted ({sx}, {sy})",
                                    q[0], q[1]
                                ));
                                break;
                            }
                        }
                    }
                    out.push(RelationKind::EmbedPath, why.is_none(), || {
                        why.clone().unwrap_or_default()
                    });
                }
            }
        }
        _ => {
            if o.reached() && r.reached() {
                let (a, b) = (f64::from(o.start_pot), f64::from(r.start_pot));
                let ok = (a - b).abs() <= APPROX_REL * a.max(b);
                out.push(RelationKind::ApproxStartPotential, ok, || {
                    format!("start potential {a} vs {b}")
                });
            }
            if let (Some(a), Some(b)) = (o.cost, r.cost)
                && (a > 0.0 || b > 0.0)
            {
                let ok = (a - b).abs() <= APPROX_REL * a.max(b);
                out.push(RelationKind::ApproxPathCost, ok, || {
                    format!("path cost {a:.1} vs {b:.1}")
                });
            }
        }
    }
    out.out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn digest(
        end: PropagationEnd,
        start_pot: f32,
        path: Vec<[f32; 2]>,
        cost: Option<f64>,
    ) -> RunDigest {
        RunDigest {
            end: Some((end, 4)),
            len: path.len(),
            start_pot,
            oscillated: false,
            path,
            cost,
            properties_ok: true,
        }
    }

    #[test]
    fn embedding_relations_hold_and_catch_a_changed_cell() {
        // 3x3 original, potential only in the centre cell; embed with pad 1 → 5x5.
        let mut pot = vec![POT_HIGH; 9];
        pot[4] = 0.0;
        let ctx = OriginalCtx { width: 3, height: 3, potential: &pot, connected: Some(true) };
        let o = digest(PropagationEnd::StartReached, 0.0, vec![[1.0, 1.0]], Some(0.0));
        let r = digest(PropagationEnd::StartReached, 0.0, vec![[2.0, 2.0]], Some(0.0));
        let mut rpot = vec![POT_HIGH; 25];
        rpot[12] = 0.0;
        let t = Transform::Embed { pad: 1 };
        let res = evaluate(t, &ctx, &o, &r, &rpot);
        assert!(res.iter().all(|x| x.held), "{res:?}");
        assert!(res.iter().any(|x| x.relation.to_string() == "embed_potential@embed1"));
        assert!(res.iter().any(|x| x.relation.to_string() == "embed_path@embed1"));
        rpot[0] = 5.0;
        let res = evaluate(t, &ctx, &o, &r, &rpot);
        let bad = res
            .iter()
            .find(|x| x.relation.to_string() == "embed_potential@embed1")
            .expect("evaluated");
        assert!(!bad.held && bad.detail.contains("(0, 0)"));
        // A shifted path point off by more than rounding breaks embed_path.
        let r2 = digest(PropagationEnd::StartReached, 0.0, vec![[2.01, 2.0]], Some(0.0));
        rpot[0] = POT_HIGH;
        let res = evaluate(t, &ctx, &o, &r2, &rpot);
        assert!(
            !res.iter()
                .find(|x| x.relation.to_string() == "embed_path@embed1")
                .expect("evaluated")
                .held
        );
    }

    #[test]
    fn reachability_must_match_connectivity_unless_cycle_limited() {
        let pot = vec![0.0f32; 4];
        let ctx = OriginalCtx { width: 2, height: 2, potential: &pot, connected: Some(true) };
        let o = digest(PropagationEnd::StartReached, 10.0, vec![], None);
        let unreached = digest(PropagationEnd::QueuesEmpty, POT_HIGH, vec![], None);
        let res = evaluate(Transform::Rot90, &ctx, &o, &unreached, &pot);
        assert!(
            !res.iter()
                .find(|x| x.relation.to_string() == "reachability@rot90")
                .expect("evaluated")
                .held
        );
        let limited = digest(PropagationEnd::CycleLimit, POT_HIGH, vec![], None);
        let res = evaluate(Transform::Rot90, &ctx, &o, &limited, &pot);
        assert!(
            res.iter().all(|x| x.relation.to_string() != "reachability@rot90"),
            "not applicable when cut by the cycle limit"
        );
        // Approximate: start potentials 10 vs 20 differ by 50 % > 25 %.
        let far = digest(PropagationEnd::StartReached, 20.0, vec![], None);
        let res = evaluate(Transform::MirrorX, &ctx, &o, &far, &pot);
        assert!(
            !res.iter()
                .find(|x| x.relation.to_string() == "approx_start_potential@mirror_x")
                .expect("evaluated")
                .held
        );
    }
}
