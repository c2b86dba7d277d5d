//! SVG text of a [`super::BlockGraph`] (layout described in the parent module).

use super::{BlockGraph, EdgeKind, Forbid, GEdge};

const NODE_H: f64 = 34.0;
const PITCH: f64 = 52.0;
const LANE: f64 = 11.0;
const TOP: f64 = 110.0;

fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

fn color(e: &GEdge) -> &'static str {
    match (e.forbid, e.kind) {
        (Forbid::Always | Forbid::When, _) | (_, EdgeKind::ForbiddenOnly) => "#d62728",
        (_, EdgeKind::Next) => "#555555",
        (_, EdgeKind::Deroute) => "#1f6fd1",
        (_, EdgeKind::Return) => "#2a9d4b",
        (_, EdgeKind::Exception) => "#e07b00",
        (_, EdgeKind::GlobalException) => "#9c5a1a",
    }
}

fn dash(e: &GEdge) -> &'static str {
    match e.kind {
        EdgeKind::Next | EdgeKind::Deroute => "",
        EdgeKind::Return => " stroke-dasharray=\"2,3\"",
        EdgeKind::Exception | EdgeKind::GlobalException => " stroke-dasharray=\"7,3\"",
        EdgeKind::ForbiddenOnly => " stroke-dasharray=\"1,4\"",
    }
}

fn marker_id(c: &str) -> String {
    format!("arrow{}", c.trim_start_matches('#'))
}

/// Greedy interval colouring: each arc gets the lowest lane free over its vertical span.
fn lanes(spans: &[(f64, f64)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..spans.len()).collect();
    order.sort_by(|&a, &b| {
        let la = spans[a].1 - spans[a].0;
        let lb = spans[b].1 - spans[b].0;
        la.partial_cmp(&lb).unwrap_or(std::cmp::Ordering::Equal).then(a.cmp(&b))
    });
    let mut used: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut lane = vec![0; spans.len()];
    for i in order {
        let (lo, hi) = spans[i];
        let l = (0..)
            .find(|&l| {
                used.get(l).is_none_or(|v: &Vec<(f64, f64)>| {
                    v.iter().all(|&(a, b)| hi + 4.0 < a || lo - 4.0 > b)
                })
            })
            .unwrap_or(0);
        if used.len() <= l {
            used.resize(l + 1, Vec::new());
        }
        used[l].push((lo, hi));
        lane[i] = l;
    }
    lane
}

fn y_of(row: Option<usize>) -> f64 {
    match row {
        Some(r) => TOP + r as f64 * PITCH + NODE_H / 2.0,
        None => TOP - 38.0,
    }
}

