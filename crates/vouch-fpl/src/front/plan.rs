//! Plan-level typed building: `<flight_plan>` attributes, header, waypoints, sectors,
//! variables, modules, global exceptions, blocks, the implicit `HOME` block and forbidden
//! deroutes.

use crate::ast::*;
use crate::diag::ErrorKind;
use crate::ids::{BlockId, WpId};
use crate::span::{SourceMap, Span};

use super::ctx::Ctx;
use super::include::Merged;
use super::stages::{build_exception, build_stages};
use super::tree::Elem;

pub fn build_plan(ctx: &mut Ctx, root: &Elem, m: Merged) -> Option<FlightPlan> {
    index_names(ctx, &m);
    check_waypoint_list(ctx, root, &m);

    // Plan attributes (required ones make the plan unbuildable when absent).
    let name = ctx.req_text(root, "name");
    let lat0 = req_deg(ctx, root, "lat0", 90.0);
    let lon0 = req_deg(ctx, root, "lon0", 180.0);
    if let Some(l) = lon0.as_ref().filter(|l| l.value >= 180.0) {
        ctx.error_help(
            ErrorKind::NumberOutOfRange,
            format!("lon0 = {} is outside [-180, 180) degrees", l.text.value),
            l.text.span,
            "upstream's UTM projection refuses it (Invalid_argument \"Latlong.utm_of\")",
        );
    }
    let max_dist_from_home = ctx.req_num(root, "max_dist_from_home");
    let ground_alt = ctx.req_num(root, "ground_alt");
    let security_height = ctx.req_num(root, "security_height");
    if let Some(sh) = &security_height
        && sh.value < 0.0
    {
        ctx.error(
            ErrorKind::NumberOutOfRange,
            "security_height must not be negative",
            sh.text.span,
        );
    }
    let alt = ctx.req_num(root, "alt");
    let wp_frame = wp_frame(ctx, root);
    let qfu = ctx.opt_num(root, "qfu");
    let home_mode_height = ctx.opt_num(root, "home_mode_height");
    let geofence_max_alt = ctx.opt_num(root, "geofence_max_alt");
    let geofence_max_height = ctx.opt_num(root, "geofence_max_height");
    let geofence_sector = ctx.text(root, "geofence_sector");

    let waypoints: Vec<Waypoint> = m.waypoints.iter().filter_map(|w| waypoint(ctx, w)).collect();
    let (sectors, kml) = sectors(ctx, &m.sectors);
    if let Some(g) = &geofence_sector {
        let function = |n: &str| capitalized(n) == capitalized(&g.value);
        if !sectors.iter().any(|s: &Sector| function(&s.name.value)) {
            ctx.error_help(
                ErrorKind::BadValue,
                format!("geofence_sector '{}' names no sector", g.value),
                g.span,
                format!(
                    "upstream prints InGeofenceSector as Inside{}(), a function no sector defines",
                    capitalized(&g.value)
                ),
            );
        }
    }
    let variables = m.variables.iter().filter_map(|v| variable(ctx, v)).collect();
    let modules = m.modules.iter().filter_map(|x| module(ctx, x)).collect();
    let exceptions = global_exceptions(ctx, &m.exceptions);
    let blocks = blocks(ctx, root, &m.blocks);
    let forbidden_deroutes = m.forbidden.iter().filter_map(|f| forbidden(ctx, f)).collect();
    let header = m.header.map(|(text, span)| Header { text, span });

    Some(FlightPlan {
        sources: SourceMap::default(),
        span: root.span,
        name: name?,
        lat0: lat0?,
        lon0: lon0?,
        max_dist_from_home: max_dist_from_home?,
        ground_alt: ground_alt?,
        security_height: security_height?,
        alt: alt?,
        wp_frame,
        qfu,
        home_mode_height,
        geofence_max_alt,
        geofence_max_height,
        geofence_sector,
        attrs: root.attrs.clone(),
        header,
        waypoints_attrs: root.child("waypoints").map(|w| w.attrs.clone()).unwrap_or_default(),
        waypoints,
        sectors,
        kml,
        variables,
        modules,
        includes: m.includes,
        exceptions,
        blocks,
        forbidden_deroutes,
        warnings: Vec::new(),
        expanded: None,
    })
}

