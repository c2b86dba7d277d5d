//! `inflate_costmap` and `check_body`: nav2's inflation of a static layer for a robot radius or
//! footprint, and the robot's body swept along a plan against the static layer's lethal cells,
//! with the semantics of `vouch navfn costmap` and `vouch navfn plan --robot-radius/--footprint`.

use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use vouch_navfn::costmap::{
    Body, BodyCheck, CostmapError, DEFAULT_PADDING, Footprint, FootprintSpec, InflationLayer,
    InflationParams,
};
use vouch_navfn::maps::WorldParams;
use vouch_navfn::planner::Pose;

use crate::{grid, json, value_error};

/// A footprint or parameter error with its code, as the command line names it.
fn costmap_error(e: CostmapError) -> PyErr {
    let code = match e {
        CostmapError::Footprint { .. } => "navfn::E120",
        CostmapError::Parameter { .. } => "navfn::E121",
    };
    value_error(format!("{code}: {e}"))
}

/// The robot as the command line takes it: `footprint` (nav2's parameter string) or the disc
/// of `robot_radius` (nav2's 16-gon), padded; neither is a point robot.
fn robot(
    robot_radius: Option<f64>,
    footprint: Option<&str>,
    padding: Option<f64>,
) -> PyResult<Option<Footprint>> {
    let pad = padding.unwrap_or(DEFAULT_PADDING);
    if !pad.is_finite() || pad < 0.0 {
        return Err(costmap_error(CostmapError::Parameter {
            name: "footprint_padding",
            value: pad,
        }));
    }
    let f = match (footprint, robot_radius) {
        (Some(_), Some(_)) => return Err(value_error("give robot_radius or footprint, not both")),
        (Some(text), None) => Footprint::from_polygon_str(text, pad),
        (None, Some(r)) => Footprint::from_radius(r, pad),
        (None, None) => return Ok(None),
    };
    f.map(Some).map_err(costmap_error)
}

/// The static layer `costmap` (uint8, Costmap2D values, shape (height, width), row 0 = the
/// map's bottom row) inflated as nav2's `InflationLayer` does on its first full update, for a
/// robot of `robot_radius` or `footprint` (`"[[x, y], …]"`, metres, robot frame; neither: a
/// point robot) with nav2's parameters; `footprint_padding` defaults to nav2's (the float 0.01).
/// `resolution` is the map's, read as the map message carries it (a float, widened). Returns
/// the inflated costmap (uint8, same shape): the bytes `vouch navfn costmap` writes.
#[pyfunction]
#[pyo3(signature = (costmap, *, resolution=1.0, robot_radius=None, footprint=None,
    footprint_padding=None, inflation_radius=0.55, cost_scaling_factor=10.0,
    inflate_unknown=false, inflate_around_unknown=false))]
#[allow(clippy::too_many_arguments)] // Python keyword arguments
pub fn inflate_costmap<'py>(
    py: Python<'py>,
    costmap: PyReadonlyArray2<'py, u8>,
    resolution: f64,
    robot_radius: Option<f64>,
    footprint: Option<&str>,
    footprint_padding: Option<f64>,
    inflation_radius: f64,
    cost_scaling_factor: f64,
    inflate_unknown: bool,
    inflate_around_unknown: bool,
) -> PyResult<Bound<'py, numpy::PyArray2<u8>>> {
    let (h, w) = (costmap.shape()[0], costmap.shape()[1]);
    let mut costs: Vec<u8> = costmap.as_array().iter().copied().collect();
    let footprint = robot(robot_radius, footprint, footprint_padding)?;
    let params = InflationParams {
        inflation_radius,
        cost_scaling_factor,
        inflate_unknown,
        inflate_around_unknown,
    };
    if !resolution.is_finite() || resolution <= 0.0 {
        return Err(costmap_error(CostmapError::Parameter {
            name: "resolution",
            value: resolution,
        }));
    }
    // as `costmap_resolution` reads a map: the message's float, widened
    let resolution = f64::from(resolution as f32);
    let inscribed = footprint.as_ref().map_or(0.0, Footprint::inscribed_radius);
    let layer = InflationLayer::new(params, resolution, inscribed).map_err(costmap_error)?;
    layer.inflate(&mut costs, w, h);
    grid(py, h, w, costs)
}

