//! From the resolved AST to [`Fp`]: composes the C text of every stage exactly as upstream's
//! generator does (GENERATOR_FACTS.md section 7) so that both the emitter and the interpreter
//! work from the same texts. Errors are the generator-level ones the front end leaves to us
//! (missing altitude for `alt` vmode, glide without route, ...).

use crate::ast::{
    self, BlockRef, ExprAttr, FlightPlan, HMode, NavCommon, Pitch, StageKind, Text, VMode,
    Vertical, WpRef,
};
use crate::expr::print_upstream;
use crate::span::Span;

use super::CompileError;
use super::fp::*;

/// Builds the FP structure of a resolved plan.
pub fn lower(plan: &FlightPlan) -> Result<Fp, CompileError> {
    let mut blocks = Vec::with_capacity(plan.blocks.len());
    for b in &plan.blocks {
        let mut stages = Vec::with_capacity(b.stages.len());
        for s in &b.stages {
            stages.push(lower_stage(s)?);
        }
        blocks.push(FpBlock {
            name: b.name.value.clone(),
            pre_call: b.pre_call.as_ref().map(raw),
            post_call: b.post_call.as_ref().map(raw),
            on_enter: b.on_enter.as_ref().map(raw),
            on_exit: b.on_exit.as_ref().map(raw),
            exceptions: b.exceptions.iter().map(lower_exception).collect(),
            stages,
            span: b.span,
        });
    }
    let forbidden = plan
        .forbidden_deroutes
        .iter()
        .map(|f| FpForbidden {
            from: f.from.id.0,
            to: f.to.id.0,
            only_when: f.only_when.as_ref().map(p),
        })
        .collect();
    let init = plan
        .variables
        .iter()
        .filter_map(|v| match v {
            ast::VariableDecl::Abi(a) => Some(abi_bind(a)),
            ast::VariableDecl::Var(_) => None,
        })
        .collect();
    Ok(Fp {
        blocks,
        exceptions: plan.exceptions.iter().map(lower_exception).collect(),
        forbidden,
        init,
    })
}

/// `AbiBindMsg<name>(<id>, &FP_<name>_ev, <callback or handler>)` of `auto_nav_init`.
pub fn abi_bind(a: &ast::AbiBinding) -> Code {
    let name = &a.name.value;
    let id = a.id.as_ref().map(|t| t.value.as_str()).unwrap_or("ABI_BROADCAST");
    let cb = match &a.handler {
        Some(h) => h.value.clone(),
        None => format!("FP_{name}_cb"),
    };
    Code::stmt(format!("AbiBindMsg{name}({id}, &FP_{name}_ev, {cb})"))
}

fn raw(t: &Text) -> Code {
    Code::stmt(t.value.clone())
}

/// `P(e)`: the upstream re-printing of an expression attribute.
fn p(e: &ExprAttr) -> String {
    print_upstream(&e.expr)
}

fn wp(w: &WpRef) -> String {
    w.id.upstream_index().to_string()
}

fn blk(b: &BlockRef) -> usize {
    b.id.0
}

fn lower_exception(e: &ast::Exception) -> FpException {
    FpException {
        cond: p(&e.cond),
        target: blk(&e.deroute),
        exec: e.exec.as_ref().map(raw),
        span: e.span,
    }
}

fn lower_body(body: &[ast::Stage]) -> Result<Vec<FpStage>, CompileError> {
    body.iter().map(lower_stage).collect()
}

