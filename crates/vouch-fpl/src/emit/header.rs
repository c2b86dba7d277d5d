//! Everything of `flight_plan.h` before the `nav_on_*_block` functions: banner, includes,
//! variables, `<header>` text, reference and waypoint tables, blocks table, altitude constants,
//! sectors, variable definitions and ABI bindings, `auto_nav_init` (GENERATOR_FACTS.md §4, §8, §10).

use crate::ast::{AbiBinding, FlightPlan, VariableDecl, WpFrame};
use crate::expr::ocaml_float_text;
use crate::passes::size::Fps;
use crate::passes::{CompileError, lower};

use super::compat::GeoidUse;
use super::geo::{self, Geo, Utm};
use super::{EmitOptions, Flavor, HEADER_MARKER, Writer};
use crate::front::values::ocaml_float;

/// One row of the waypoint tables (the implicit `dummy` waypoint is row 0).
struct WpRow {
    name: String,
    /// Local x/y relative to the reference UTM (after upstream's `%.2f` round trip for lat/lon).
    x: f64,
    y: f64,
    /// The ALT column of `WAYPOINTS_UTM`, a text.
    alt_text: String,
    alt: f64,
    /// `WAYPOINTS_GLOBAL`: the waypoint is given by latitude and longitude.
    global: bool,
    /// What upstream prints there: TRUE only when both texts are OCaml float literals.
    global_upstream: bool,
    /// Geodetic position when already known (LTP frame).
    geo: Option<Geo>,
    /// LTP frame: the ENU row is simply (x, y, ALT - ground_alt) of the written coordinates.
    ltp_enu: Option<[f64; 3]>,
    span: crate::span::Span,
}

fn parse_alt(text: &str, what: &str, span: crate::span::Span) -> Result<f64, CompileError> {
    ocaml_float(text).ok_or_else(|| {
        CompileError::new(format!("{what}: altitude '{text}' is not a number"), span)
    })
}

fn rows(plan: &FlightPlan, ref_geo: Geo, utm0: Utm) -> Result<Vec<WpRow>, CompileError> {
    let ground = plan.ground_alt.value;
    let ltp = matches!(plan.wp_frame.as_ref().map(|f| f.value), Some(WpFrame::Ltp));
    let plan_alt = plan.alt.text.value.clone();
    let mut out = vec![WpRow {
        name: "dummy".into(),
        x: 0.0,
        y: 0.0,
        alt: parse_alt(&plan_alt, "flight plan", plan.span)?,
        alt_text: plan_alt.clone(),
        global: false,
        global_upstream: false,
        geo: None,
        ltp_enu: None,
        span: plan.lat0.text.span,
    }];
    let ecef0 = geo::ecef_of_geo(ref_geo, ground);
    if ltp {
        // The dummy waypoint (0, 0) goes through the tangent plane like every LTP waypoint.
        let (x, y, g) = ltp_position(0.0, 0.0, out[0].alt - ground, ecef0, utm0);
        let dummy = &mut out[0];
        (dummy.x, dummy.y, dummy.geo) = (x, y, Some(g));
        dummy.ltp_enu = Some([0.0, 0.0, dummy.alt - ground]);
    }
    for w in &plan.waypoints {
        out.push(row(w, &plan_alt, ground, ltp, ecef0, utm0)?);
    }
    Ok(out)
}

/// A tangent-plane waypoint: its UTM offset in the reference zone and its geodetic position.
fn ltp_position(x: f64, y: f64, height: f64, ecef0: [f64; 3], utm0: Utm) -> (f64, f64, Geo) {
    let (g, _) = geo::geo_of_ecef(geo::ecef_of_ned(ecef0, [y, x, -height]));
    let u = geo::utm_of(g, Some(utm0.zone));
    (u.x - utm0.x, u.y - utm0.y, g)
}

