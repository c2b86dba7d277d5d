//! The checks upstream's generator makes while it prints the header (UPSTREAM_CHECKS.md,
//! sections G4, H7, H11, H12b, H13, H14, H18e, H18p and A1–A5; the terrain checks H8, H12c come
//! from [`super::terrain`]): the geofence limits (errors
//! below the ground, security or home-mode altitude; warnings otherwise), and upstream's
//! warnings and NOTICEs as located warnings with their own codes: low altitudes, waypoints far
//! from HOME, a reference close to a UTM zone border, `route` without `from`.

use crate::ast::{FlightPlan, HMode, Stage, StageKind, VMode, Vertical, WpFrame};
use crate::diag::{Diagnostic, ErrorKind};
use crate::expr::print_upstream;
use crate::front::values::{degrees, ocaml_float};
use crate::passes::CompileError;
use crate::span::Span;

use super::geo::{self, Geo, Utm};
use super::terrain::Terrain;

/// The plan's warnings (in upstream's order on stderr, the terrain checks at their place), or
/// the geofence error.
pub fn notices(
    plan: &FlightPlan,
    terrain: Terrain,
    compat: super::Compat,
) -> Result<Vec<Diagnostic>, CompileError> {
    let mut out = Vec::new();
    let low = Low { upstream_compat: compat == super::Compat::Upstream, ..Low::of(plan) };
    zone_border(plan, &mut out)?;
    low.check(plan.alt.value, "the plan's default altitude", plan.alt.text.span, &mut out);
    out.extend(terrain.reference);
    distances(plan, &mut out);
    low.check(
        plan.alt.value,
        "waypoint 'dummy' (index 0, at the plan's altitude)",
        plan.alt.text.span,
        &mut out,
    );
    for w in &plan.waypoints {
        let alt = match (&w.alt, &w.height) {
            (Some(a), _) => a.value,
            (None, Some(h)) => h.value + low.ground,
            (None, None) => plan.alt.value,
        };
        let at = w.alt.as_ref().or(w.height.as_ref()).map_or(w.span, |n| n.text.span);
        low.check(alt, &format!("waypoint '{}'", w.name.value), at, &mut out);
    }
    out.extend(terrain.waypoints);
    geofence(plan, &mut out)?;
    for b in &plan.blocks {
        stages(&b.stages, &low, &mut out);
    }
    Ok(out)
}

/// The low-altitude threshold: `ground_alt + security_height` (and whether upstream's
/// output is printed, for the stage notices).
struct Low {
    ground: f64,
    security: f64,
    upstream_compat: bool,
}

impl Low {
    fn of(plan: &FlightPlan) -> Low {
        Low {
            ground: plan.ground_alt.value,
            security: plan.security_height.value,
            upstream_compat: false,
        }
    }
    fn check(&self, alt: f64, what: &str, span: Span, out: &mut Vec<Diagnostic>) {
        if alt < self.ground + self.security {
            out.push(Diagnostic::warning_of(
                ErrorKind::LowAltitude,
                format!(
                    "low altitude: {what} is {alt:.0} m, below ground_alt + security_height \
                     ({:.0}+{:.0}) (upstream's NOTICE)",
                    self.ground, self.security
                ),
                Some(span),
            ));
        }
    }
    /// A stage's vertical mode `alt`: its `alt` when it prints as a plain number, else its
    /// `height` (plus ground) when that does (upstream checks nothing else).
    fn stage(&self, v: &Vertical, out: &mut Vec<Diagnostic>) {
        if v.vmode.as_ref().is_some_and(|m| m.value != VMode::Alt) {
            return;
        }
        let printed = |e: &crate::ast::ExprAttr| ocaml_float(&print_upstream(&e.expr));
        match (&v.alt, &v.height) {
            (Some(a), _) => {
                if let Some(x) = printed(a) {
                    self.check(x, "the stage's alt", a.text.span, out);
                }
            }
            (None, Some(h)) => {
                if let Some(x) = printed(h) {
                    self.check(
                        x + self.ground,
                        "the stage's height + ground_alt",
                        h.text.span,
                        out,
                    );
                }
            }
            _ => {}
        }
    }
}

