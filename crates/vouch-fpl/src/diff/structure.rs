//! The structural summary a reviewer reads first: blocks, stages and exceptions added,
//! removed, renamed or changed (blocks matched by content, not only by name), waypoints
//! added, removed, renamed or moved (metres), and the plan's own settings that changed.

use serde::Serialize;

use super::normal::Canon;
use super::{Location, Version};
use crate::ast::{self, FlightPlan};
use crate::emit::geo::{geo_of_deg, utm_of};
use crate::passes::fp::{FpBlock, FpException, FpStage};

/// One changed attribute (raw texts as written).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttrChange {
    pub name: String,
    pub old: Option<String>,
    pub new: Option<String>,
}

/// A stage that differs inside a block found in both versions.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "change", rename_all = "snake_case")]
pub enum StageChange {
    Added { tag: String, at: Location },
    Removed { tag: String, at: Location },
    Changed { tag: String, attrs: Vec<AttrChange>, old_at: Location, new_at: Location },
}

/// What happened to a block.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "change", rename_all = "snake_case")]
pub enum BlockChange {
    Added {
        name: String,
        number: usize,
        at: Location,
    },
    Removed {
        name: String,
        number: usize,
        at: Location,
    },
    /// Same content under another name.
    Renamed {
        old: String,
        new: String,
        old_number: usize,
        new_number: usize,
    },
    /// Same name and content, another number.
    Renumbered {
        name: String,
        old_number: usize,
        new_number: usize,
    },
    Changed {
        name: String,
        old_number: usize,
        new_number: usize,
        attrs: Vec<AttrChange>,
        stages: Vec<StageChange>,
        exceptions: Vec<StageChange>,
    },
}

/// What happened to a waypoint.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "change", rename_all = "snake_case")]
pub enum WaypointChange {
    Added {
        name: String,
        number: usize,
    },
    Removed {
        name: String,
        number: usize,
    },
    /// Same number, another name.
    Renamed {
        old: String,
        new: String,
        number: usize,
    },
    Renumbered {
        name: String,
        old_number: usize,
        new_number: usize,
    },
    /// Moved on the ground by this many metres (between the positions the header gives it).
    Moved {
        name: String,
        metres: f64,
    },
    Altitude {
        name: String,
        old: Option<String>,
        new: Option<String>,
    },
}

/// The summary.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Structure {
    /// `<flight_plan>` attributes that changed.
    pub plan: Vec<AttrChange>,
    pub blocks: Vec<BlockChange>,
    /// Global exceptions.
    pub exceptions: Vec<StageChange>,
    pub waypoints: Vec<WaypointChange>,
    /// The `<header>` C text changed.
    pub header_changed: bool,
}

impl Structure {
    pub fn is_empty(&self) -> bool {
        self.plan.is_empty()
            && self.blocks.is_empty()
            && self.exceptions.is_empty()
            && self.waypoints.is_empty()
            && !self.header_changed
    }
}

/// Compares the two versions' structure.
pub fn compare(old: Version<'_>, new: Version<'_>, ca: &mut Canon, cb: &mut Canon) -> Structure {
    let mut s = Structure {
        plan: attr_changes(&old.plan.attrs, &new.plan.attrs),
        header_changed: old.plan.header.as_ref().map(|h| &h.text)
            != new.plan.header.as_ref().map(|h| &h.text),
        ..Structure::default()
    };
    s.blocks = blocks(old, new, ca, cb);
    s.exceptions = exceptions(
        (old.plan, &old.plan.exceptions, &old.fp.exceptions),
        (new.plan, &new.plan.exceptions, &new.fp.exceptions),
        ca,
        cb,
    );
    s.waypoints = waypoints(old.plan, new.plan);
    s
}

