//! What the campaign measures on one case: outcome, search-trace and final-state properties,
//! reachability against connectivity, optimality and path shape, and the metamorphic relations
//! against the six transformed maps. A *unit* is a run of consecutive cases of one prepared map
//! sharing one NavFn and one optimum cache.

use std::collections::HashMap;
use std::time::Instant;

use crate::campaign::error::CampaignError;
use crate::campaign::exec::{CaseRun, navfn_ends, plan_checks, run_case};
use crate::campaign::grid::{Case, OBSTACLE, SuiteMap};
use crate::campaign::metamorphic::{self, OriginalCtx, RunDigest};
use crate::campaign::names::{Failed, FindingKind, Outcome, Property};
use crate::campaign::optimal::{dijkstra, path_cost, path_shape};
use crate::campaign::report::{CaseRecord, CategoryStats, Finding};
use crate::campaign::shard::Shard;
use crate::campaign::transform::Transform;
use crate::core::{Cell, POT_HIGH, PropagationEnd};
use crate::suite::{CaseRunner, RunMode};

/// What a campaign does.
#[derive(Clone, Debug)]
pub struct CampaignOptions {
    /// The call sequence every case runs in.
    pub mode: RunMode,
    /// The cases this process runs.
    pub shard: Shard,
    /// Run the metamorphic transforms (6 extra runs per case).
    pub metamorphic: bool,
    /// Compute the 8-connected optimum of every found path.
    pub optimality: bool,
    /// A path whose campaign-model cost exceeds the optimum by this factor is a counterexample.
    /// Both costs are of 8-connected cell paths in one metric, so every ratio above 1 is a real
    /// detour (none can be below 1); the default 1.10 keeps the findings to detours of 10 %.
    pub suboptimal_ratio: f64,
    /// Cases per work unit (a unit = consecutive cases of one map, sharing one NavFn and one
    /// optimum cache).
    pub unit_cases: usize,
}

impl Default for CampaignOptions {
    fn default() -> Self {
        CampaignOptions {
            mode: RunMode::Paper,
            shard: Shard::ALL,
            metamorphic: true,
            optimality: true,
            suboptimal_ratio: 1.10,
            unit_cases: 1024,
        }
    }
}

/// A loaded map with what every case on it shares.
pub struct PreparedMap {
    /// The map and its cases.
    pub map: SuiteMap,
    /// Costs as NavFn's set-up leaves them (border 254).
    pub setup_costs: Vec<u8>,
    /// 4-connected component of every cell.
    pub components: Vec<u32>,
    /// Its key in the suite (see [`crate::campaign::suite_io::SuiteEntry::key`]).
    pub key: String,
    /// Its home shard (see [`crate::campaign::shard`]) among the campaign's shards.
    pub home: u32,
    /// Transformed maps (same order as [`Transform::ALL_BASIC`]), when metamorphic testing is on.
    pub transformed: Vec<(Transform, SuiteMap, Vec<u8>)>,
}

fn stamped(m: &SuiteMap) -> Vec<u8> {
    let mut c = m.clone();
    c.stamp_border();
    c.costs
}

/// Prepares a map: set-up costs, components, and the transformed maps when asked for.
pub fn prepare(map: SuiteMap, metamorphic: bool) -> PreparedMap {
    let setup_costs = stamped(&map);
    let components = map.components().0;
    let transformed = if metamorphic {
        Transform::ALL_BASIC
            .iter()
            .map(|&t| {
                let tm = t.apply(&map);
                let tc = stamped(&tm);
                (t, tm, tc)
            })
            .collect()
    } else {
        Vec::new()
    };
    let key = format!("{}/{}", map.category, map.name);
    PreparedMap { map, key, home: 0, setup_costs, components, transformed }
}