fn stages(list: &[Stage], low: &Low, out: &mut Vec<Diagnostic>) {
    for s in list {
        match &s.kind {
            StageKind::While(w) => stages(&w.body, low, out),
            StageKind::For(f) => stages(&f.body, low, out),
            StageKind::Go(g) => {
                if let Some(t) = g.exceeding_time.as_ref().filter(|t| !is_simple(&t.value)) {
                    out.push(exceeding_time(&t.value, t.span, low.upstream_compat));
                }
                if g.hmode.as_ref().is_some_and(|h| h.value == HMode::Route) && g.from.is_none() {
                    out.push(Diagnostic::warning_of(
                        ErrorKind::RouteWithoutFrom,
                        "hmode=\"route\" without 'from': the segment starts at the last waypoint \
                         reached (deprecated, upstream's NOTICE)",
                        Some(s.span),
                    ));
                }
                low.stage(&g.vertical, out);
            }
            StageKind::Stay(x) => low.stage(&x.vertical, out),
            StageKind::Circle(x) => low.stage(&x.vertical, out),
            StageKind::Heading(x) => low.stage(&x.vertical, out),
            StageKind::Attitude(x) => low.stage(&x.vertical, out),
            StageKind::Eight(x) => low.stage(&x.vertical, out),
            StageKind::Oval(x) => low.stage(&x.vertical, out),
            _ => {}
        }
    }
}

/// An `exceeding_time` of several terms: upstream's `-t` negates only the first. By default the
/// whole value is negated (a correction); `--upstream-compat` prints upstream's text and says
/// what that C does.
fn exceeding_time(t: &str, span: Span, upstream_compat: bool) -> Diagnostic {
    const WHY: &str = "upstream puts a minus sign before the raw text, which negates only its \
                       first term";
    if upstream_compat {
        return Diagnostic::warning_of(
            ErrorKind::UpstreamMistake,
            format!(
                "exceeding_time=\"{t}\" is printed as upstream prints it, -{t}: the generated C \
                 negates only the first term, not the whole time -({t})"
            ),
            Some(span),
        )
        .with_help(format!("{WHY}; without --upstream-compat vouch prints -({t})"));
    }
    Diagnostic::correction(
        format!(
            "exceeding_time=\"{t}\" is printed as the approach time -({t}); upstream prints -{t}"
        ),
        span,
        format!("{WHY}; --upstream-compat prints upstream's text"),
    )
}

/// A single number or name, where `-t` negates the whole value.
fn is_simple(t: &str) -> bool {
    !t.is_empty() && t.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '.')
}

fn reference(plan: &FlightPlan) -> (Geo, Utm) {
    let g = Geo { lat: geo::rad_of_deg(plan.lat0.value), lon: geo::rad_of_deg(plan.lon0.value) };
    (g, geo::utm_of(g, None))
}

/// Upstream's G4: the points 2·min(1000, max_dist_from_home) m east and west of the reference
/// fall in another UTM zone.
fn zone_border(plan: &FlightPlan, out: &mut Vec<Diagnostic>) -> Result<(), CompileError> {
    let (_, utm0) = reference(plan);
    let d = 2.0 * plan.max_dist_from_home.value.min(1000.0);
    for dx in [d, -d] {
        let u = Utm { x: utm0.x + dx, ..utm0 };
        if !(0.0..=1e7).contains(&u.x) {
            // Upstream: Invalid_argument "Latlong.of_utm" (G4b).
            return Err(CompileError::new(
                format!(
                    "max_dist_from_home {} puts the zone check outside the UTM domain",
                    plan.max_dist_from_home.text.value
                ),
                plan.max_dist_from_home.text.span,
            ));
        }
        if geo::utm_of(geo::of_utm(u), None).zone != utm0.zone {
            out.push(Diagnostic::warning_of(
                ErrorKind::UtmZoneBorder,
                format!(
                    "the reference is less than {d:.0} m (twice the max distance) from a UTM zone \
                     border: navigation needs the GPS receiver's POSLLH message"
                ),
                Some(plan.lon0.text.span),
            ));
        }
    }
    Ok(())
}