/// A `HOME` waypoint exists, and at least one waypoint.
fn check_waypoint_list(ctx: &mut Ctx, root: &Elem, m: &Merged) {
    let at = root.child("waypoints").map_or(root.span, |w| w.span);
    if !ctx.waypoints.contains_key("HOME") && !m.waypoints.is_empty() {
        ctx.error(ErrorKind::MissingElement, "no waypoint named 'HOME'", at);
    }
    if m.waypoints.is_empty() && root.child("waypoints").is_some() {
        ctx.error(ErrorKind::EmptyPlan, "the plan has no waypoint", at);
    }
}

/// The name upstream gives a sector's function (`Inside<Name>`): first letter upper-cased.
fn capitalized(s: &str) -> String {
    let mut c = s.chars();
    c.next().map(|f| f.to_ascii_uppercase().to_string() + c.as_str()).unwrap_or_default()
}

fn wp_frame(ctx: &mut Ctx, root: &Elem) -> Option<Spanned<WpFrame>> {
    let t = ctx.text(root, "wp_frame")?;
    match t.value.to_ascii_lowercase().as_str() {
        "utm" => Some(Spanned { value: WpFrame::Utm, span: t.span }),
        "ltp" => Some(Spanned { value: WpFrame::Ltp, span: t.span }),
        _ => {
            ctx.error(
                ErrorKind::BadValue,
                format!("unknown wp_frame '{}' (UTM or LTP)", t.value),
                t.span,
            );
            None
        }
    }
}

fn global_exceptions(ctx: &mut Ctx, elems: &[Elem]) -> Vec<Exception> {
    elems
        .iter()
        .filter_map(|e| {
            if e.tag_is("exception") {
                build_exception(ctx, e)
            } else {
                ctx.error(
                    ErrorKind::UnexpectedElement,
                    format!("unexpected <{}> in <exceptions>", e.tag),
                    e.span,
                );
                None
            }
        })
        .collect()
}

/// The blocks, then the implicit `HOME` block.
fn blocks(ctx: &mut Ctx, root: &Elem, elems: &[Elem]) -> Vec<Block> {
    let mut blocks: Vec<Block> = Vec::new();
    for (i, b) in elems.iter().enumerate() {
        if !b.tag_is("block") {
            ctx.error(
                ErrorKind::UnexpectedElement,
                format!("unexpected <{}> in <blocks>", b.tag),
                b.span,
            );
            continue;
        }
        if let Some(blk) = block(ctx, b, BlockId(i)) {
            blocks.push(blk);
        }
    }
    blocks.push(home_block(root.span, BlockId(elems.len())));
    blocks
}

fn req_deg(ctx: &mut Ctx, e: &Elem, name: &str, limit: f64) -> Option<Num> {
    if e.attr(name).is_none() {
        ctx.missing(e, name);
        return None;
    }
    ctx.opt_deg(e, name, limit)
}

fn waypoint(ctx: &mut Ctx, w: &Elem) -> Option<Waypoint> {
    if !w.tag_is("waypoint") {
        ctx.error(
            ErrorKind::UnexpectedElement,
            format!("unexpected <{}> in <waypoints>", w.tag),
            w.span,
        );
        return None;
    }
    let name = ctx.req_text(w, "name");
    let x = ctx.opt_num(w, "x");
    let y = ctx.opt_num(w, "y");
    let lat = ctx.opt_deg(w, "lat", 90.0);
    // Upstream normalises waypoint longitudes: any finite value is accepted.
    let lon = ctx.opt_deg(w, "lon", f64::INFINITY);
    let alt = ctx.opt_num(w, "alt");
    let height = ctx.opt_num(w, "height");
    let has_xy = w.attr("x").is_some() && w.attr("y").is_some();
    let has_ll = w.attr("lat").is_some() && w.attr("lon").is_some();
    if !has_xy && !has_ll {
        ctx.error(ErrorKind::MissingAttribute, "a waypoint needs x and y, or lat and lon", w.span);
    }
    let origin = match (&w.relative, &w.origin) {
        (Some((base, qdr, dist)), _) => {
            WaypointOrigin::Relative { base: base.clone(), qdr: *qdr, dist: *dist }
        }
        (None, Some(inc)) => WaypointOrigin::Procedure { include: inc.clone() },
        (None, None) => WaypointOrigin::Plan,
    };
    Some(Waypoint {
        name: name?,
        x,
        y,
        lat,
        lon,
        alt,
        height,
        origin,
        attrs: w.attrs.clone(),
        span: w.span,
    })
}