fn lower_stage(s: &ast::Stage) -> Result<FpStage, CompileError> {
    let span = s.span;
    Ok(match &s.kind {
        StageKind::While(w) => FpStage::While {
            cond: w.cond.as_ref().map(p).unwrap_or_else(|| "TRUE".to_string()),
            body: lower_body(&w.body)?,
            span,
        },
        StageKind::For(f) => FpStage::For {
            var: format!("_var_{}", f.var.value.trim_start_matches('$')),
            from: p(&f.from),
            to: p(&f.to),
            body: lower_body(&f.body)?,
            span,
        },
        StageKind::Set(x) => {
            FpStage::Set { code: Code::stmt(format!("{} = {}", x.var.value, p(&x.value))), span }
        }
        StageKind::Call(c) => FpStage::Call {
            fun: c.fun.value.clone(),
            loop_: c.loop_.as_ref().map(|l| l.value).unwrap_or(true),
            brk: c.break_.as_ref().map(|b| b.value).unwrap_or(false),
            until: c.until.as_ref().map(p),
            span,
        },
        StageKind::CallOnce(c) => FpStage::Call {
            fun: c.fun.value.clone(),
            loop_: false,
            brk: c.break_.as_ref().map(|b| b.value).unwrap_or(false),
            until: None,
            span,
        },
        StageKind::Deroute(d) => FpStage::Deroute { target: blk(&d.block), span },
        StageKind::Return(r) => FpStage::Return {
            reset: Reset { text: r.reset_text().to_string(), resume: r.resume() },
            span,
        },
        kind => FpStage::Nav(Box::new(lower_nav(kind, span)?)),
    })
}

/// Navigation prefix `t` (`nav_type`, default `Nav`) and extra parameters `NP`.
struct Prefix {
    t: String,
    np: String,
}

fn prefix(c: &NavCommon) -> Prefix {
    Prefix {
        t: c.nav_type.as_ref().map(|t| t.value.clone()).unwrap_or_else(|| "Nav".to_string()),
        np: c.nav_params.as_ref().map(|t| format!(", {}", t.value)).unwrap_or_default(),
    }
}

/// `MS` [2024-10]: the max-speed line.
fn max_speed(t: &str, c: &NavCommon) -> Code {
    let v = c.max_speed.as_ref().map(|m| m.value.clone()).unwrap_or_else(|| "-1.".to_string());
    Code::stmt(format!("{t}SetMaxSpeed({v})"))
}

/// The "vmode lines": pitch line, then the vertical mode line.
/// `wp` is the stage's default-altitude waypoint; `from` the glide start (`last_wp` if absent).
fn vmode_lines(
    t: &str,
    v: &Vertical,
    wp: Option<&str>,
    from: Option<&str>,
    only_pitch: bool,
    span: Span,
) -> Result<Vec<Code>, CompileError> {
    let mut out = Vec::new();
    let vmode = v.vmode.as_ref().map(|m| m.value).unwrap_or(VMode::Alt);
    match &v.pitch {
        Some(Pitch::Auto(_)) => {
            if vmode == VMode::Throttle && !only_pitch {
                return Err(CompileError::new(
                    "pitch=\"auto\" is not compatible with vmode=\"throttle\"",
                    span,
                ));
            }
            let th = v.throttle.as_ref().ok_or_else(|| {
                CompileError::new("pitch=\"auto\" needs a throttle attribute", span)
            })?;
            out.push(Code::stmt(format!("{t}VerticalAutoPitchMode(9600*({}))", p(th))));
        }
        Some(Pitch::Expr(e)) => {
            out.push(Code::stmt(format!("{t}VerticalAutoThrottleMode(RadOfDeg({}))", p(e))))
        }
        None => out.push(Code::stmt(format!("{t}VerticalAutoThrottleMode(RadOfDeg(0.000000))"))),
    }
    if only_pitch {
        return Ok(out);
    }
    match vmode {
        VMode::Alt => {
            let a = if let Some(a) = &v.alt {
                p(a)
            } else if let Some(h) = &v.height {
                format!("Height({})", p(h))
            } else if let Some(w) = wp {
                format!("WaypointAlt({w})")
            } else {
                return Err(CompileError::new(
                    "vmode \"alt\" needs an alt or height attribute (this stage has no waypoint)",
                    span,
                ));
            };
            out.push(Code::stmt(format!("{t}VerticalAltitudeMode({a}, 0.)")));
        }
        VMode::Climb => {
            let c = v.climb.as_ref().ok_or_else(|| {
                CompileError::new("vmode \"climb\" needs a climb attribute", span)
            })?;
            out.push(Code::stmt(format!("{t}VerticalClimbMode({})", p(c))));
        }
        VMode::Throttle => {
            let th = v.throttle.as_ref().ok_or_else(|| {
                CompileError::new("vmode \"throttle\" needs a throttle attribute", span)
            })?;
            out.push(Code::stmt(format!("{t}VerticalThrottleMode(9600*({}))", p(th))));
        }
        VMode::Glide => {
            let w =
                wp.ok_or_else(|| CompileError::new("vmode \"glide\" needs a waypoint", span))?;
            out.push(Code::stmt(format!("{t}Glide({}, {w})", from.unwrap_or("last_wp"))));
        }
        VMode::Xyz => {}
    }
    Ok(out)
}