fn attr_changes(a: &ast::Attrs, b: &ast::Attrs) -> Vec<AttrChange> {
    let mut names: Vec<&str> = a.0.iter().chain(&b.0).map(|x| x.name.as_str()).collect();
    names.sort_unstable();
    names.dedup();
    names
        .into_iter()
        .filter_map(|n| {
            let (x, y) = (a.get(n).map(|v| v.value.clone()), b.get(n).map(|v| v.value.clone()));
            (x != y).then(|| AttrChange { name: n.to_string(), old: x, new: y })
        })
        .collect()
}

/// A canonical text of one stage (its behaviour, not its spelling).
fn stage_key(c: &mut Canon, s: &FpStage) -> String {
    let mut out = String::new();
    stage_text(c, s, &mut out);
    out
}

fn stage_text(c: &mut Canon, s: &FpStage, out: &mut String) {
    use std::fmt::Write;
    let _ = match s {
        FpStage::While { cond, body, .. } => {
            let _ = write!(out, "while {} {{", c.text(cond));
            body.iter().for_each(|b| stage_text(c, b, out));
            write!(out, "}}")
        }
        FpStage::For { var, from, to, body, .. } => {
            let _ = write!(out, "for {var} {} {} {{", c.text(from), c.text(to));
            body.iter().for_each(|b| stage_text(c, b, out));
            write!(out, "}}")
        }
        FpStage::Set { code, .. } => write!(out, "set {};", c.text(&code.text)),
        FpStage::Call { fun, loop_, brk, until, .. } => {
            let u = until.as_deref().map(|u| c.text(u));
            write!(out, "call {} {loop_} {brk} {u:?};", c.text(fun))
        }
        FpStage::Deroute { target, .. } => write!(out, "deroute {target};"),
        FpStage::Return { reset, .. } => write!(out, "return {:?};", reset.resume),
        FpStage::Nav(n) => {
            let mut texts: Vec<String> = Vec::new();
            let mut add = |t: &str| texts.push(c.text(t).to_string());
            n.init.iter().flatten().for_each(|x| add(&x.text));
            n.pre_call
                .iter()
                .chain(&n.before)
                .chain(&n.lines)
                .chain(&n.post_call)
                .for_each(|x| add(&x.text));
            n.approach.iter().for_each(|(x, _)| add(x));
            n.until.iter().for_each(|x| add(x));
            write!(out, "{:?} {};", n.kind, texts.join("|"))
        }
    };
}

fn block_key(c: &mut Canon, b: &FpBlock) -> String {
    let mut out: String = b.stages.iter().map(|s| stage_key(c, s)).collect();
    for e in &b.exceptions {
        out.push_str(&exception_key(c, e));
    }
    for h in [&b.pre_call, &b.post_call, &b.on_enter, &b.on_exit] {
        out.push_str(&format!("|{:?}", h.as_ref().map(|x| c.text(&x.text))));
    }
    out
}

fn exception_key(c: &mut Canon, e: &FpException) -> String {
    format!("exc {} {} {:?};", c.text(&e.cond), e.target, e.exec.as_ref().map(|x| c.text(&x.text)))
}