fn sectors(ctx: &mut Ctx, elems: &[Elem]) -> (Vec<Sector>, Vec<Text>) {
    let (mut sectors, mut kml) = (Vec::new(), Vec::new());
    for s in elems {
        if s.tag_is("kml") {
            if let Some(f) = ctx.req_text(s, "file") {
                kml.push(f);
            }
            continue;
        }
        if !s.tag_is("sector") {
            ctx.error(
                ErrorKind::UnexpectedElement,
                format!("unexpected <{}> in <sectors>", s.tag),
                s.span,
            );
            continue;
        }
        let name = ctx.req_text(s, "name");
        let mut corners = Vec::new();
        for c in &s.children {
            if !c.tag_is("corner") {
                ctx.error(
                    ErrorKind::UnexpectedElement,
                    format!("unexpected <{}> in <sector>", c.tag),
                    c.span,
                );
                continue;
            }
            if let Some(r) = ctx.req_wp(c, "name") {
                corners.push(r);
            }
        }
        if let Some(name) = name {
            sectors.push(Sector {
                name,
                color: ctx.text(s, "color"),
                sector_type: ctx.text(s, "type"),
                corners,
                attrs: s.attrs.clone(),
                span: s.span,
            });
        }
    }
    (sectors, kml)
}

fn variable(ctx: &mut Ctx, v: &Elem) -> Option<VariableDecl> {
    if v.tag_is("variable") {
        let var = ctx.req_text(v, "var")?;
        return Some(VariableDecl::Var(Variable {
            var,
            var_type: ctx.text(v, "type"),
            init: ctx.text(v, "init"),
            attrs: v.attrs.clone(),
            span: v.span,
        }));
    }
    if v.tag_is("abi_binding") {
        let name = ctx.req_text(v, "name")?;
        let vars_text = ctx.text(v, "vars");
        let handler = ctx.text(v, "handler");
        if vars_text.is_some() == handler.is_some() {
            ctx.error(
                ErrorKind::Conflict,
                "an <abi_binding> needs exactly one of 'vars' and 'handler'",
                v.span,
            );
        }
        let vars =
            vars_text.as_ref().map(|t| t.value.split(',').map(|s| s.trim().to_string()).collect());
        return Some(VariableDecl::Abi(AbiBinding {
            name,
            vars,
            vars_text,
            handler,
            id: ctx.text(v, "id"),
            attrs: v.attrs.clone(),
            span: v.span,
        }));
    }
    ctx.error(
        ErrorKind::UnexpectedElement,
        format!("unexpected <{}> in <variables>", v.tag),
        v.span,
    );
    None
}

fn module(ctx: &mut Ctx, x: &Elem) -> Option<Module> {
    if !x.tag_is("module") {
        ctx.error(
            ErrorKind::UnexpectedElement,
            format!("unexpected <{}> in <modules>", x.tag),
            x.span,
        );
        return None;
    }
    let name = ctx.req_text(x, "name")?;
    let (mut configures, mut defines) = (Vec::new(), Vec::new());
    for c in &x.children {
        let nv = |ctx: &mut Ctx| {
            Some(NameValue {
                name: ctx.req_text(c, "name")?,
                value: ctx.text(c, "value"),
                span: c.span,
            })
        };
        if c.tag_is("configure") {
            configures.extend(nv(ctx));
        } else if c.tag_is("define") {
            defines.extend(nv(ctx));
        } else {
            ctx.error(
                ErrorKind::UnexpectedElement,
                format!("unexpected <{}> in <module>", c.tag),
                c.span,
            );
        }
    }
    Some(Module {
        name,
        module_type: ctx.text(x, "type"),
        configures,
        defines,
        attrs: x.attrs.clone(),
        span: x.span,
    })
}