fn until(c: &NavCommon) -> Option<Cond> {
    c.until.as_ref().map(p)
}

fn nav(kind: NavKind, c: &NavCommon, span: Span) -> NavStage {
    NavStage {
        kind,
        init: None,
        pre_call: c.pre_call.as_ref().map(raw),
        before: Vec::new(),
        approach: None,
        approach_upstream: None,
        lines: Vec::new(),
        until: until(c),
        post_call: c.post_call.as_ref().map(raw),
        span,
    }
}

fn lower_nav(kind: &StageKind, span: Span) -> Result<NavStage, CompileError> {
    match kind {
        StageKind::Go(g) => go(g, span),
        StageKind::Stay(s) => stay(s, span),
        StageKind::Circle(c) => circle(c, span),
        StageKind::Heading(h) => heading(h, span),
        StageKind::Attitude(a) => attitude(a, span),
        StageKind::Guided(g) => guided(g, span),
        StageKind::Follow(f) => follow(f, span),
        StageKind::Xyz(x) => xyz(x, span),
        StageKind::Home => Ok(NavStage {
            kind: NavKind::Home,
            init: None,
            pre_call: None,
            before: Vec::new(),
            approach: None,
            approach_upstream: None,
            lines: vec![Code::stmt("nav_home()")],
            until: None,
            post_call: None,
            span,
        }),
        StageKind::Eight(e) => eight(e, span),
        StageKind::Oval(o) => oval(o, span),
        StageKind::SurveyRectangle(s) => survey_rectangle(s, span),
        StageKind::While(_)
        | StageKind::For(_)
        | StageKind::Set(_)
        | StageKind::Call(_)
        | StageKind::CallOnce(_)
        | StageKind::Deroute(_)
        | StageKind::Return(_) => Err(CompileError::new("internal: not a navigation stage", span)),
    }
}

/// `<go>`.
fn go(g: &ast::Go, span: Span) -> Result<NavStage, CompileError> {
    let pf = prefix(&g.common);
    let t = &pf.t;
    let mut n = nav(NavKind::Go, &g.common, span);
    let w = match &g.wp {
        Some(w) => wp(w),
        None => {
            let (x, y) = match (&g.x, &g.y) {
                (Some(x), Some(y)) => (p(x), p(y)),
                _ => return Err(CompileError::new("go needs a wp or both x and y", span)),
            };
            n.before.push(Code::stmt(format!("waypoints[0].x = {x}")));
            n.before.push(Code::stmt(format!("waypoints[0].y = {y}")));
            "0".to_string()
        }
    };
    // Upstream's text: the minus sign before the raw text (quirk 7).
    let upstream_at = g.exceeding_time.as_ref().map(|e| format!("-{}", e.value));
    let at = match (&g.approaching_time, &g.exceeding_time) {
        (Some(a), None) => a.value.clone(),
        (None, Some(e)) => negate(&e.value),
        (None, None) => "CARROT".to_string(),
        (Some(_), Some(_)) => {
            return Err(CompileError::new(
                "approaching_time and exceeding_time are not compatible",
                span,
            ));
        }
    };
    let from = g.from.as_ref().map(wp);
    let approaching = |at: &str| match &from {
        Some(f) => format!("{t}ApproachingFrom({w},{f},{at})"),
        None => format!("{t}Approaching({w},{at})"),
    };
    let cond = approaching(&at);
    n.approach_upstream = upstream_at.filter(|u| *u != at).map(|u| approaching(&u));
    let route = matches!(g.hmode.as_ref().map(|h| h.value), Some(HMode::Route));
    let vm = g.vertical.vmode.as_ref().map(|m| m.value);
    if vm == Some(VMode::Glide) && !route {
        return Err(CompileError::new("vmode \"glide\" requires hmode \"route\"", span));
    }
    n.lines.push(max_speed(t, &g.common));
    n.lines.push(hmode_line(
        t,
        g.hmode.as_ref().map(|h| h.value),
        from.as_deref().or(Some("last_wp")),
        &w,
        &pf.np,
    ));
    n.lines.extend(vmode_lines(t, &g.vertical, Some(&w), from.as_deref(), false, span)?);
    n.approach = Some((cond, g.wp.as_ref().map(|w| w.id.upstream_index()).unwrap_or(0)));
    Ok(n)
}