/// Upstream's H11: every waypoint (the dummy at 0,0 included) farther than
/// `max_dist_from_home` from HOME, in local x/y (lat/lon waypoints localised first).
fn distances(plan: &FlightPlan, out: &mut Vec<Diagnostic>) {
    let (_, utm0) = reference(plan);
    let utm_frame = !matches!(plan.wp_frame.as_ref().map(|f| f.value), Some(WpFrame::Ltp));
    let xy = |w: &crate::ast::Waypoint| -> Option<(f64, f64)> {
        if let (true, Some(la), Some(lo)) = (utm_frame, &w.lat, &w.lon) {
            let (la, lo) = (degrees(&la.text.value)?, degrees(&lo.text.value)?);
            let u = geo::utm_of(geo::geo_of_deg(la, lo), Some(utm0.zone));
            let r = |v: f64| format!("{v:.2}").parse::<f64>().ok();
            return Some((r(u.x - utm0.x)?, r(u.y - utm0.y)?));
        }
        Some((w.x.as_ref()?.value, w.y.as_ref()?.value))
    };
    let Some(home) = plan.waypoints.iter().find(|w| w.name.value == "HOME").and_then(xy) else {
        return;
    };
    let max = plan.max_dist_from_home.value;
    let mut far = |name: &str, (x, y): (f64, f64), span: Span| {
        let d = ((x - home.0).powf(2.0) + (y - home.1).powf(2.0)).sqrt();
        if d > max {
            out.push(Diagnostic::warning_of(
                ErrorKind::FarFromHome,
                format!("waypoint '{name}' is {d:.0} m from HOME, farther than max_dist_from_home ({max:.0})"),
                Some(span),
            ));
        }
    };
    far("dummy", (0.0, 0.0), plan.max_dist_from_home.text.span);
    for w in &plan.waypoints {
        if let Some(p) = xy(w) {
            far(&w.name.value, p, w.span);
        }
    }
}

/// Upstream's H13/H14: geofence limits below the ground, security or home-mode altitude are
/// errors; below the default altitude a warning; an accepted limit is announced.
fn geofence(plan: &FlightPlan, out: &mut Vec<Diagnostic>) -> Result<(), CompileError> {
    let ground = plan.ground_alt.value;
    let sh = plan.security_height.value;
    let hmh = plan.home_mode_height.as_ref().map_or(sh, |h| h.value.max(sh));
    let alt = plan.alt.value;
    let fail = |msg: String, span: Span| Err(CompileError::geofence(msg, span));
    let note = |msg: String, span: Span| {
        Diagnostic::warning_of(ErrorKind::GeofenceNotice, msg, Some(span))
    };
    if let Some(g) = &plan.geofence_max_alt {
        let (v, sp) = (g.value, g.text.span);
        if v < ground {
            return fail(format!("geofence_max_alt {v:.0} is below ground_alt {ground:.0}"), sp);
        }
        if v < ground + sh {
            return fail(
                format!(
                    "geofence_max_alt {v:.0} is below ground_alt + security_height ({ground:.0}+{sh:.0})"
                ),
                sp,
            );
        }
        if v < ground + hmh {
            return fail(
                format!(
                    "geofence_max_alt {v:.0} is below ground_alt + home_mode_height ({ground:.0}+{hmh:.0})"
                ),
                sp,
            );
        }
        if v < alt {
            out.push(note(
                format!("geofence_max_alt {v:.0} is below the plan's default altitude {alt:.0}"),
                sp,
            ));
        }
        out.push(note(
            format!("geofence maximum altitude set to {v:.0} (GEOFENCE_MAX_ALTITUDE)"),
            sp,
        ));
    }
    if let Some(g) = &plan.geofence_max_height {
        let (v, sp) = (g.value, g.text.span);
        if v < sh {
            return fail(
                format!("geofence_max_height {v:.0} is below security_height {sh:.0}"),
                sp,
            );
        }
        if v < hmh {
            return fail(
                format!("geofence_max_height {v:.0} is below home_mode_height {hmh:.0}"),
                sp,
            );
        }
        if v + ground < alt {
            out.push(note(
                format!("geofence_max_height + ground_alt ({:.0}) is below the plan's default altitude {alt:.0}", v + ground),
                sp,
            ));
        }
        out.push(note(
            format!("geofence maximum height above ground set to {v:.0} (GEOFENCE_MAX_HEIGHT)"),
            sp,
        ));
    }
    Ok(())
}