fn row(
    w: &crate::ast::Waypoint,
    plan_alt: &str,
    ground: f64,
    ltp: bool,
    ecef0: [f64; 3],
    utm0: Utm,
) -> Result<WpRow, CompileError> {
    let alt_text = match (&w.alt, &w.height) {
        (Some(a), _) => a.text.value.clone(),
        (None, Some(h)) => ocaml_float_text(h.value + ground),
        (None, None) => plan_alt.to_string(),
    };
    let alt = parse_alt(&alt_text, &format!("waypoint '{}'", w.name.value), w.span)?;
    let latlon = match (&w.lat, &w.lon) {
        (Some(la), Some(lo)) => Some((la, lo)),
        _ => None,
    };
    let (x, y, g) = match (latlon, ltp) {
        (Some(_), true) => {
            return Err(CompileError::new(
                format!(
                    "waypoint '{}': lat/lon waypoints are not supported with wp_frame=\"ltp\" \
                     (upstream crashes here, quirk 10)",
                    w.name.value
                ),
                w.span,
            ));
        }
        (Some((la, lo)), false) => {
            // Projected in the reference zone, then printed "%.2f" and parsed back.
            let u = geo::utm_of(geo::geo_of_deg(la.value, lo.value), Some(utm0.zone));
            let x: f64 = format!("{:.2}", u.x - utm0.x).parse().unwrap_or(0.0);
            let y: f64 = format!("{:.2}", u.y - utm0.y).parse().unwrap_or(0.0);
            (x, y, None)
        }
        (None, _) => {
            let (Some(x), Some(y)) = (&w.x, &w.y) else {
                return Err(CompileError::new(
                    format!("waypoint '{}' needs x/y or lat/lon", w.name.value),
                    w.span,
                ));
            };
            if ltp {
                let (x, y, g) = ltp_position(x.value, y.value, alt - ground, ecef0, utm0);
                (x, y, Some(g))
            } else {
                (x.value, y.value, None)
            }
        }
    };
    if g.is_none() {
        utm_domain(&w.name.value, x, y, utm0, w.span)?;
    }
    let ltp_enu = match (&w.x, &w.y) {
        (Some(lx), Some(ly)) if ltp => Some([lx.value, ly.value, alt - ground]),
        _ => None,
    };
    let global_upstream = latlon.is_some_and(|(la, lo)| {
        ocaml_float(&la.text.value).is_some() && ocaml_float(&lo.text.value).is_some()
    });
    Ok(WpRow {
        name: w.name.value.clone(),
        x,
        y,
        alt_text,
        alt,
        global: latlon.is_some(),
        global_upstream,
        geo: g,
        ltp_enu,
        span: latlon.map_or(w.span, |(la, _)| la.text.span),
    })
}

/// Upstream's H12d: a waypoint whose UTM position (reference + local offset) lies outside the
/// domain of the inverse projection, x in 0..=1e7 and y in -1e7..=1e7 (more than about 170 to
/// 830 km west of the reference, depending on where it is in its zone): upstream's generator
/// stops there with `Invalid_argument("Latlong.of_utm")`; vouch's own inverse would print a
/// position, but not the one the plan means.
fn utm_domain(
    name: &str,
    x: f64,
    y: f64,
    utm0: Utm,
    span: crate::span::Span,
) -> Result<(), CompileError> {
    let (ux, uy) = (utm0.x + x, utm0.y + y);
    if (0.0..=1e7).contains(&ux) && (-1e7..=1e7).contains(&uy) {
        return Ok(());
    }
    Err(CompileError::new(
        format!(
            "waypoint '{name}' at x={x}, y={y} lies outside the UTM domain of the reference's \
             zone {} (UTM x {ux:.0} must be in 0..10000000, y {uy:.0} in -10000000..10000000): \
             it has no latitude/longitude (upstream stops with Invalid_argument \
             \"Latlong.of_utm\")",
            utm0.zone
        ),
        span,
    ))
}

fn is_c_suffix(name: &str) -> bool {
    name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

fn capitalize(s: &str) -> String {
    let mut c = s.chars();
    match c.next() {
        Some(f) => f.to_ascii_uppercase().to_string() + c.as_str(),
        None => String::new(),
    }
}

/// The reference and the waypoint rows (the implicit `dummy` first).
pub(super) struct Layout {
    ref_geo: Geo,
    utm0: Utm,
    wps: Vec<WpRow>,
}

impl Layout {
    pub(super) fn of(plan: &FlightPlan) -> Result<Layout, CompileError> {
        let ref_geo =
            Geo { lat: geo::rad_of_deg(plan.lat0.value), lon: geo::rad_of_deg(plan.lon0.value) };
        let utm0 = geo::utm_of(ref_geo, None);
        let wps = rows(plan, ref_geo, utm0)?;
        Ok(Layout { ref_geo, utm0, wps })
    }

    /// Where each waypoint is, at which altitude (what upstream checks against the terrain).
    pub(super) fn points(&self) -> Vec<super::terrain::Point<'_>> {
        self.wps
            .iter()
            .enumerate()
            .map(|(i, r)| super::terrain::Point {
                name: (i > 0).then_some(r.name.as_str()),
                geo: r.geo(self.utm0),
                alt: r.alt,
                span: r.span,
            })
            .collect()
    }
}