/// `<stay>`.
fn stay(s: &ast::Stay, span: Span) -> Result<NavStage, CompileError> {
    let pf = prefix(&s.common);
    let mut n = nav(NavKind::Stay, &s.common, span);
    let w = wp(&s.wp);
    n.lines.push(max_speed(&pf.t, &s.common));
    // Quirk 18: a route stay has no `from`; upstream prints an empty first argument.
    n.lines.push(hmode_line(&pf.t, s.hmode.as_ref().map(|h| h.value), Some(""), &w, &pf.np));
    n.lines.extend(vmode_lines(&pf.t, &s.vertical, Some(&w), None, false, span)?);
    Ok(n)
}

/// `<circle>`.
fn circle(c: &ast::Circle, span: Span) -> Result<NavStage, CompileError> {
    let pf = prefix(&c.common);
    let mut n = nav(NavKind::Circle, &c.common, span);
    let w = wp(&c.wp);
    n.lines.extend(vmode_lines(&pf.t, &c.vertical, Some(&w), None, false, span)?);
    n.lines.push(max_speed(&pf.t, &c.common));
    n.lines.push(Code::stmt(format!("{}CircleWaypoint({w}, {}{})", pf.t, p(&c.radius), pf.np)));
    Ok(n)
}

/// `<heading>`.
fn heading(h: &ast::Heading, span: Span) -> Result<NavStage, CompileError> {
    let pf = prefix(&h.common);
    let mut n = nav(NavKind::Heading, &h.common, span);
    n.lines.push(max_speed(&pf.t, &h.common));
    n.lines.push(Code::stmt(format!("{}Heading(RadOfDeg({}){})", pf.t, p(&h.course), pf.np)));
    n.lines.extend(vmode_lines(&pf.t, &h.vertical, None, None, false, span)?);
    Ok(n)
}

/// `<attitude>`.
fn attitude(a: &ast::Attitude, span: Span) -> Result<NavStage, CompileError> {
    let pf = prefix(&a.common);
    let mut n = nav(NavKind::Attitude, &a.common, span);
    n.lines.push(Code::stmt(format!("{}Attitude(RadOfDeg({}){})", pf.t, p(&a.roll), pf.np)));
    n.lines.extend(vmode_lines(&pf.t, &a.vertical, None, None, false, span)?);
    Ok(n)
}

/// `<guided>`.
fn guided(g: &ast::Guided, span: Span) -> Result<NavStage, CompileError> {
    let pf = prefix(&g.common);
    let mut n = nav(NavKind::Guided, &g.common, span);
    n.lines.push(max_speed(&pf.t, &g.common));
    let flags = g.flags.as_ref().map(|f| f.value.as_str()).unwrap_or("0");
    n.lines.push(Code::stmt(format!("{}Guided({flags}, {}{})", pf.t, g.commands.value, pf.np)));
    Ok(n)
}

