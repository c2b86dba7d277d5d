//! The lint rules, one function per [`Rule`] (two for the forbidden-deroute pair).

use std::collections::{BTreeSet, HashSet, VecDeque};

use super::{Note, Rule, Warning};
use crate::ast::{FlightPlan, ForbiddenDeroute, Resume, Stage, StageKind};
use crate::expr::{Expr, UnOp};
use crate::span::Span;

fn walk<'a>(stages: &'a [Stage], f: &mut impl FnMut(&'a Stage)) {
    for s in stages {
        f(s);
        match &s.kind {
            StageKind::While(w) => walk(&w.body, f),
            StageKind::For(l) => walk(&l.body, f),
            _ => {}
        }
    }
}

/// How a block change `from -> to` is forbidden, if it is.
enum Forbid<'a> {
    Always(&'a ForbiddenDeroute),
    When(&'a ForbiddenDeroute),
}

fn forbidden(plan: &FlightPlan, from: usize, to: usize) -> Option<Forbid<'_>> {
    let matching =
        plan.forbidden_deroutes.iter().filter(|f| f.from.id.0 == from && f.to.id.0 == to);
    let mut when = None;
    for f in matching {
        if f.only_when.is_none() {
            return Some(Forbid::Always(f));
        }
        when.get_or_insert(f);
    }
    when.map(Forbid::When)
}

fn always_forbidden(plan: &FlightPlan, from: usize, to: usize) -> bool {
    matches!(forbidden(plan, from, to), Some(Forbid::Always(_)))
}

fn warn(rule: Rule, message: String, span: Span) -> Warning {
    Warning::new(rule, message, span)
}

/// Block names given to `IndexOfBlock(..)` anywhere in the sources (such blocks are entered
/// by C code the plan runs, which these rules cannot follow).
fn index_of_block_names(plan: &FlightPlan) -> HashSet<String> {
    let mut names = HashSet::new();
    for f in &plan.sources.files {
        let mut rest = f.text.as_str();
        while let Some(i) = rest.find("IndexOfBlock(") {
            rest = &rest[i + "IndexOfBlock(".len()..];
            if let Some(j) = rest.find(')') {
                names.insert(rest[..j].trim().trim_matches('\'').trim().to_string());
            }
        }
    }
    names
}

/// W001: blocks no next/deroute/exception chain reaches from block 0 or from a block the
/// operator can start (strip button or key).
pub fn unreachable_blocks(plan: &FlightPlan, out: &mut Vec<Warning>) {
    let n = plan.blocks.len();
    let mut succ: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); n];
    for (b, block) in plan.blocks.iter().enumerate() {
        if b + 1 < n && reaches_end(&block.stages) {
            succ[b].insert(b + 1);
        }
        walk(&block.stages, &mut |s| {
            if let StageKind::Deroute(d) = &s.kind {
                succ[b].insert(d.block.id.0);
            }
        });
        for e in block.exceptions.iter().chain(plan.exceptions.iter()) {
            succ[b].insert(e.deroute.id.0);
        }
        succ[b].retain(|&t| t < n && !always_forbidden(plan, b, t));
    }
    // Roots: the first block, and the operator's entry points (strip buttons, keys).
    let mut seen = vec![false; n];
    let mut queue = VecDeque::new();
    for (b, block) in plan.blocks.iter().enumerate() {
        if b == 0 || block.strip_button.is_some() || block.key.is_some() {
            seen[b] = true;
            queue.push_back(b);
        }
    }
    while let Some(b) = queue.pop_front() {
        for &t in &succ[b] {
            if !seen[t] {
                seen[t] = true;
                queue.push_back(t);
            }
        }
    }
    let by_code = index_of_block_names(plan);
    for (b, block) in plan.blocks.iter().enumerate() {
        let operator = block.strip_button.is_some() || block.key.is_some();
        let named = by_code
            .iter()
            .any(|x| *x == block.name.value || block.name.value.ends_with(&format!(".{x}")));
        if !seen[b] && !block.implicit && !operator && !named {
            out.push(warn(
                Rule::UnreachableBlock,
                format!("block '{}' is never entered: no next, deroute or exception step leads to it from the first block or from a block with a strip button or key", block.name.value),
                block.span,
            ));
        }
    }
}

fn forbid_warning(
    plan: &FlightPlan,
    what: &str,
    from: usize,
    to: usize,
    span: Span,
) -> Option<Warning> {
    let name = |i: usize| plan.blocks.get(i).map(|b| b.name.value.clone()).unwrap_or_default();
    let (code, how, f) = match forbidden(plan, from, to)? {
        Forbid::Always(f) => (
            Rule::AlwaysForbidden,
            "is always forbidden: this step can never leave the block and the plan stays here",
            f,
        ),
        Forbid::When(f) => {
            (Rule::ForbiddenWhen, "is forbidden when `only_when` holds: this step can block", f)
        }
    };
    let mut w = warn(code, format!("{what} from '{}' to '{}' {how}", name(from), name(to)), span);
    w.notes.push(Note::new("forbidden by this declaration", f.span));
    Some(w)
}