impl WpRow {
    /// The geodetic position (LTP rows know it; UTM rows are offsets from the reference).
    fn geo(&self, utm0: Utm) -> Geo {
        self.geo.unwrap_or_else(|| {
            geo::of_utm(Utm { x: utm0.x + self.x, y: utm0.y + self.y, zone: utm0.zone })
        })
    }
}

pub(super) fn top(
    w: &mut Writer,
    plan: &FlightPlan,
    fps: &Fps,
    opts: &EmitOptions,
    layout: &Layout,
) -> Result<(), CompileError> {
    let ground = plan.ground_alt.value;
    let Layout { ref_geo, utm0, wps } = layout;
    let (ref_geo, utm0) = (*ref_geo, *utm0);

    banner(w, plan, opts);
    w.raw(&format!("#define FLIGHT_PLAN_NAME \"{}\"", plan.name.value));
    w.raw(&format!(
        "#define NAV_DEFAULT_ALT {:.0} /* nominal altitude of the flight plan */",
        plan.alt.value
    ));
    w.raw(&format!("#define NAV_UTM_EAST0 {:.0}", utm0.x));
    w.raw(&format!("#define NAV_UTM_NORTH0 {:.0}", utm0.y));
    w.raw(&format!("#define NAV_UTM_ZONE0 {}", utm0.zone));
    w.raw(&format!("#define NAV_LAT0 {} /* 1e7deg */", geo::e7_of_rad(ref_geo.lat)));
    w.raw(&format!("#define NAV_LON0 {} /* 1e7deg */", geo::e7_of_rad(ref_geo.lon)));
    w.raw(&format!("#define NAV_ALT0 {:.0} /* mm above msl */", 1000.0 * ground));
    let node = w.geoid_node(ref_geo);
    let msl0 = w.compat.geoid_height(node, plan.lat0.text.span, GeoidUse::Reference);
    w.raw(&format!(
        "#define NAV_MSL0 {:.0} /* mm, EGM96 geoid-height (msl) over ellipsoid */",
        1000.0 * msl0
    ));
    w.raw(&format!("#define QFU {:.1}", plan.qfu.as_ref().map(|q| q.value).unwrap_or(0.0)));
    for (i, r) in wps.iter().enumerate() {
        if is_c_suffix(&r.name) {
            w.raw(&format!("#define WP_{} {i}", r.name));
        }
    }
    waypoint_tables(w, wps, utm0, geo::ecef_of_geo(ref_geo, ground));
    w.raw(&format!("#define NB_WAYPOINT {}", wps.len()));
    w.raw("#define FP_BLOCKS { \\");
    for b in &fps.plan().blocks {
        w.raw(&format!(" \"{}\" , \\", b.name));
    }
    w.raw("}");
    w.raw(&format!("#define NB_BLOCK {}", fps.nb_block()));
    altitudes(w, plan);
    w.raw("");
    w.raw("");
    w.raw("#ifndef FBW");
    w.raw("");
    sectors(w, plan)?;
    if let Some(s) = &plan.geofence_sector {
        w.raw("");
        w.raw(&format!("#define InGeofenceSector(_x, _y) Inside{}(_x, _y)", capitalize(&s.value)));
    }
    w.raw("");
    w.raw("#endif");
    w.raw("");
    w.raw("#ifdef NAV_C");
    w.raw("");
    variables_and_abi(w, plan)?;
    Ok(())
}

/// The banner, the includes, the variables' `extern` declarations and the `<header>` text.
fn banner(w: &mut Writer, plan: &FlightPlan, opts: &EmitOptions) {
    w.raw(&format!(
        "/* This file has been generated by gen_flight_plan from {} */",
        opts.source_path
    ));
    w.raw(&format!("/* Version {} */", opts.version));
    w.raw("/* Please DO NOT EDIT */");
    w.raw("");
    w.raw("#ifndef FLIGHT_PLAN_H");
    w.raw("#define FLIGHT_PLAN_H");
    w.raw("");
    for inc in ["std.h", "generated/modules.h", "modules/core/abi.h", "autopilot.h"] {
        w.raw(&format!("#include \"{inc}\""));
    }
    w.raw("");
    for v in &plan.variables {
        if let VariableDecl::Var(v) = v {
            let ty = v.var_type.as_ref().map(|t| t.value.as_str()).unwrap_or("float");
            w.raw(&format!("extern {ty} {};", v.var.value));
        }
    }
    w.raw("");
    if let Some(h) = &plan.header {
        match w.flavor {
            Flavor::DropIn => w.out.push_str(&h.text),
            Flavor::Instrumented => w.out.push_str(HEADER_MARKER),
        }
        w.out.push_str("\n\n");
    }
}