pub fn render(g: &BlockGraph) -> String {
    let maxlen = g.nodes.iter().map(|n| n.name.chars().count() + 5).max().unwrap_or(10).max(24);
    let node_w = (maxlen as f64 * 7.4 + 24.0).max(190.0);
    // Sides: left = exceptions, right = deroutes, returns, forbidden-only pairs.
    let side_right = |e: &GEdge| {
        matches!(e.kind, EdgeKind::Deroute | EdgeKind::Return | EdgeKind::ForbiddenOnly)
    };
    let arcs: Vec<&GEdge> = g.edges.iter().filter(|e| e.kind != EdgeKind::Next).collect();
    let span = |e: &GEdge| {
        let (a, b) = (y_of(e.from), y_of(Some(e.to)));
        (a.min(b) - 8.0, a.max(b) + 8.0)
    };
    let right: Vec<&GEdge> = arcs.iter().copied().filter(|e| side_right(e)).collect();
    let left: Vec<&GEdge> = arcs.iter().copied().filter(|e| !side_right(e)).collect();
    let rl = lanes(&right.iter().map(|e| span(e)).collect::<Vec<_>>());
    let ll = lanes(&left.iter().map(|e| span(e)).collect::<Vec<_>>());
    let nl = ll.iter().max().map_or(0, |m| m + 1) as f64;
    let nr = rl.iter().max().map_or(0, |m| m + 1) as f64;
    let x0 = 30.0 + 20.0 + nl * LANE;
    let x1 = x0 + node_w;
    let width = x1 + 20.0 + nr * LANE + 40.0;
    let height = TOP + g.nodes.len() as f64 * PITCH + 150.0;
    let mut s = String::new();
    s.push_str(&format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.0}\" height=\"{height:.0}\" viewBox=\"0 0 {width:.0} {height:.0}\" font-family=\"DejaVu Sans, Arial, sans-serif\">\n"
    ));
    s.push_str("<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<defs>\n");
    for c in ["#555555", "#1f6fd1", "#2a9d4b", "#e07b00", "#9c5a1a", "#d62728"] {
        s.push_str(&format!(
            "<marker id=\"{}\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" markerWidth=\"7\" markerHeight=\"7\" orient=\"auto-start-reverse\"><path d=\"M0,0 L10,5 L0,10 z\" fill=\"{c}\"/></marker>\n",
            marker_id(c)
        ));
    }
    s.push_str("</defs>\n");
    s.push_str(&format!(
        "<text x=\"20\" y=\"28\" font-size=\"18\" font-weight=\"bold\">{}</text>\n",
        esc(&g.title)
    ));
    s.push_str(&format!(
        "<text x=\"20\" y=\"48\" font-size=\"11\" fill=\"#444\">{} blocks, {} transitions (vouch fpl graph)</text>\n",
        g.nodes.len(),
        g.edges.len()
    ));
    if g.edges.iter().any(|e| e.kind == EdgeKind::GlobalException) {
        s.push_str(&format!(
            "<rect x=\"{x0:.1}\" y=\"{:.1}\" width=\"{node_w:.1}\" height=\"24\" rx=\"12\" fill=\"#fff4e6\" stroke=\"#9c5a1a\" stroke-dasharray=\"4,2\"/>\n<text x=\"{:.1}\" y=\"{:.1}\" font-size=\"11\" text-anchor=\"middle\" fill=\"#9c5a1a\">global exceptions (any block)</text>\n",
            TOP - 50.0,
            x0 + node_w / 2.0,
            TOP - 34.0
        ));
    }
    next_arrows(&mut s, g, x0, node_w);
    for (side, list, ls) in [(1.0, &right, &rl), (-1.0, &left, &ll)] {
        for (e, &lane) in list.iter().zip(ls.iter()) {
            arc(&mut s, e, side, lane, x0, x1);
        }
    }
    boxes(&mut s, g, x0, node_w);
    legend(&mut s, 20.0, TOP + g.nodes.len() as f64 * PITCH + 20.0);
    s.push_str("</svg>\n");
    s
}

/// The next-block arrows, straight down between consecutive boxes.
fn next_arrows(s: &mut String, g: &BlockGraph, x0: f64, node_w: f64) {
    for e in g.edges.iter().filter(|e| e.kind == EdgeKind::Next) {
        let Some(f) = e.from else { continue };
        let c = color(e);
        let x = x0 + node_w / 2.0;
        let y1 = TOP + f as f64 * PITCH + NODE_H;
        let y2 = TOP + e.to as f64 * PITCH - 1.0;
        s.push_str(&format!(
            "<line x1=\"{x:.1}\" y1=\"{y1:.1}\" x2=\"{x:.1}\" y2=\"{y2:.1}\" stroke=\"{c}\" stroke-width=\"1.4\" marker-end=\"url(#{})\"/>\n",
            marker_id(c)
        ));
        if e.forbid != Forbid::No {
            cross(s, x, (y1 + y2) / 2.0, e.forbid);
        }
    }
}

/// One box per block: number, name, stage and exception counts.
fn boxes(s: &mut String, g: &BlockGraph, x0: f64, node_w: f64) {
    for (i, n) in g.nodes.iter().enumerate() {
        let y = TOP + i as f64 * PITCH;
        let (fill, dash) =
            if n.implicit { ("#eeeeee", " stroke-dasharray=\"4,2\"") } else { ("#f4f6fb", "") };
        s.push_str(&format!(
            "<rect x=\"{x0:.1}\" y=\"{y:.1}\" width=\"{node_w:.1}\" height=\"{NODE_H}\" rx=\"5\" fill=\"{fill}\" stroke=\"#333\"{dash}/>\n"
        ));
        s.push_str(&format!(
            "<text x=\"{:.1}\" y=\"{:.1}\" font-size=\"13\"><tspan fill=\"#888\">{i}</tspan>  {}</text>\n",
            x0 + 8.0,
            y + 15.0,
            esc(&n.name)
        ));
        let detail = format!(
            "{} stage{}{}{}",
            n.stages,
            if n.stages == 1 { "" } else { "s" },
            if n.exceptions > 0 {
                format!(", {} exception{}", n.exceptions, if n.exceptions == 1 { "" } else { "s" })
            } else {
                String::new()
            },
            if n.implicit { " (implicit)" } else { "" }
        );
        s.push_str(&format!(
            "<text x=\"{:.1}\" y=\"{:.1}\" font-size=\"10\" fill=\"#555\">{}</text>\n",
            x0 + 8.0,
            y + 28.0,
            esc(&detail)
        ));
    }
}