/// W002/W003: deroutes, exceptions and next-block steps whose block change is forbidden.
pub fn forbidden_steps(plan: &FlightPlan, out: &mut Vec<Warning>) {
    if plan.forbidden_deroutes.is_empty() {
        return;
    }
    let n = plan.blocks.len();
    for (b, block) in plan.blocks.iter().enumerate() {
        walk(&block.stages, &mut |s| {
            if let StageKind::Deroute(d) = &s.kind {
                out.extend(forbid_warning(plan, "deroute", b, d.block.id.0, s.span));
            }
        });
        for e in &block.exceptions {
            if e.deroute.id.0 != b {
                out.extend(forbid_warning(plan, "exception", b, e.deroute.id.0, e.span));
            }
        }
        if b + 1 < n && reaches_end(&block.stages) {
            out.extend(forbid_warning(
                plan,
                "the end of the block (next block)",
                b,
                b + 1,
                block.span,
            ));
        }
    }
    for e in &plan.exceptions {
        let t = e.deroute.id.0;
        for (code, always) in [(Rule::AlwaysForbidden, true), (Rule::ForbiddenWhen, false)] {
            let blocked: Vec<&str> = (0..n)
                .filter(|&b| b != t)
                .filter(|&b| match forbidden(plan, b, t) {
                    Some(Forbid::Always(_)) => always,
                    Some(Forbid::When(_)) => !always,
                    None => false,
                })
                .map(|b| plan.blocks[b].name.value.as_str())
                .collect();
            if !blocked.is_empty() {
                let how =
                    if always { "always forbidden" } else { "forbidden when `only_when` holds" };
                out.push(warn(
                    code,
                    format!(
                        "global exception to '{}' is {how} from block(s) {}: there it can block",
                        plan.blocks.get(t).map(|b| b.name.value.as_str()).unwrap_or("?"),
                        blocked.iter().map(|s| format!("'{s}'")).collect::<Vec<_>>().join(", ")
                    ),
                    e.span,
                ));
            }
        }
    }
}

/// Live stages of a list: those not after a stage that never hands over to the next one.
pub(crate) fn live_stages<'a>(stages: &'a [Stage], f: &mut impl FnMut(&'a Stage)) {
    for s in stages {
        f(s);
        match &s.kind {
            StageKind::While(w) => live_stages(&w.body, f),
            StageKind::For(l) => live_stages(&l.body, f),
            _ => {}
        }
        if ends_list(s) {
            break;
        }
    }
}

/// Whether a block's stage list can run to its end (the implicit next-block stage).
pub(crate) fn reaches_end(stages: &[Stage]) -> bool {
    !stages.iter().any(ends_list)
}

/// A stage after which the next stage of the same list can never run.
pub(crate) fn ends_list(s: &Stage) -> bool {
    match &s.kind {
        StageKind::Deroute(_) | StageKind::Return(_) | StageKind::Home => true,
        StageKind::While(w) => match &w.cond {
            None => true,
            Some(c) => {
                matches!(&c.expr, Expr::Ident(i) if i == "TRUE" || i == "true")
                    || matches!(&c.expr, Expr::Int(v) if *v != 0)
            }
        },
        _ => false,
    }
}

/// W004: a live `return` (not resetting) in a block some deroute stage enters. The deroute
/// saved itself as the last stage, so the return resumes at the deroute, which jumps back.
pub fn return_after_deroute(plan: &FlightPlan, out: &mut Vec<Warning>) {
    let mut into: Vec<Vec<(usize, Span)>> = vec![Vec::new(); plan.blocks.len()];
    for (b, block) in plan.blocks.iter().enumerate() {
        live_stages(&block.stages, &mut |s| {
            if let StageKind::Deroute(d) = &s.kind {
                let t = d.block.id.0;
                if t != b && t < into.len() && !always_forbidden(plan, b, t) {
                    into[t].push((b, s.span));
                }
            }
        });
    }
    for (t, block) in plan.blocks.iter().enumerate() {
        if into[t].is_empty() {
            continue;
        }
        live_stages(&block.stages, &mut |s| {
            if let StageKind::Return(r) = &s.kind
                && r.resume() == Resume::SavedStage
            {
                let from: Vec<String> = into[t]
                    .iter()
                    .map(|(b, _)| format!("'{}'", plan.blocks[*b].name.value))
                    .collect();
                let mut w = warn(
                    Rule::ReturnAfterDeroute,
                    format!(
                        "return in '{}' after a deroute from {} resumes at that deroute stage, which derouts here again (ping-pong); use a deroute back, or return reset_stage=\"1\"",
                        block.name.value,
                        from.join(", ")
                    ),
                    s.span,
                );
                for (_, span) in into[t].iter().take(3) {
                    w.notes.push(Note::new("the deroute that comes here", *span));
                }
                out.push(w);
            }
        });
    }
}