fn block(ctx: &mut Ctx, b: &Elem, id: BlockId) -> Option<Block> {
    let name = ctx.req_text(b, "name")?;
    let mut exceptions = Vec::new();
    let stages = build_stages(ctx, &b.children, false, &mut exceptions);
    Some(Block {
        name,
        id,
        pre_call: ctx.text(b, "pre_call"),
        post_call: ctx.text(b, "post_call"),
        on_enter: ctx.text(b, "on_enter"),
        on_exit: ctx.text(b, "on_exit"),
        strip_button: ctx.text(b, "strip_button"),
        strip_icon: ctx.text(b, "strip_icon"),
        group: ctx.text(b, "group"),
        key: ctx.text(b, "key"),
        description: ctx.text(b, "description"),
        exceptions,
        stages,
        procedure: b.origin.clone(),
        implicit: false,
        attrs: b.attrs.clone(),
        span: b.span,
    })
}

/// Upstream appends `<block name="HOME"><home/></block>` after every block.
fn home_block(span: Span, id: BlockId) -> Block {
    Block {
        name: Text { value: "HOME".to_string(), span },
        id,
        pre_call: None,
        post_call: None,
        on_enter: None,
        on_exit: None,
        strip_button: None,
        strip_icon: None,
        group: None,
        key: None,
        description: None,
        exceptions: Vec::new(),
        stages: vec![Stage {
            kind: StageKind::Home,
            attrs: Attrs::default(),
            span,
            from_path: false,
        }],
        procedure: None,
        implicit: true,
        attrs: Attrs::default(),
        span,
    }
}

fn forbidden(ctx: &mut Ctx, f: &Elem) -> Option<ForbiddenDeroute> {
    if !f.tag_is("forbidden_deroute") {
        ctx.error(
            ErrorKind::UnexpectedElement,
            format!("unexpected <{}> in <forbidden_deroutes>", f.tag),
            f.span,
        );
        return None;
    }
    let from = ctx.req_text(f, "from").and_then(|t| ctx.block_ref(t));
    let to = ctx.req_text(f, "to").and_then(|t| ctx.block_ref(t));
    let only_when = ctx.expr_attr(f, "only_when");
    Some(ForbiddenDeroute { from: from?, to: to?, only_when, attrs: f.attrs.clone(), span: f.span })
}

/// Keeps the first of each name in a table and reports later duplicates.
pub fn index_names(ctx: &mut Ctx, m: &Merged) {
    for (i, b) in m.blocks.iter().enumerate() {
        let Some(a) = b.attr("name") else { continue };
        if ctx.blocks.contains_key(&a.value) {
            ctx.error(
                ErrorKind::DuplicateBlock,
                format!("duplicate block name '{}'", a.value),
                a.value_span,
            );
        } else {
            ctx.blocks.insert(a.value.clone(), BlockId(i));
        }
    }
    let home = m.blocks.len();
    if ctx.blocks.contains_key("HOME") {
        if let Some(a) = m.blocks.iter().filter_map(|b| b.attr("name")).find(|a| a.value == "HOME")
        {
            ctx.error_help(
                ErrorKind::DuplicateBlock,
                "duplicate block name 'HOME'",
                a.value_span,
                "the implicit safety block appended after all blocks is named HOME",
            );
        }
    } else {
        ctx.blocks.insert("HOME".to_string(), BlockId(home));
    }
    for (i, w) in m.waypoints.iter().enumerate() {
        let Some(a) = w.attr("name") else { continue };
        if ctx.waypoints.contains_key(&a.value) {
            if w.relative.is_some() {
                ctx.warn(
                    format!(
                        "relative waypoint '{}' created twice (references use the first)",
                        a.value
                    ),
                    a.value_span,
                );
            } else {
                ctx.error_help(
                    ErrorKind::DuplicateWaypoint,
                    format!("duplicate waypoint name '{}'", a.value),
                    a.value_span,
                    "upstream would silently use the first one; procedures' waypoints are not prefixed",
                );
            }
        } else {
            ctx.waypoints.insert(a.value.clone(), WpId(i));
        }
    }
}