/// `<follow>`.
fn follow(f: &ast::Follow, span: Span) -> Result<NavStage, CompileError> {
    let pf = prefix(&f.common);
    let mut n = nav(NavKind::Follow, &f.common, span);
    n.until = None;
    n.lines.push(Code::stmt(format!(
        "{}Follow({}, {}, {}{})",
        pf.t, f.ac_id.value, f.distance.value, f.height.value, pf.np
    )));
    Ok(n)
}

/// `<xyz>`.
fn xyz(x: &ast::Xyz, span: Span) -> Result<NavStage, CompileError> {
    let pf = prefix(&x.common);
    let mut n = nav(NavKind::Xyz, &x.common, span);
    n.until = None;
    let r = x.radius.as_ref().map(p).unwrap_or_else(|| "100".to_string());
    n.lines.push(Code { text: format!("Goto3D({r})"), semi: false });
    n.lines.extend(vmode_lines(&pf.t, &x.vertical, None, None, true, span)?);
    Ok(n)
}

/// `<eight>`.
fn eight(e: &ast::Eight, span: Span) -> Result<NavStage, CompileError> {
    let pf = prefix(&e.common);
    let mut n = nav(NavKind::Eight, &e.common, span);
    let c = wp(&e.center);
    n.init = Some(vec![Code::stmt("nav_eight_init()")]);
    n.lines.push(max_speed("Nav", &e.common));
    n.lines.extend(vmode_lines(&pf.t, &e.vertical, Some(&c), None, false, span)?);
    n.lines.push(Code::stmt(format!("Eight({c}, {}, {})", wp(&e.turn_around), p(&e.radius))));
    Ok(n)
}

/// `<oval>`.
fn oval(o: &ast::Oval, span: Span) -> Result<NavStage, CompileError> {
    let pf = prefix(&o.common);
    let mut n = nav(NavKind::Oval, &o.common, span);
    let p1 = wp(&o.p1);
    n.init = Some(vec![Code::stmt("nav_oval_init()")]);
    n.lines.push(max_speed("Nav", &o.common));
    n.lines.extend(vmode_lines(&pf.t, &o.vertical, Some(&p1), None, false, span)?);
    n.lines.push(Code::stmt(format!("Oval({p1}, {}, {})", wp(&o.p2), p(&o.radius))));
    Ok(n)
}

/// `<survey_rectangle>`.
fn survey_rectangle(s: &ast::SurveyRectangle, span: Span) -> Result<NavStage, CompileError> {
    let pf = prefix(&s.common);
    let mut n = nav(NavKind::SurveyRectangle, &s.common, span);
    let (w1, w2) = (wp(&s.wp1), wp(&s.wp2));
    let o = match s.orientation.as_ref().map(|o| o.value) {
        Some(ast::Orientation::WE) => "WE",
        _ => "NS",
    };
    n.init = Some(vec![
        max_speed(&pf.t, &s.common),
        Code::stmt(format!(
            "{}SurveyRectangleInit({w1}, {w2}, {}, {o}{})",
            pf.t,
            p(&s.grid),
            pf.np
        )),
    ]);
    n.lines.push(Code::stmt(format!("{}SurveyRectangle({w1}, {w2})", pf.t)));
    Ok(n)
}

/// `exceeding_time` becomes a negative approach time. Upstream prepends `-` to the raw text, so
/// `a+b` gives `-a+b` (quirk 7); vouch negates the whole value: `-(a+b)`, and keeps the upstream
/// text `-t` when `t` is a single number or identifier (where both agree).
fn negate(t: &str) -> String {
    let simple =
        !t.is_empty() && t.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '.');
    if simple { format!("-{t}") } else { format!("-({t})") }
}

/// The "hmode line". `from` is the route start (`last_wp` when the stage has none).
fn hmode_line(t: &str, h: Option<HMode>, from: Option<&str>, w: &str, np: &str) -> Code {
    match h {
        Some(HMode::Route) => {
            Code::stmt(format!("{t}Segment({}, {w}{np})", from.unwrap_or("last_wp")))
        }
        _ => Code::stmt(format!("{t}GotoWaypoint({w}{np})")),
    }
}