fn literal(e: &Expr) -> Option<i64> {
    match e {
        Expr::Int(v) => Some(*v),
        Expr::Unary(UnOp::Neg, x) => literal(x).map(|v| -v),
        _ => None,
    }
}

/// W005: literal `for` bounds outside `int8_t` (the counter starts at `from - 1`).
pub fn for_bounds(plan: &FlightPlan, out: &mut Vec<Warning>) {
    let fits = |v: i64| (-128..=127).contains(&v);
    for block in &plan.blocks {
        walk(&block.stages, &mut |s| {
            if let StageKind::For(l) = &s.kind {
                if let Some(to) = literal(&l.to.expr)
                    && !fits(to)
                {
                    out.push(warn(Rule::ForBound, format!("`for` bound to=\"{to}\" does not fit the int8_t counter (-128..127): it wraps in C"), l.to.text.span));
                }
                if let Some(from) = literal(&l.from.expr)
                    && (!fits(from - 1) || !fits(from))
                {
                    out.push(warn(Rule::ForBound, format!("`for` start from=\"{from}\" does not fit the int8_t counter (the counter starts at from-1)"), l.from.text.span));
                }
            }
        });
    }
}

/// W006: a block exception whose target is its own block (`nav_block != T` is always false).
pub fn self_exceptions(plan: &FlightPlan, out: &mut Vec<Warning>) {
    for (b, block) in plan.blocks.iter().enumerate() {
        for e in &block.exceptions {
            if e.deroute.id.0 == b {
                out.push(warn(
                    Rule::SelfException,
                    format!(
                        "exception of block '{}' targets its own block: it can never fire",
                        block.name.value
                    ),
                    e.span,
                ));
            }
        }
    }
}

fn mentions_wp(text: &str, name: &str) -> bool {
    let pat = format!("WP_{name}");
    text.match_indices(&pat).any(|(i, _)| {
        let after = text[i + pat.len()..].chars().next();
        let before = text[..i].chars().next_back();
        !after.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_')
            && !before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_')
    })
}

/// W007: waypoints no stage, sector or C text (`WP_name`) refers to. `HOME` is used by the
/// runtime and never reported.
pub fn unused_waypoints(plan: &FlightPlan, out: &mut Vec<Warning>) {
    let mut used: HashSet<usize> = HashSet::new();
    for block in &plan.blocks {
        walk(&block.stages, &mut |s| {
            let mut add = |r: &crate::ast::WpRef| {
                used.insert(r.id.0);
            };
            match &s.kind {
                StageKind::Go(g) => {
                    g.wp.iter().for_each(&mut add);
                    g.from.iter().for_each(&mut add);
                }
                StageKind::Stay(x) => add(&x.wp),
                StageKind::Circle(x) => add(&x.wp),
                StageKind::Eight(x) => {
                    add(&x.center);
                    add(&x.turn_around);
                }
                StageKind::Oval(x) => {
                    add(&x.p1);
                    add(&x.p2);
                }
                StageKind::SurveyRectangle(x) => {
                    add(&x.wp1);
                    add(&x.wp2);
                }
                _ => {}
            }
        });
    }
    for s in &plan.sectors {
        used.extend(s.corners.iter().map(|c| c.id.0));
    }
    let bases: HashSet<&str> = plan
        .waypoints
        .iter()
        .filter_map(|w| match &w.origin {
            crate::ast::WaypointOrigin::Relative { base, .. } => Some(base.as_str()),
            _ => None,
        })
        .collect();
    for (i, w) in plan.waypoints.iter().enumerate() {
        let name = w.name.value.as_str();
        if used.contains(&i) || name == "HOME" || bases.contains(name) {
            continue;
        }
        if plan.sources.files.iter().any(|f| mentions_wp(&f.text, name)) {
            continue;
        }
        out.push(warn(
            Rule::UnusedWaypoint,
            format!("waypoint '{name}' is never used by a stage, a sector or C code (WP_{name})"),
            w.span,
        ));
    }
}

/// W008: stages after a deroute, return, home or endless `while` in the same list.
pub fn dead_stages(plan: &FlightPlan, out: &mut Vec<Warning>) {
    fn list(stages: &[Stage], block: &str, out: &mut Vec<Warning>) {
        for (i, s) in stages.iter().enumerate() {
            match &s.kind {
                StageKind::While(w) => list(&w.body, block, out),
                StageKind::For(l) => list(&l.body, block, out),
                _ => {}
            }
            if ends_list(s) {
                if let Some(next) = stages.get(i + 1) {
                    let n = stages.len() - i - 1;
                    let mut w = warn(
                        Rule::DeadStage,
                        format!(
                            "{n} stage(s) of block '{block}' can never run: they follow a <{}> that never goes on to the next stage",
                            s.kind.tag()
                        ),
                        next.span,
                    );
                    w.notes.push(Note::new("this stage never hands over", s.span));
                    out.push(w);
                }
                return;
            }
        }
    }
    for block in &plan.blocks {
        list(&block.stages, &block.name.value, out);
    }
}