fn blocks(old: Version<'_>, new: Version<'_>, ca: &mut Canon, cb: &mut Canon) -> Vec<BlockChange> {
    let ka: Vec<String> = old.fp.blocks.iter().map(|b| block_key(ca, b)).collect();
    let kb: Vec<String> = new.fp.blocks.iter().map(|b| block_key(cb, b)).collect();
    let name = |p: &FlightPlan, i: usize| p.blocks[i].name.value.clone();
    let mut used_a = vec![false; ka.len()];
    let mut used_b = vec![false; kb.len()];
    let mut out = Vec::new();
    // Same name: unchanged, renumbered or changed.
    for i in 0..ka.len() {
        let Some(j) = new.plan.block_id(&name(old.plan, i)).map(|b| b.0) else { continue };
        if used_b[j] {
            continue;
        }
        used_a[i] = true;
        used_b[j] = true;
        if ka[i] == kb[j] {
            if i != j {
                out.push(BlockChange::Renumbered {
                    name: name(old.plan, i),
                    old_number: i,
                    new_number: j,
                });
            }
            continue;
        }
        let (pa, pb) = (&old.plan.blocks[i], &new.plan.blocks[j]);
        let mut attrs = attr_changes(&pa.attrs, &pb.attrs);
        attrs.retain(|a| a.name != "name");
        out.push(BlockChange::Changed {
            name: name(old.plan, i),
            old_number: i,
            new_number: j,
            attrs,
            stages: stages(
                (old.plan, &pa.stages, &old.fp.blocks[i].stages),
                (new.plan, &pb.stages, &new.fp.blocks[j].stages),
                ca,
                cb,
            ),
            exceptions: exceptions(
                (old.plan, &pa.exceptions, &old.fp.blocks[i].exceptions),
                (new.plan, &pb.exceptions, &new.fp.blocks[j].exceptions),
                ca,
                cb,
            ),
        });
    }
    // Same content, another name: renamed.
    for i in 0..ka.len() {
        if used_a[i] {
            continue;
        }
        if let Some(j) = (0..kb.len()).find(|&j| !used_b[j] && kb[j] == ka[i]) {
            used_a[i] = true;
            used_b[j] = true;
            out.push(BlockChange::Renamed {
                old: name(old.plan, i),
                new: name(new.plan, j),
                old_number: i,
                new_number: j,
            });
        }
    }
    for i in (0..ka.len()).filter(|&i| !used_a[i]) {
        let at = Location::of(old.plan, old.plan.blocks[i].span);
        out.push(BlockChange::Removed { name: name(old.plan, i), number: i, at });
    }
    for j in (0..kb.len()).filter(|&j| !used_b[j]) {
        let at = Location::of(new.plan, new.plan.blocks[j].span);
        out.push(BlockChange::Added { name: name(new.plan, j), number: j, at });
    }
    out
}

/// Stages of both versions, flattened in order (loop bodies after their loop).
fn flatten<'a>(
    ast: &'a [ast::Stage],
    fp: &'a [FpStage],
    out: &mut Vec<(&'a ast::Stage, &'a FpStage)>,
) {
    for (a, f) in ast.iter().zip(fp) {
        out.push((a, f));
        match (&a.kind, f) {
            (ast::StageKind::While(w), FpStage::While { body, .. }) => flatten(&w.body, body, out),
            (ast::StageKind::For(w), FpStage::For { body, .. }) => flatten(&w.body, body, out),
            _ => {}
        }
    }
}

type StageSide<'a> = (&'a FlightPlan, &'a [ast::Stage], &'a [FpStage]);

fn stages(a: StageSide<'_>, b: StageSide<'_>, ca: &mut Canon, cb: &mut Canon) -> Vec<StageChange> {
    let (mut fa, mut fb) = (Vec::new(), Vec::new());
    flatten(a.1, a.2, &mut fa);
    flatten(b.1, b.2, &mut fb);
    // A loop's key holds its body: compare loops by their own line only.
    let own = |c: &mut Canon, f: &FpStage| match f {
        FpStage::While { cond, .. } => format!("while {}", c.text(cond)),
        FpStage::For { var, from, to, .. } => format!("for {var} {} {}", c.text(from), c.text(to)),
        other => stage_key(c, other),
    };
    let ka: Vec<String> = fa.iter().map(|(_, f)| own(ca, f)).collect();
    let kb: Vec<String> = fb.iter().map(|(_, f)| own(cb, f)).collect();
    let items: Vec<(Option<&ast::Stage>, Option<&ast::Stage>)> = align(&ka, &kb)
        .into_iter()
        .map(|(i, j)| (i.map(|i| fa[i].0), j.map(|j| fb[j].0)))
        .collect();
    describe(items, a.0, b.0)
}