/// Poses as (x, y, yaw): an n×3 array as given, or the n×7 poses of `plan` (x y z qx qy qz qw)
/// with the heading of their quaternion.
fn plan_poses(poses: &PyReadonlyArray2<'_, f64>) -> PyResult<Vec<[f64; 3]>> {
    let a = poses.as_array();
    let rows = a.rows().into_iter();
    let out: Vec<[f64; 3]> = match a.dim().1 {
        3 => rows.map(|r| [r[0], r[1], r[2]]).collect(),
        7 => rows
            .map(|r| {
                let p =
                    Pose { position: [r[0], r[1], r[2]], orientation: [r[3], r[4], r[5], r[6]] };
                [r[0], r[1], p.yaw()]
            })
            .collect(),
        n => return Err(value_error(format!("poses must be n×3 (x, y, yaw) or n×7, not n×{n}"))),
    };
    if let Some((i, p)) = out.iter().enumerate().find(|(_, p)| !p.iter().all(|v| v.is_finite())) {
        return Err(value_error(format!("pose {i} ({}, {}, {}) is not finite", p[0], p[1], p[2])));
    }
    Ok(out)
}

/// The robot's body swept along `poses` (n×3 x, y, yaw; or the n×7 poses `plan` returns)
/// checked against the lethal cells (254) of the static layer `costmap` (uint8, shape (height,
/// width), world frame `origin` and `resolution`), as `vouch navfn plan` checks its plan: the
/// disc of `robot_radius` or the `footprint` polygon as given (no padding). Lethal cells within
/// `window` metres beyond the body give the minimum clearance. Returns a dict: `ok` (no
/// contact), `contacts` (how many motions touch), `min_clearance` (metres, None when no lethal
/// cell lies within the window) and, as `vouch navfn plan --json` prints under `body`:
/// `motions`, `min` (clearance, pose, cell, cell_xy: where the body comes closest), `window`,
/// `violations` (each contact).
#[pyfunction]
#[pyo3(signature = (costmap, poses, *, resolution=1.0, origin=(0.0, 0.0), robot_radius=None,
    footprint=None, window=2.0))]
#[allow(clippy::too_many_arguments)] // Python keyword arguments
pub fn check_body<'py>(
    py: Python<'py>,
    costmap: PyReadonlyArray2<'py, u8>,
    poses: PyReadonlyArray2<'py, f64>,
    resolution: f64,
    origin: (f64, f64),
    robot_radius: Option<f64>,
    footprint: Option<&str>,
    window: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let (h, w) = (costmap.shape()[0], costmap.shape()[1]);
    if w == 0 || h == 0 {
        return Err(value_error(format!("a {w}x{h} costmap has no cells")));
    }
    if !resolution.is_finite() || resolution <= 0.0 {
        return Err(value_error(format!("resolution {resolution} must be finite and > 0")));
    }
    if !origin.0.is_finite() || !origin.1.is_finite() {
        return Err(value_error(format!("origin ({}, {}) must be finite", origin.0, origin.1)));
    }
    if !window.is_finite() || window < 0.0 {
        return Err(value_error(format!("window {window} must be finite and ≥ 0")));
    }
    // the padding does not enter the body: the body is the robot as given
    let body = match robot(robot_radius, footprint, None)? {
        Some(f) => match f.spec {
            FootprintSpec::Radius(r) => Body::Disc(r),
            FootprintSpec::Polygon(p) => Body::Polygon(p),
        },
        None => return Err(value_error("no robot_radius or footprint")),
    };
    let xyyaw = plan_poses(&poses)?;
    let costs: Vec<u8> = costmap.as_array().iter().copied().collect();
    let world = WorldParams { origin: [origin.0, origin.1], resolution };
    let check = BodyCheck { costs: &costs, width: w, height: h, world, body, window };
    let report = check.check(&xyyaw);
    let d = json(py, &report)?.cast_into::<PyDict>()?;
    d.set_item("ok", report.is_ok())?;
    d.set_item("contacts", report.violations.len())?;
    d.set_item("min_clearance", report.min.map(|m| m.clearance))?;
    Ok(d.into_any())
}
