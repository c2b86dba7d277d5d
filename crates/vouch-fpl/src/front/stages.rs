//! Typed building of stages and exceptions. Stage tags are matched case-sensitively, as
//! upstream's generator does (`<GO>` passes the DTD but is an unknown stage).

use crate::ast::*;
use crate::diag::ErrorKind;

use super::ctx::Ctx;
use super::schema::STAGE_TAGS;
use super::tree::Elem;
use super::values::bool_text;

/// Builds the stages of a block (`in_loop = false`) or of a `while`/`for` body. Block-level
/// exceptions are collected into `exceptions` (they take no stage slot).
pub fn build_stages(
    ctx: &mut Ctx,
    elems: &[Elem],
    in_loop: bool,
    exceptions: &mut Vec<Exception>,
) -> Vec<Stage> {
    let mut out = Vec::new();
    for e in elems {
        if e.tag == "exception" {
            if in_loop {
                ctx.error_help(
                    ErrorKind::UnexpectedElement,
                    "an <exception> inside <while>/<for> is not supported",
                    e.span,
                    "upstream's generator fails on it with Failure(\"Unreachable\"); put it at block level",
                );
            } else if let Some(x) = build_exception(ctx, e) {
                exceptions.push(x);
            }
            continue;
        }
        if let Some(kind) = stage_kind(ctx, e) {
            out.push(Stage { kind, attrs: e.attrs.clone(), span: e.span, from_path: e.from_path });
        }
    }
    out
}

pub fn build_exception(ctx: &mut Ctx, e: &Elem) -> Option<Exception> {
    let cond = ctx.req_expr(e, "cond");
    let deroute = ctx.req_text(e, "deroute").and_then(|t| ctx.block_ref(t));
    Some(Exception {
        cond: cond?,
        deroute: deroute?,
        exec: ctx.text(e, "exec"),
        attrs: e.attrs.clone(),
        span: e.span,
    })
}

fn stage_kind(ctx: &mut Ctx, e: &Elem) -> Option<StageKind> {
    match e.tag.as_str() {
        "while" | "for" | "set" | "call" | "call_once" | "deroute" | "return" => control(ctx, e),
        "go" => go(ctx, e),
        "stay" | "circle" | "heading" | "attitude" | "guided" | "follow" | "xyz" | "home" => {
            navigation(ctx, e)
        }
        "eight" | "oval" | "survey_rectangle" => two_step(ctx, e),
        tag => unknown_stage(ctx, e, tag),
    }
}

/// Loops, assignments, calls and block changes.
fn control(ctx: &mut Ctx, e: &Elem) -> Option<StageKind> {
    Some(match e.tag.as_str() {
        "while" => {
            let cond = ctx.expr_attr(e, "cond");
            let body = build_stages(ctx, &e.children, true, &mut Vec::new());
            StageKind::While(While { cond, body })
        }
        "for" => {
            let var = ctx.req_text(e, "var");
            let from = ctx.req_expr(e, "from");
            let to = ctx.req_expr(e, "to");
            let body = build_stages(ctx, &e.children, true, &mut Vec::new());
            StageKind::For(For { var: var?, from: from?, to: to?, body })
        }
        "set" => {
            let var = ctx.req_text(e, "var");
            let value = ctx.req_expr(e, "value");
            StageKind::Set(Set { var: var?, value: value? })
        }
        "call" => {
            let fun = ctx.req_text(e, "fun");
            let until = ctx.expr_attr(e, "until");
            let loop_ = flag(ctx, e, "loop");
            let break_ = flag(ctx, e, "break");
            StageKind::Call(Call { fun: fun?, until, loop_, break_ })
        }
        "call_once" => {
            let fun = ctx.req_text(e, "fun");
            let break_ = flag(ctx, e, "break");
            StageKind::CallOnce(CallOnce { fun: fun?, break_ })
        }
        "deroute" => {
            let block = ctx.req_text(e, "block").and_then(|t| ctx.block_ref(t));
            StageKind::Deroute(Deroute { block: block? })
        }
        "return" => StageKind::Return(Return { reset_stage: ctx.text(e, "reset_stage") }),
        _ => return None,
    })
}