/// Everything one unit produces.
#[derive(Default)]
pub struct UnitResult {
    /// The map's category.
    pub category: String,
    /// Counts over the unit's cases.
    pub stats: CategoryStats,
    /// What the cases showed.
    pub findings: Vec<Finding>,
    /// One record per case, when asked for.
    pub records: Vec<CaseRecord>,
    /// Time spent, seconds.
    pub seconds: f64,
}

/// Optimum distances from a NavFn goal, cached per unit (small maps) — the cost model is
/// symmetric, so one Dijkstra from the goal serves every start.
#[derive(Default)]
struct OptimumCache {
    full: HashMap<usize, Vec<f64>>,
}

const FULL_DIJKSTRA_MAX_CELLS: usize = 4096;

impl OptimumCache {
    fn optimum(&mut self, costs: &[u8], w: usize, h: usize, start: usize, goal: usize) -> f64 {
        if w * h <= FULL_DIJKSTRA_MAX_CELLS {
            let d = self.full.entry(goal).or_insert_with(|| dijkstra(costs, w, h, goal, None).0);
            d[start]
        } else {
            dijkstra(costs, w, h, goal, Some(start)).0[start]
        }
    }
}

fn digest(
    run: &CaseRun,
    runner: &CaseRunner,
    start: Cell,
    costs: &[u8],
    w: u32,
    h: u32,
) -> RunDigest {
    let nav = runner.nav();
    let path = nav.path().to_vec();
    let oscillated = path_shape(&to_pairs(nav.path_recorded())).oscillations > 0;
    let cost = (run.outcome.len > 0).then(|| path_cost(costs, w, h, &to_pairs(&path)));
    RunDigest {
        end: run.end,
        len: run.outcome.len,
        start_pot: nav.potential()[start.y * w as usize + start.x],
        oscillated,
        path,
        cost,
        properties_ok: run.violations.is_empty(),
    }
}

/// A path as coordinate pairs.
pub fn to_pairs(p: &[[f32; 2]]) -> Vec<(f32, f32)> {
    p.iter().map(|q| (q[0], q[1])).collect()
}

/// The state of one case while its results are gathered.
struct CaseCtx<'a> {
    pm: &'a PreparedMap,
    k: usize,
    case: &'a Case,
    record: Option<CaseRecord>,
}

impl CaseCtx<'_> {
    fn finding(&self, kind: FindingKind, detail: String, score: f64) -> Finding {
        let (m, c) = (&self.pm.map, self.case);
        Finding {
            kind,
            category: m.category.clone(),
            map: m.name.clone(),
            case: self.k as u64,
            coords: [c.x0, c.y0, c.x1, c.y1],
            detail,
            score,
            picture: None,
        }
    }

    fn failed(&mut self, f: Failed) {
        if let Some(r) = self.record.as_mut() {
            r.failed.push(f);
        }
    }
}

/// What a unit runs with.
struct Unit<'a> {
    opts: &'a CampaignOptions,
    per_case: bool,
    runner: CaseRunner,
    cache: OptimumCache,
    res: UnitResult,
}

