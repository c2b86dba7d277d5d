//! A human-readable outline of a resolved plan (`vouch fpl parse`): waypoints with their
//! upstream numbers, blocks with their numbers, exceptions and stages with resolved references.

use std::fmt::Write;

use super::*;
use crate::expr::print_upstream;
use crate::ids::WpId;

/// The outline text, one line per item.
pub fn outline(p: &FlightPlan) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "flight plan \"{}\"  lat0={} lon0={} alt={} ground_alt={} security_height={} max_dist_from_home={}",
        p.name.value,
        p.lat0.value,
        p.lon0.value,
        p.alt.text.value,
        p.ground_alt.text.value,
        p.security_height.text.value,
        p.max_dist_from_home.text.value
    );
    for inc in &p.includes {
        let _ = writeln!(s, "include {} <- {}", inc.name.value, p.sources.path(inc.file));
    }
    let _ = writeln!(s, "waypoints ({} + dummy):", p.waypoints.len());
    for (i, w) in p.waypoints.iter().enumerate() {
        let pos = match (&w.x, &w.y, &w.lat, &w.lon) {
            (Some(x), Some(y), _, _) => format!("x={} y={}", x.text.value, y.text.value),
            (_, _, Some(la), Some(lo)) => format!("lat={} lon={}", la.value, lo.value),
            _ => String::new(),
        };
        let alt = w.alt.as_ref().map(|a| format!(" alt={}", a.text.value)).unwrap_or_default();
        let h = w.height.as_ref().map(|a| format!(" height={}", a.text.value)).unwrap_or_default();
        let _ = writeln!(s, "  {:>3} {:<16} {pos}{alt}{h}", WpId(i).upstream_index(), w.name.value);
    }
    for sec in &p.sectors {
        let c: Vec<&str> = sec.corners.iter().map(|c| c.name.as_str()).collect();
        let _ = writeln!(s, "sector {}: {}", sec.name.value, c.join(" "));
    }
    for e in &p.exceptions {
        let _ = writeln!(
            s,
            "exception if {} -> block {} ({})",
            print_upstream(&e.cond.expr),
            e.deroute.id.0,
            e.deroute.name
        );
    }
    for f in &p.forbidden_deroutes {
        let w = f
            .only_when
            .as_ref()
            .map(|c| format!(" only when {}", print_upstream(&c.expr)))
            .unwrap_or_default();
        let _ = writeln!(s, "forbidden deroute {} -> {}{w}", f.from.name, f.to.name);
    }
    let _ = writeln!(s, "blocks ({}):", p.blocks.len());
    for b in &p.blocks {
        let tag = if b.implicit { "  (implicit)" } else { "" };
        let _ = writeln!(s, "  {:>3} {}{tag}", b.id.0, b.name.value);
        for e in &b.exceptions {
            let _ = writeln!(
                s,
                "        exception if {} -> block {} ({})",
                print_upstream(&e.cond.expr),
                e.deroute.id.0,
                e.deroute.name
            );
        }
        stages(&mut s, &b.stages, 8);
    }
    s
}

fn stages(s: &mut String, list: &[Stage], indent: usize) {
    for st in list {
        let _ = writeln!(s, "{:indent$}{}", "", describe(&st.kind));
        match &st.kind {
            StageKind::While(w) => stages(s, &w.body, indent + 2),
            StageKind::For(f) => stages(s, &f.body, indent + 2),
            _ => {}
        }
    }
}

fn e(x: &ExprAttr) -> String {
    print_upstream(&x.expr)
}

fn wp(w: &WpRef) -> String {
    format!("{}#{}", w.name, w.id.upstream_index())
}

fn describe(k: &StageKind) -> String {
    match k {
        StageKind::While(w) => {
            format!("while {}", w.cond.as_ref().map(e).unwrap_or_else(|| "TRUE".into()))
        }
        StageKind::For(f) => format!("for {} = {} to {}", f.var.value, e(&f.from), e(&f.to)),
        StageKind::Set(x) => format!("set {} = {}", x.var.value, e(&x.value)),
        StageKind::Call(c) => format!("call {}", c.fun.value),
        StageKind::CallOnce(c) => format!("call_once {}", c.fun.value),
        StageKind::Deroute(d) => format!("deroute -> block {} ({})", d.block.id.0, d.block.name),
        StageKind::Return(_) => "return".into(),
        StageKind::Go(g) => {
            let to = g.wp.as_ref().map(wp).unwrap_or_else(|| "(x,y)".into());
            let from = g.from.as_ref().map(|f| format!(" from {}", wp(f))).unwrap_or_default();
            format!("go {to}{from}")
        }
        StageKind::Stay(x) => format!("stay {}", wp(&x.wp)),
        StageKind::Circle(c) => format!("circle {} radius {}", wp(&c.wp), e(&c.radius)),
        StageKind::Heading(h) => format!("heading {}", e(&h.course)),
        StageKind::Attitude(a) => format!("attitude roll {}", e(&a.roll)),
        StageKind::Guided(g) => format!("guided {}", g.commands.value),
        StageKind::Follow(f) => format!("follow {}", f.ac_id.value),
        StageKind::Xyz(_) => "xyz".into(),
        StageKind::Home => "home".into(),
        StageKind::Eight(x) => format!("eight {} {}", wp(&x.center), wp(&x.turn_around)),
        StageKind::Oval(x) => format!("oval {} {}", wp(&x.p1), wp(&x.p2)),
        StageKind::SurveyRectangle(x) => format!("survey_rectangle {} {}", wp(&x.wp1), wp(&x.wp2)),
    }
}