/// One-step navigation stages other than `go`.
fn navigation(ctx: &mut Ctx, e: &Elem) -> Option<StageKind> {
    Some(match e.tag.as_str() {
        "stay" => {
            let wp = ctx.req_wp(e, "wp");
            let hmode = hmode(ctx, e);
            if let Some(h) = hmode.as_ref().filter(|h| h.value == HMode::Route) {
                ctx.error_help(
                    ErrorKind::Conflict,
                    "hmode=\"route\" on <stay>: a stay has no 'from' waypoint",
                    h.span,
                    "upstream prints NavSegment(, wp) here, which is not valid C",
                );
            }
            let vertical = vertical(ctx, e, hmode.as_ref());
            let common = common(ctx, e);
            StageKind::Stay(Stay { wp: wp?, hmode, vertical, common })
        }
        "circle" => {
            let wp = ctx.req_wp(e, "wp");
            let radius = ctx.req_expr(e, "radius");
            let vertical = vertical(ctx, e, None);
            let common = common(ctx, e);
            StageKind::Circle(Circle { wp: wp?, radius: radius?, vertical, common })
        }
        "heading" => {
            let course = ctx.req_expr(e, "course");
            let vertical = vertical(ctx, e, None);
            let common = common(ctx, e);
            StageKind::Heading(Heading { course: course?, vertical, common })
        }
        "attitude" => {
            let roll = ctx.req_expr(e, "roll");
            let vertical = vertical(ctx, e, None);
            let common = common(ctx, e);
            StageKind::Attitude(Attitude { roll: roll?, vertical, common })
        }
        "guided" => {
            let commands = ctx.req_text(e, "commands");
            let flags = ctx.text(e, "flags");
            let common = common(ctx, e);
            StageKind::Guided(Guided { commands: commands?, flags, common })
        }
        "follow" => {
            let ac_id = ctx.req_text(e, "ac_id");
            let distance = ctx.req_text(e, "distance");
            let height = ctx.req_text(e, "height");
            let common = common(ctx, e);
            StageKind::Follow(Follow {
                ac_id: ac_id?,
                distance: distance?,
                height: height?,
                common,
            })
        }
        "xyz" => {
            let radius = ctx.expr_attr(e, "radius");
            let vertical = vertical(ctx, e, None);
            let common = common(ctx, e);
            StageKind::Xyz(Xyz { radius, vertical, common })
        }
        "home" => StageKind::Home,
        _ => return None,
    })
}

/// Navigation stages with their own init stage.
fn two_step(ctx: &mut Ctx, e: &Elem) -> Option<StageKind> {
    Some(match e.tag.as_str() {
        "eight" => {
            let center = ctx.req_wp(e, "center");
            let turn_around = ctx.req_wp(e, "turn_around");
            let radius = ctx.req_expr(e, "radius");
            let vertical = vertical(ctx, e, None);
            let common = common(ctx, e);
            StageKind::Eight(Eight {
                center: center?,
                turn_around: turn_around?,
                radius: radius?,
                vertical,
                common,
            })
        }
        "oval" => {
            let p1 = ctx.req_wp(e, "p1");
            let p2 = ctx.req_wp(e, "p2");
            let radius = ctx.req_expr(e, "radius");
            let vertical = vertical(ctx, e, None);
            let common = common(ctx, e);
            StageKind::Oval(Oval { p1: p1?, p2: p2?, radius: radius?, vertical, common })
        }
        "survey_rectangle" => {
            let wp1 = ctx.req_wp(e, "wp1");
            let wp2 = ctx.req_wp(e, "wp2");
            let grid = ctx.req_expr(e, "grid");
            let orientation = ctx.text(e, "orientation").and_then(|t| match t.value.as_str() {
                "NS" => Some(Spanned { value: Orientation::NS, span: t.span }),
                "WE" => Some(Spanned { value: Orientation::WE, span: t.span }),
                _ => {
                    ctx.error(
                        ErrorKind::BadValue,
                        format!("survey orientation must be NS or WE, found '{}'", t.value),
                        t.span,
                    );
                    None
                }
            });
            let common = common(ctx, e);
            StageKind::SurveyRectangle(SurveyRectangle {
                wp1: wp1?,
                wp2: wp2?,
                grid: grid?,
                orientation,
                common,
            })
        }
        _ => return None,
    })
}

/// A tag that is no stage: located, with the known ones (or the case hint) as help.
fn unknown_stage(ctx: &mut Ctx, e: &Elem, tag: &str) -> Option<StageKind> {
    let lc = tag.to_ascii_lowercase();
    let help = if STAGE_TAGS.contains(&lc.as_str()) {
        "stage tags are case-sensitive in upstream's generator".to_string()
    } else {
        format!(
            "known stages: {}",
            STAGE_TAGS
                .iter()
                .filter(|t| **t != "exception")
                .copied()
                .collect::<Vec<_>>()
                .join(", ")
        )
    };
    ctx.error_help(ErrorKind::UnknownStage, format!("unknown stage '<{tag}>'"), e.span, help);
    None
}