impl Unit<'_> {
    /// Runs case `k` of `pm` and adds everything it shows to the unit's result.
    fn case(&mut self, pm: &PreparedMap, k: usize) -> Result<(), CampaignError> {
        let m = &pm.map;
        let (w, mode) = (m.width as usize, self.opts.mode);
        let case = &m.cases[k];
        let err =
            |source| CampaignError::Case { map: format!("{}/{}", m.category, m.name), source };
        self.res.stats.cases += 1;
        let run = run_case(&mut self.runner, m, &pm.setup_costs, case, mode, None).map_err(err)?;
        let (start, goal) = navfn_ends(mode, case);
        let (si, gi) = (start.y * w + start.x, goal.y * w + goal.x);
        let st = &mut self.res.stats;
        st.max_buffer_occupancy = st.max_buffer_occupancy.max(run.max_occupancy as u64);
        let goal_open = pm.setup_costs[gi] < OBSTACLE;
        let connected = goal_open
            .then(|| pm.components[si] != u32::MAX && pm.components[si] == pm.components[gi]);
        let reached = self.runner.nav().potential()[si] < POT_HIGH;
        // Outcome classes (as in golden/README.md: "truly unreachable" = not connected).
        let outcome = if si == gi {
            Outcome::StartIsGoal
        } else if run.outcome.len > 0 {
            Outcome::Found
        } else if reached {
            Outcome::PathFailed
        } else if connected == Some(false) {
            Outcome::Unreachable
        } else {
            Outcome::CycleLimit
        };
        st.outcomes.record(outcome);
        let record = self.per_case.then(|| CaseRecord {
            category: m.category.clone(),
            map: m.name.clone(),
            case: k as u64,
            coords: [case.x0, case.y0, case.x1, case.y1],
            outcome,
            path_points: run.outcome.len,
            ..CaseRecord::default()
        });
        let mut cx = CaseCtx { pm, k, case, record };
        let cycle_limited = matches!(run.end, Some((PropagationEnd::CycleLimit, _)));
        if let (false, Some(conn)) = (cycle_limited, connected) {
            let ok = reached == conn || si == gi;
            self.res.stats.check(Property::ReachabilityIsConnectivity, ok);
            if !ok {
                cx.failed(Failed::Property(Property::ReachabilityIsConnectivity));
            }
        }
        self.properties(&mut cx, &run);
        self.optimality(&mut cx, &run, (si, gi));
        if self.opts.metamorphic && !pm.transformed.is_empty() {
            self.metamorphic(&mut cx, &run, start, connected)?;
        }
        self.res.records.extend(cx.record);
        Ok(())
    }

    /// Search-trace properties (observer) and final-state properties.
    fn properties(&mut self, cx: &mut CaseCtx<'_>, run: &CaseRun) {
        let st = &mut self.res.stats;
        for p in Property::SEARCH_TRACE {
            st.check(p, !run.violations.iter().any(|v| v.property == p));
        }
        let fin = plan_checks(self.runner.nav());
        for p in Property::PLAN_CHECKS {
            st.check(p, !fin.iter().any(|v| v.property == p));
        }
        for v in run.violations.iter().chain(fin.iter()) {
            cx.failed(Failed::Property(v.property));
            let detail = format!("{}: {}", v.property, v.detail);
            self.res.findings.push(cx.finding(FindingKind::CheckFailed, detail, 1.0));
        }
    }

    /// Optimality and path shape.
    fn optimality(&mut self, cx: &mut CaseCtx<'_>, run: &CaseRun, (si, gi): (usize, usize)) {
        let (pm, nav) = (cx.pm, self.runner.nav());
        let m = &pm.map;
        let st = &mut self.res.stats;
        let shape_rec = path_shape(&to_pairs(nav.path_recorded()));
        let oscillated = shape_rec.oscillations > 0;
        if let Some(r) = cx.record.as_mut() {
            r.oscillations = shape_rec.oscillations;
        }
        if oscillated {
            st.optimality.oscillating_paths += 1;
            let n = shape_rec.oscillations;
            let detail = format!("{n} repeated points, path len {}", run.outcome.len);
            self.res.findings.push(cx.finding(FindingKind::Oscillation, detail, f64::from(n)));
        }
        if run.outcome.len == 0 || si == gi {
            return;
        }
        let path = to_pairs(nav.path());
        let shape = path_shape(&path);
        if let Some(r) = cx.record.as_mut() {
            r.obtuse_turns = shape.obtuse_turns;
            r.max_turn_deg = shape.max_turn_deg;
        }
        if !oscillated && shape.obtuse_turns > 0 {
            st.optimality.obtuse_paths += 1;
            let (n, deg) = (shape.obtuse_turns, shape.max_turn_deg);
            let detail = format!("{n} obtuse turns, sharpest {deg:.1}°");
            self.res.findings.push(cx.finding(FindingKind::Obtuse, detail, deg));
        }
        if !self.opts.optimality {
            return;
        }
        let (w, h) = (m.width as usize, m.height as usize);
        let best = self.cache.optimum(&pm.setup_costs, w, h, si, gi);
        let cost = path_cost(&pm.setup_costs, m.width, m.height, &path);
        if let Some(r) = cx.record.as_mut() {
            r.navfn_cost = Some(cost);
            r.optimal_cost = best.is_finite().then_some(best);
            r.excess = best.is_finite().then_some(cost - best);
        }
        if best.is_finite() {
            st.optimality.record(cost, best);
            let ratio = if best > 0.0 { cost / best } else { 1.0 };
            if ratio > self.opts.suboptimal_ratio {
                st.optimality.suboptimal_paths += 1;
                let detail = format!(
                    "NavFn path cost {cost:.1}, optimum {best:.1} (+{:.1}, ×{ratio:.3})",
                    cost - best
                );
                self.res.findings.push(cx.finding(FindingKind::Suboptimal, detail, ratio));
            }
        }
    }

    /// The metamorphic relations between this run and the runs on every transformed map.
    fn metamorphic(
        &mut self,
        cx: &mut CaseCtx<'_>,
        run: &CaseRun,
        start: Cell,
        connected: Option<bool>,
    ) -> Result<(), CampaignError> {
        let (pm, mode) = (cx.pm, self.opts.mode);
        let m = &pm.map;
        let o_dig = digest(run, &self.runner, start, &pm.setup_costs, m.width, m.height);
        let o_pot = self.runner.nav().potential().to_vec();
        let ctx = OriginalCtx { width: m.width, height: m.height, potential: &o_pot, connected };
        for (t, tm, tcosts) in &pm.transformed {
            let tc = tm.cases[cx.k];
            let trun =
                run_case(&mut self.runner, tm, tcosts, &tc, mode, None).map_err(|source| {
                    CampaignError::Case { map: format!("{}/{}", tm.category, tm.name), source }
                })?;
            let (tstart, _) = navfn_ends(mode, &tc);
            let tfin = plan_checks(self.runner.nav());
            let mut t_dig = digest(&trun, &self.runner, tstart, tcosts, tm.width, tm.height);
            t_dig.properties_ok &= tfin.is_empty();
            let t_pot = self.runner.nav().potential();
            for r in metamorphic::evaluate(*t, &ctx, &o_dig, &t_dig, t_pot) {
                self.res.stats.relation(r.relation, r.held);
                if r.held {
                    continue;
                }
                let kind = if r.relation.exact() {
                    cx.failed(Failed::Relation(r.relation));
                    FindingKind::RelationFailed
                } else {
                    FindingKind::ApproxRelation
                };
                let detail = format!("{}: {}", r.relation, r.detail);
                self.res.findings.push(cx.finding(kind, detail, 1.0));
            }
        }
        Ok(())
    }
}

/// Run the cases of `range` of `pm` that the campaign's shard owns; `per_case` keeps a
/// record of each.
pub fn run_unit(
    pm: &PreparedMap,
    range: std::ops::Range<usize>,
    opts: &CampaignOptions,
    per_case: bool,
) -> Result<UnitResult, CampaignError> {
    let res = UnitResult { category: pm.map.category.clone(), ..Default::default() };
    let mut unit =
        Unit { opts, per_case, runner: CaseRunner::new(), cache: OptimumCache::default(), res };
    let began = Instant::now();
    for k in range {
        if opts.shard.owns_case(pm.home, k as u64) {
            unit.case(pm, k)?;
        }
    }
    unit.res.seconds = began.elapsed().as_secs_f64();
    Ok(unit.res)
}

/// Where pictures go: `<dir>/<kind>_<category>_<map>_<case>.png`.
pub fn picture_path(dir: &std::path::Path, f: &Finding) -> std::path::PathBuf {
    dir.join(format!("{}_{}_{}_{}.png", f.kind, f.category, f.map, f.case))
}