/// Ground, security and home-mode altitudes, distance and geofence limits.
fn altitudes(w: &mut Writer, plan: &FlightPlan) {
    let ground = plan.ground_alt.value;
    let sh = plan.security_height.value;
    let hmh = plan.home_mode_height.as_ref().map(|h| h.value.max(sh)).unwrap_or(sh);
    w.raw(&format!("#define GROUND_ALT {}", ocaml_float_text(ground)));
    w.raw(&format!("#define GROUND_ALT_CM {:.0}", 100.0 * ground));
    w.raw(&format!("#define SECURITY_HEIGHT {}", ocaml_float_text(sh)));
    w.raw(&format!("#define SECURITY_ALT {}", ocaml_float_text(sh + ground)));
    w.raw(&format!("#define HOME_MODE_HEIGHT {}", ocaml_float_text(hmh)));
    w.raw(&format!(
        "#define MAX_DIST_FROM_HOME {}",
        ocaml_float_text(plan.max_dist_from_home.value)
    ));
    if let Some(g) = &plan.geofence_max_alt {
        w.raw(&format!("#define GEOFENCE_MAX_ALTITUDE {}", ocaml_float_text(g.value)));
    }
    if let Some(g) = &plan.geofence_max_height {
        w.raw(&format!("#define GEOFENCE_MAX_HEIGHT {}", ocaml_float_text(g.value)));
    }
}

fn waypoint_tables(w: &mut Writer, wps: &[WpRow], utm0: Utm, ecef0: [f64; 3]) {
    w.raw("#define WAYPOINTS_UTM { \\");
    for r in wps {
        w.raw(&format!(" {{{:.1}, {:.1}, {}}},\\", r.x, r.y, r.alt_text));
    }
    w.raw("};");
    let geo_of = |r: &WpRow| r.geo(utm0);
    w.raw("#define WAYPOINTS_ENU { \\");
    for r in wps {
        let enu = match r.ltp_enu {
            Some(e) => e,
            None => {
                let ned = geo::ned_of_ecef(ecef0, geo::ecef_of_geo(geo_of(r), r.alt));
                [ned[1], ned[0], -ned[2]]
            }
        };
        w.raw(&format!(
            " {{{:.2}, {:.2}, {:.2}}}, /* ENU in meters  */ \\",
            enu[0], enu[1], enu[2]
        ));
    }
    w.raw("};");
    // the two LLA tables differ only in the altitude datum (and its comment)
    for (name, above_ellipsoid) in [("WAYPOINTS_LLA", false), ("WAYPOINTS_LLA_WGS84", true)] {
        w.raw(&format!("#define {name} {{ \\"));
        for r in wps {
            let g = geo_of(r);
            let node = w.geoid_node(g);
            let geoid = w.compat.geoid_height(node, r.span, GeoidUse::Row(above_ellipsoid));
            let (alt, datum) = if above_ellipsoid {
                (r.alt + geoid, "above WGS84 ref ellipsoid".to_string())
            } else {
                (r.alt, format!("above NAV_MSL0, local msl={geoid:.2}m"))
            };
            w.raw(&format!(
                " {{.lat={}, .lon={}, .alt={:.0}}}, /* 1e7deg, 1e7deg, mm ({datum}) */ \\",
                geo::e7_of_rad(g.lat),
                geo::e7_of_rad(g.lon),
                1000.0 * alt
            ));
        }
        w.raw("};");
    }
    w.raw("#define WAYPOINTS_GLOBAL { \\");
    for r in wps {
        let global = w.compat.global_flag(r.global, r.global_upstream, &r.name, r.span);
        w.raw(if global { " TRUE, \\" } else { " FALSE, \\" });
    }
    w.raw("};");
}