fn exceptions(
    a: (&FlightPlan, &[ast::Exception], &[FpException]),
    b: (&FlightPlan, &[ast::Exception], &[FpException]),
    ca: &mut Canon,
    cb: &mut Canon,
) -> Vec<StageChange> {
    let ka: Vec<String> = a.2.iter().map(|e| exception_key(ca, e)).collect();
    let kb: Vec<String> = b.2.iter().map(|e| exception_key(cb, e)).collect();
    let mut out = Vec::new();
    for (i, j) in align(&ka, &kb) {
        match (i, j) {
            (Some(i), None) => out.push(StageChange::Removed {
                tag: "exception".into(),
                at: Location::of(a.0, a.1[i].span),
            }),
            (None, Some(j)) => out.push(StageChange::Added {
                tag: "exception".into(),
                at: Location::of(b.0, b.1[j].span),
            }),
            _ => {}
        }
    }
    pair_changes(out, |old, new| {
        let (x, y) = (
            find_at(a.1.iter().map(|e| (e.span, &e.attrs)), a.0, old),
            find_at(b.1.iter().map(|e| (e.span, &e.attrs)), b.0, new),
        );
        x.zip(y).map(|(x, y)| attr_changes(x, y))
    })
}

fn find_at<'a>(
    mut it: impl Iterator<Item = (crate::span::Span, &'a ast::Attrs)>,
    p: &FlightPlan,
    at: &Location,
) -> Option<&'a ast::Attrs> {
    it.find(|(s, _)| Location::of(p, *s) == *at).map(|(_, a)| a)
}

/// Adjacent removed + added of the same tag become one "changed" entry.
fn pair_changes(
    list: Vec<StageChange>,
    attrs: impl Fn(&Location, &Location) -> Option<Vec<AttrChange>>,
) -> Vec<StageChange> {
    let mut out: Vec<StageChange> = Vec::new();
    for c in list {
        let merged = match (out.last(), &c) {
            (
                Some(StageChange::Removed { tag: t0, at: old_at }),
                StageChange::Added { tag, at },
            ) if t0 == tag => attrs(old_at, at).map(|a| StageChange::Changed {
                tag: tag.clone(),
                attrs: a,
                old_at: old_at.clone(),
                new_at: at.clone(),
            }),
            _ => None,
        };
        match merged {
            Some(m) => {
                out.pop();
                out.push(m);
            }
            None => out.push(c),
        }
    }
    out
}

fn describe(
    items: Vec<(Option<&ast::Stage>, Option<&ast::Stage>)>,
    pa: &FlightPlan,
    pb: &FlightPlan,
) -> Vec<StageChange> {
    let mut list = Vec::new();
    let mut by_loc: Vec<(Location, &ast::Attrs)> = Vec::new();
    for (x, y) in items {
        match (x, y) {
            (Some(s), None) => {
                let at = Location::of(pa, s.span);
                by_loc.push((at.clone(), &s.attrs));
                list.push(StageChange::Removed { tag: s.kind.tag().into(), at });
            }
            (None, Some(s)) => {
                let at = Location::of(pb, s.span);
                by_loc.push((at.clone(), &s.attrs));
                list.push(StageChange::Added { tag: s.kind.tag().into(), at });
            }
            _ => {}
        }
    }
    pair_changes(list, |o, n| {
        let x = by_loc.iter().find(|(l, _)| l == o)?.1;
        let y = by_loc.iter().find(|(l, _)| l == n)?.1;
        Some(attr_changes(x, y))
    })
}