fn go(ctx: &mut Ctx, e: &Elem) -> Option<StageKind> {
    let wp = ctx.wp_ref(e, "wp");
    let xy_read = e.attr("wp").is_none();
    let x = ctx.lazy_expr(e, "x", xy_read, "the stage has a 'wp'");
    let y = ctx.lazy_expr(e, "y", xy_read, "the stage has a 'wp'");
    if e.attr("wp").is_none() && (e.attr("x").is_none() || e.attr("y").is_none()) {
        ctx.missing(e, "wp");
    }
    let from = ctx.wp_ref(e, "from");
    let hmode = hmode(ctx, e);
    let vertical = vertical(ctx, e, hmode.as_ref());
    let approaching_time = ctx.text(e, "approaching_time");
    let exceeding_time = ctx.text(e, "exceeding_time");
    if let (Some(_), Some(t)) = (&approaching_time, &exceeding_time) {
        ctx.error(
            ErrorKind::Conflict,
            "both 'approaching_time' and 'exceeding_time' are given",
            t.span,
        );
    }
    let common = common(ctx, e);
    if e.attr("wp").is_some() && wp.is_none() {
        return None;
    }
    if e.attr("from").is_some() && from.is_none() {
        return None;
    }
    Some(StageKind::Go(Go {
        wp,
        x,
        y,
        from,
        hmode,
        vertical,
        approaching_time,
        exceeding_time,
        common,
    }))
}

fn flag(ctx: &mut Ctx, e: &Elem, name: &str) -> Option<Spanned<bool>> {
    let t = ctx.text(e, name)?;
    match bool_text(&t.value) {
        Some(v) => Some(Spanned { value: v, span: t.span }),
        None => {
            ctx.error(
                ErrorKind::BadValue,
                format!("'{name}' must be TRUE or FALSE, found '{}'", t.value),
                t.span,
            );
            None
        }
    }
}

fn hmode(ctx: &mut Ctx, e: &Elem) -> Option<Spanned<HMode>> {
    let t = ctx.text(e, "hmode")?;
    let v = match t.value.as_str() {
        "route" => HMode::Route,
        "direct" => HMode::Direct,
        _ => {
            ctx.error(
                ErrorKind::BadValue,
                format!("unknown hmode '{}' (route or direct)", t.value),
                t.span,
            );
            return None;
        }
    };
    Some(Spanned { value: v, span: t.span })
}

fn vertical(ctx: &mut Ctx, e: &Elem, hmode: Option<&Spanned<HMode>>) -> Vertical {
    let vmode = ctx.text(e, "vmode").and_then(|t| {
        let v = match t.value.as_str() {
            "alt" => VMode::Alt,
            "climb" => VMode::Climb,
            "throttle" => VMode::Throttle,
            "glide" => VMode::Glide,
            "xyz" => VMode::Xyz,
            _ => {
                ctx.error(
                    ErrorKind::BadValue,
                    format!("unknown vmode '{}' (alt, climb, throttle, glide, xyz)", t.value),
                    t.span,
                );
                return None;
            }
        };
        Some(Spanned { value: v, span: t.span })
    });
    let pitch = match ctx.text(e, "pitch") {
        Some(t) if t.value == "auto" => Some(Pitch::Auto(t.span)),
        Some(_) => ctx.expr_attr(e, "pitch").map(Pitch::Expr),
        None => None,
    };
    if let (Some(Pitch::Auto(sp)), Some(v)) = (&pitch, &vmode)
        && v.value == VMode::Throttle
    {
        ctx.error(
            ErrorKind::Conflict,
            "pitch=\"auto\" cannot be combined with vmode=\"throttle\"",
            *sp,
        );
    }
    if let Some(v) = vmode.as_ref().filter(|v| v.value == VMode::Glide) {
        if e.tag != "go" {
            ctx.error_help(
                ErrorKind::Conflict,
                format!("vmode=\"glide\" only works on <go> (here <{}>)", e.tag),
                v.span,
                "upstream prints NavGlide(, wp) here, which is not valid C",
            );
        } else if hmode.is_none_or(|h| h.value != HMode::Route) {
            ctx.error(ErrorKind::Conflict, "vmode=\"glide\" needs hmode=\"route\"", v.span);
        }
    }
    // `xyz` stages force the vertical mode; everything but the pitch line is left out.
    let mode =
        if e.tag == "xyz" { VMode::Xyz } else { vmode.as_ref().map_or(VMode::Alt, |v| v.value) };
    let auto = matches!(pitch, Some(Pitch::Auto(_)));
    let alt = ctx.lazy_expr(e, "alt", mode == VMode::Alt, "the vertical mode is not alt");
    let height_read = mode == VMode::Alt && e.attr("alt").is_none();
    let height =
        ctx.lazy_expr(e, "height", height_read, "alt is given, or the vertical mode is not alt");
    let climb = ctx.lazy_expr(e, "climb", mode == VMode::Climb, "the vertical mode is not climb");
    let throttle = ctx.lazy_expr(
        e,
        "throttle",
        auto || mode == VMode::Throttle,
        "the vertical mode is not throttle and pitch is not auto",
    );
    Vertical { vmode, alt, height, climb, throttle, pitch }
}

fn common(ctx: &mut Ctx, e: &Elem) -> NavCommon {
    NavCommon {
        pre_call: ctx.text(e, "pre_call"),
        post_call: ctx.text(e, "post_call"),
        nav_type: ctx.text(e, "nav_type"),
        nav_params: ctx.text(e, "nav_params"),
        until: ctx.expr_attr(e, "until"),
        max_speed: ctx.text(e, "max_speed"),
    }
}
