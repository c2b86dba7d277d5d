//! Inflation and the body check without a handle: the checks of the C arguments and the calls
//! into `vouch_navfn::costmap`, in safe Rust (the C entry points are in `ffi_costmap.rs`). The
//! robot and the parameters mean what `vouch navfn costmap` and `vouch navfn plan` take.

use vouch_navfn::costmap::{
    Body, BodyCheck, BodyReport, Clearance, CostmapError, DEFAULT_PADDING, Footprint,
    FootprintSpec, InflationLayer, InflationParams,
};
use vouch_navfn::maps::WorldParams;

use crate::planner::Failure;
use crate::{VouchNavfnBodyReport, VouchNavfnClearance, VouchNavfnInflationParams};

fn invalid(msg: impl std::fmt::Display) -> Failure {
    (crate::VouchNavfnStatus::InvalidArgument, msg.to_string())
}

/// A footprint or parameter error with its code, as the command line names it.
fn costmap_error(e: CostmapError) -> Failure {
    let code = match e {
        CostmapError::Footprint { .. } => "navfn::E120",
        CostmapError::Parameter { .. } => "navfn::E121",
    };
    invalid(format!("{code}: {e}"))
}

/// nav2's defaults (`InflationParams::default` and `DEFAULT_PADDING`).
pub(crate) fn default_inflation_params() -> VouchNavfnInflationParams {
    let p = InflationParams::default();
    VouchNavfnInflationParams {
        inflation_radius: p.inflation_radius,
        cost_scaling_factor: p.cost_scaling_factor,
        inflate_unknown: p.inflate_unknown,
        inflate_around_unknown: p.inflate_around_unknown,
        footprint_padding: DEFAULT_PADDING,
    }
}

/// The robot as nav2 takes it: the `footprint` string when there is one, else the disc of
/// `robot_radius` (nav2's 16-gon), padded by `padding`.
pub(crate) fn footprint(
    robot_radius: f64,
    footprint: Option<&str>,
    padding: f64,
) -> Result<Footprint, Failure> {
    if !padding.is_finite() || padding < 0.0 {
        return Err(costmap_error(CostmapError::Parameter {
            name: "footprint_padding",
            value: padding,
        }));
    }
    match footprint {
        Some(text) => Footprint::from_polygon_str(text, padding),
        None => Footprint::from_radius(robot_radius, padding),
    }
    .map_err(costmap_error)
}

/// `width`·`height` cells, and as many values given.
fn cells(len: usize, width: usize, height: usize) -> Result<usize, Failure> {
    let cells = width
        .checked_mul(height)
        .ok_or_else(|| invalid(format!("a {width}x{height} map is too large")))?;
    if len != cells {
        return Err(invalid(format!(
            "{len} costs given, a {width}x{height} map has {cells} cells"
        )));
    }
    Ok(cells)
}

/// The static layer `costs` inflated for `footprint`, as `vouch navfn costmap` does: the
/// resolution taken as the map message carries it (a float, widened), so that 0.05 and the
/// costmap's own 0.05000000074505806 give the same bytes.
pub(crate) fn inflate(
    costs: &[u8],
    width: usize,
    height: usize,
    resolution: f64,
    footprint: &Footprint,
    p: &VouchNavfnInflationParams,
) -> Result<Vec<u8>, Failure> {
    cells(costs.len(), width, height)?;
    let params = InflationParams {
        inflation_radius: p.inflation_radius,
        cost_scaling_factor: p.cost_scaling_factor,
        inflate_unknown: p.inflate_unknown,
        inflate_around_unknown: p.inflate_around_unknown,
    };
    // the check before the narrowing: a NaN or negative resolution is named as given
    if !resolution.is_finite() || resolution <= 0.0 {
        return Err(costmap_error(CostmapError::Parameter {
            name: "resolution",
            value: resolution,
        }));
    }
    let resolution = f64::from(resolution as f32);
    let layer = InflationLayer::new(params, resolution, footprint.inscribed_radius())
        .map_err(costmap_error)?;
    let mut out = costs.to_vec();
    layer.inflate(&mut out, width, height);
    Ok(out)
}

/// The static map and the window of a body check.
pub(crate) struct BodyMap<'m> {
    pub costs: &'m [u8],
    pub width: usize,
    pub height: usize,
    pub world: WorldParams,
    pub window: f64,
}

/// The body `vouch navfn plan` checks: the disc of the radius or the polygon as given (nav2's
/// padding is a margin, not the robot).
pub(crate) fn body(footprint: Footprint) -> Body {
    match footprint.spec {
        FootprintSpec::Radius(r) => Body::Disc(r),
        FootprintSpec::Polygon(p) => Body::Polygon(p),
    }
}

/// The body swept along `poses` (x, y, yaw) against the lethal cells of `map`.
pub(crate) fn check_body(
    map: &BodyMap<'_>,
    body: Body,
    poses: &[[f64; 3]],
) -> Result<BodyReport, Failure> {
    cells(map.costs.len(), map.width, map.height)?;
    if map.width == 0 || map.height == 0 {
        return Err(invalid(format!("a {}x{} map has no cells", map.width, map.height)));
    }
    let w = map.world;
    if !w.resolution.is_finite() || w.resolution <= 0.0 {
        return Err(invalid(format!("resolution {} must be finite and > 0", w.resolution)));
    }
    if !w.origin.iter().all(|o| o.is_finite()) {
        return Err(invalid(format!("origin ({}, {}) must be finite", w.origin[0], w.origin[1])));
    }
    if !map.window.is_finite() || map.window < 0.0 {
        return Err(invalid(format!("window {} must be finite and ≥ 0", map.window)));
    }
    if let Some((i, p)) = poses.iter().enumerate().find(|(_, p)| !p.iter().all(|v| v.is_finite())) {
        return Err(invalid(format!("pose {i} ({}, {}, {}) is not finite", p[0], p[1], p[2])));
    }
    let check = BodyCheck {
        costs: map.costs,
        width: map.width,
        height: map.height,
        world: w,
        body,
        window: map.window,
    };
    Ok(check.check(poses))
}

pub(crate) fn clearance(c: &Clearance) -> VouchNavfnClearance {
    VouchNavfnClearance {
        clearance: c.clearance,
        pose: c.pose,
        cell_x: c.cell[0],
        cell_y: c.cell[1],
        x: c.cell_xy[0],
        y: c.cell_xy[1],
    }
}

pub(crate) fn report(r: &BodyReport) -> VouchNavfnBodyReport {
    VouchNavfnBodyReport {
        ok: r.is_ok(),
        contacts: r.violations.len(),
        motions: r.motions,
        has_min: r.min.is_some(),
        min: r.min.as_ref().map(clearance).unwrap_or_default(),
        window: r.window,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_nav2_defaults() {
        let d = default_inflation_params();
        assert_eq!((d.inflation_radius, d.cost_scaling_factor), (0.55, 10.0));
        assert!(!d.inflate_unknown && !d.inflate_around_unknown);
        assert_eq!(d.footprint_padding, f64::from(0.01f32));
    }

    #[test]
    fn a_footprint_string_wins_over_the_radius_as_in_nav2() {
        let f = footprint(5.0, Some("[[1,1],[1,-1],[-1,-1],[-1,1]]"), 0.0).unwrap();
        assert!(matches!(f.spec, FootprintSpec::Polygon(_)));
        assert_eq!(f.inscribed_radius(), 1.0);
    }
}