fn cross(s: &mut String, x: f64, y: f64, f: Forbid) {
    s.push_str(&format!(
        "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"6.5\" fill=\"white\" stroke=\"#d62728\" stroke-width=\"1.3\"/>\n<text x=\"{x:.1}\" y=\"{:.1}\" font-size=\"10\" font-weight=\"bold\" text-anchor=\"middle\" fill=\"#d62728\">{}</text>\n",
        y + 3.5,
        if f == Forbid::When { "?" } else { "✕" }
    ));
}

fn arc(s: &mut String, e: &GEdge, side: f64, lane: usize, x0: f64, x1: f64) {
    let c = color(e);
    let ys = y_of(e.from) + if e.from.is_none() { 0.0 } else { -6.0 };
    let yt = y_of(Some(e.to)) + 6.0;
    let base = if side > 0.0 { x1 } else { x0 };
    let sx = if e.from.is_none() { x0 } else { base };
    let x = base + side * (18.0 + lane as f64 * LANE);
    let r = 5.0f64.min((yt - ys).abs() / 2.0);
    let dy = if yt > ys { r } else { -r };
    let w = if e.kind == EdgeKind::ForbiddenOnly { 1.0 } else { 1.5 };
    s.push_str(&format!(
        "<path d=\"M{sx:.1},{ys:.1} H{:.1} Q{x:.1},{ys:.1} {x:.1},{:.1} V{:.1} Q{x:.1},{yt:.1} {:.1},{yt:.1} H{:.1}\" fill=\"none\" stroke=\"{c}\" stroke-width=\"{w}\"{} marker-end=\"url(#{})\"/>\n",
        x - side * r,
        ys + dy,
        yt - dy,
        x - side * r,
        base + side * 1.0,
        dash(e),
        marker_id(c)
    ));
    if e.count > 1 {
        s.push_str(&format!(
            "<text x=\"{:.1}\" y=\"{:.1}\" font-size=\"9\" fill=\"{c}\">×{}</text>\n",
            base + side * 4.0 - if side < 0.0 { 14.0 } else { 0.0 },
            ys - 2.0,
            e.count
        ));
    }
    if e.forbid != Forbid::No {
        cross(s, x, (ys + yt) / 2.0, e.forbid);
    }
}

fn legend(s: &mut String, x: f64, y: f64) {
    let items: [(&str, &str, &str); 7] = [
        ("#555555", "", "next block (end of stages)"),
        ("#1f6fd1", "", "deroute stage"),
        ("#2a9d4b", "2,3", "return (to a block that can come here)"),
        ("#e07b00", "7,3", "block exception"),
        ("#9c5a1a", "7,3", "global exception"),
        ("#d62728", "", "forbidden always (✕) / under only_when (?)"),
        ("#d62728", "1,4", "forbidden pair no step tries"),
    ];
    s.push_str(&format!(
        "<text x=\"{x:.1}\" y=\"{y:.1}\" font-size=\"12\" font-weight=\"bold\">Legend</text>\n"
    ));
    for (i, (c, d, label)) in items.iter().enumerate() {
        let yy = y + 18.0 + i as f64 * 16.0;
        let da = if d.is_empty() { String::new() } else { format!(" stroke-dasharray=\"{d}\"") };
        s.push_str(&format!(
            "<line x1=\"{x:.1}\" y1=\"{yy:.1}\" x2=\"{:.1}\" y2=\"{yy:.1}\" stroke=\"{c}\" stroke-width=\"1.5\"{da} marker-end=\"url(#{})\"/>\n<text x=\"{:.1}\" y=\"{:.1}\" font-size=\"11\">{}</text>\n",
            x + 40.0,
            marker_id(c),
            x + 50.0,
            yy + 4.0,
            esc(label)
        ));
    }
}