fn sectors(w: &mut Writer, plan: &FlightPlan) -> Result<(), CompileError> {
    for s in &plan.sectors {
        if s.sector_type.is_some() {
            return Err(CompileError::new(
                format!(
                    "sector '{}': typed (dynamic) sectors are not supported by the header generator",
                    s.name.value
                ),
                s.span,
            ));
        }
        let up = s.name.value.to_uppercase();
        let ids: Vec<String> =
            s.corners.iter().map(|c| c.id.upstream_index().to_string()).collect();
        w.raw(&format!("#define SECTOR_{up}_NB {}", ids.len()));
        w.raw(&format!("#define SECTOR_{up} {{ {} }}", ids.join(", ")));
        w.raw(&format!(
            "static inline bool Inside{}(float _x, float _y) {{",
            capitalize(&s.name.value)
        ));
        w.right();
        w.line("uint8_t i, j;");
        w.line("bool c = false;");
        w.line(&format!("const uint8_t nb_pts = SECTOR_{up}_NB;"));
        w.line(&format!("const uint8_t wps_id[] = SECTOR_{up};"));
        w.raw("");
        w.line("for (i = 0, j = nb_pts - 1; i < nb_pts; j = i++) {");
        w.right();
        w.line("if (((WaypointY(wps_id[i]) > _y) != (WaypointY(wps_id[j]) > _y)) &&");
        w.line("   (_x < (WaypointX(wps_id[j])-WaypointX(wps_id[i])) * (_y-WaypointY(wps_id[i])) / (WaypointY(wps_id[j])-WaypointY(wps_id[i])) + WaypointX(wps_id[i]))) {");
        w.right();
        w.line("if (c == TRUE) { c = FALSE; } else { c = TRUE; }");
        w.left();
        w.line("}");
        w.left();
        w.line("}");
        w.line("return c;");
        w.left();
        w.raw("}");
        w.raw("");
    }
    Ok(())
}

fn abi_vars(w: &Writer, a: &AbiBinding) -> Result<Option<Vec<(String, String)>>, CompileError> {
    let Some(vars) = &a.vars else { return Ok(None) };
    let types = w.abi.fields(&a.name.value).ok_or_else(|| {
        CompileError::new(
            format!(
                "ABI message '{}' is not in conf/abi.xml (class airborne): its field types are unknown \
                 (set PAPARAZZI_HOME, or bind it with handler=...)",
                a.name.value
            ),
            a.span,
        )
    })?;
    if types.len() != vars.len() {
        return Err(CompileError::new(
            format!(
                "ABI message '{}' has {} fields but {} vars are given",
                a.name.value,
                types.len(),
                vars.len()
            ),
            a.span,
        ));
    }
    Ok(Some(vars.iter().cloned().zip(types.iter().cloned()).collect()))
}

fn variables_and_abi(w: &mut Writer, plan: &FlightPlan) -> Result<(), CompileError> {
    let mut callbacks = Vec::new();
    for v in &plan.variables {
        match v {
            VariableDecl::Var(v) => {
                let ty = v.var_type.as_ref().map(|t| t.value.as_str()).unwrap_or("float");
                let init = v.init.as_ref().map(|t| t.value.as_str()).unwrap_or("0");
                let init = w.init(init);
                w.raw(&format!("{ty} {} = {init};", v.var.value));
            }
            VariableDecl::Abi(a) => {
                w.raw(&format!("static abi_event FP_{}_ev;", a.name.value));
                if let Some(fields) = abi_vars(w, a)? {
                    for (var, ty) in &fields {
                        if var != "_" {
                            w.raw(&format!("static {ty} {var};"));
                        }
                    }
                    callbacks.push((a.name.value.clone(), fields));
                }
            }
        }
    }
    w.raw("");
    for (name, fields) in &callbacks {
        let mut params = vec!["uint8_t sender_id __attribute__((unused))".to_string()];
        for (i, (var, ty)) in fields.iter().enumerate() {
            if var == "_" {
                params.push(format!("{ty} _unused_{i} __attribute__((unused))"));
            } else {
                params.push(format!("{ty} _{var}"));
            }
        }
        w.raw(&format!("static void FP_{name}_cb({}) {{", params.join(", ")));
        for (var, _) in fields.iter().filter(|(v, _)| v != "_") {
            w.raw(&format!("  {var} = _{var};"));
        }
        w.raw("}");
        w.raw("");
    }
    w.raw("static inline void auto_nav_init(void) {");
    w.right();
    for v in &plan.variables {
        if let VariableDecl::Abi(a) = v {
            let code = lower::abi_bind(a);
            let s = w.stmt(&code);
            w.line(&s);
        }
    }
    w.left();
    w.raw("}");
    w.raw("");
    Ok(())
}

pub(super) fn bottom(w: &mut Writer) {
    w.raw("#endif // NAV_C");
    w.raw("");
    w.raw("#endif // FLIGHT_PLAN_H");
}