/// A longest-common-subsequence alignment: pairs of indices, `None` where one side has none.
fn align(a: &[String], b: &[String]) -> Vec<(Option<usize>, Option<usize>)> {
    let (n, m) = (a.len(), b.len());
    let mut l = vec![vec![0u32; m + 1]; n + 1];
    for i in (0..n).rev() {
        for j in (0..m).rev() {
            l[i][j] = if a[i] == b[j] { l[i + 1][j + 1] + 1 } else { l[i + 1][j].max(l[i][j + 1]) };
        }
    }
    let (mut i, mut j, mut out) = (0, 0, Vec::new());
    while i < n || j < m {
        if i < n && j < m && a[i] == b[j] {
            out.push((Some(i), Some(j)));
            i += 1;
            j += 1;
        } else if i == n || (j < m && l[i][j + 1] > l[i + 1][j]) {
            out.push((None, Some(j)));
            j += 1;
        } else {
            out.push((Some(i), None));
            i += 1;
        }
    }
    out
}

/// Ground position of a waypoint (UTM metres) and its altitude text.
fn position(p: &FlightPlan, w: &ast::Waypoint) -> Option<(f64, f64)> {
    let r = utm_of(geo_of_deg(p.lat0.value, p.lon0.value), None);
    match (&w.x, &w.y, &w.lat, &w.lon) {
        (Some(x), Some(y), _, _) => Some((r.x + x.value, r.y + y.value)),
        (_, _, Some(la), Some(lo)) => {
            let u = utm_of(geo_of_deg(la.value, lo.value), Some(r.zone));
            Some((u.x, u.y))
        }
        _ => None,
    }
}

fn waypoints(a: &FlightPlan, b: &FlightPlan) -> Vec<WaypointChange> {
    let mut out = Vec::new();
    let (mut used_a, mut used_b) = (vec![false; a.waypoints.len()], vec![false; b.waypoints.len()]);
    for (i, w) in a.waypoints.iter().enumerate() {
        let Some(j) = b.waypoint_id(&w.name.value).map(|x| x.0) else { continue };
        used_a[i] = true;
        used_b[j] = true;
        same_waypoint(&mut out, (a, w), (b, &b.waypoints[j]), &w.name.value);
        if i != j {
            out.push(WaypointChange::Renumbered {
                name: w.name.value.clone(),
                old_number: i + 1,
                new_number: j + 1,
            });
        }
    }
    for i in 0..a.waypoints.len() {
        if !used_a[i] && i < b.waypoints.len() && !used_b[i] {
            used_a[i] = true;
            used_b[i] = true;
            let (x, y) = (&a.waypoints[i], &b.waypoints[i]);
            out.push(WaypointChange::Renamed {
                old: x.name.value.clone(),
                new: y.name.value.clone(),
                number: i + 1,
            });
            same_waypoint(&mut out, (a, x), (b, y), &y.name.value);
        }
    }
    for (i, w) in a.waypoints.iter().enumerate().filter(|(i, _)| !used_a[*i]) {
        out.push(WaypointChange::Removed { name: w.name.value.clone(), number: i + 1 });
    }
    for (j, w) in b.waypoints.iter().enumerate().filter(|(j, _)| !used_b[*j]) {
        out.push(WaypointChange::Added { name: w.name.value.clone(), number: j + 1 });
    }
    out
}

fn same_waypoint(
    out: &mut Vec<WaypointChange>,
    a: (&FlightPlan, &ast::Waypoint),
    b: (&FlightPlan, &ast::Waypoint),
    name: &str,
) {
    if let (Some(p), Some(q)) = (position(a.0, a.1), position(b.0, b.1)) {
        let metres = (p.0 - q.0).hypot(p.1 - q.1);
        if metres > 0.0 {
            out.push(WaypointChange::Moved { name: name.to_string(), metres });
        }
    }
    let alt = |w: &ast::Waypoint| w.alt.as_ref().or(w.height.as_ref()).map(|n| n.value);
    if alt(a.1) != alt(b.1) {
        let text =
            |w: &ast::Waypoint| w.alt.as_ref().or(w.height.as_ref()).map(|n| n.text.value.clone());
        out.push(WaypointChange::Altitude {
            name: name.to_string(),
            old: text(a.1),
            new: text(b.1),
        });
    }
}
