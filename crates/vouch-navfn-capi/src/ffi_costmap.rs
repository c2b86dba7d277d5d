//! The `extern "C"` entry points of inflation and the body check (no handle: arrays in, arrays
//! and a report out). Like `ffi.rs`: every body runs under `catch_unwind`, a failure is a status
//! and a per-thread message, raw pointers are touched only in short `unsafe` blocks whose
//! `SAFETY:` comments state what the caller promises (the header says the same).

use std::ffi::{CStr, c_char};
use std::panic::catch_unwind;

use vouch_navfn::costmap::DEFAULT_PADDING;
use vouch_navfn::maps::WorldParams;

use crate::costmap::{BodyMap, body, check_body, clearance, default_inflation_params, inflate};
use crate::ffi::{guarded, null};
use crate::planner::Failure;
use crate::{
    VouchNavfnBodyReport, VouchNavfnClearance, VouchNavfnInflationParams, VouchNavfnStatus,
};

/// nav2's default inflation parameters (the values the library's defaults hold; a test ties the
/// two), the answer should the conversion ever panic.
const NAV2_INFLATION_DEFAULTS: VouchNavfnInflationParams = VouchNavfnInflationParams {
    inflation_radius: 0.55,
    cost_scaling_factor: 10.0,
    inflate_unknown: false,
    inflate_around_unknown: false,
    footprint_padding: DEFAULT_PADDING,
};

/// nav2's default inflation parameters: `inflation_radius` 0.55, `cost_scaling_factor` 10, both
/// unknown flags false, `footprint_padding` the float 0.01 widened.
#[unsafe(no_mangle)]
pub extern "C" fn vouch_navfn_default_inflation_params() -> VouchNavfnInflationParams {
    catch_unwind(default_inflation_params).unwrap_or(NAV2_INFLATION_DEFAULTS)
}

/// `len` bytes at `costs`.
fn bytes<'a>(costs: *const u8, len: usize) -> Result<&'a [u8], Failure> {
    if costs.is_null() {
        return Err(null("costs"));
    }
    // SAFETY: the caller promises `costs` points to `len` readable bytes, unchanged during the
    // call.
    Ok(unsafe { std::slice::from_raw_parts(costs, len) })
}

/// The footprint string, if any.
fn footprint_text(text: *const c_char) -> Result<Option<String>, Failure> {
    if text.is_null() {
        return Ok(None);
    }
    // SAFETY: `text` is NULL or a NUL-terminated string (caller's promise).
    let s = unsafe { CStr::from_ptr(text) }.to_str().map_err(|_| {
        (VouchNavfnStatus::InvalidArgument, "the footprint string is not UTF-8".to_string())
    })?;
    Ok(Some(s.to_string()))
}

/// The static layer `costs` (`len` = `width`·`height` Costmap2D values, row 0 = bottom) inflated
/// as nav2's `InflationLayer` does on its first full update, for the robot `footprint` (nav2's
/// `footprint` parameter string `"[[x, y], [x, y], [x, y], …]"`, metres, robot frame) or, when
/// `footprint` is NULL, the disc of `robot_radius` (nav2's 16-gon), with `params` (NULL: nav2's
/// defaults), into `out` (`capacity` ≥ `width`·`height` bytes; `out` may be `costs`).
/// `resolution` is the map's, read as the map message carries it (a float, widened: 0.05 and
/// `(double)0.05f` give the same bytes). The bytes are those of `vouch navfn costmap`.
///
/// # Safety
/// `costs` points to `len` readable bytes; `footprint` is NULL or a NUL-terminated string;
/// `params` is NULL or points to a parameter struct; `out` points to `capacity` writable bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vouch_navfn_inflate(
    costs: *const u8,
    len: usize,
    width: usize,
    height: usize,
    resolution: f64,
    robot_radius: f64,
    footprint: *const c_char,
    params: *const VouchNavfnInflationParams,
    out: *mut u8,
    capacity: usize,
) -> VouchNavfnStatus {
    guarded(|| {
        let costs = bytes(costs, len)?;
        if out.is_null() {
            return Err(null("out"));
        }
        if capacity < len {
            let msg = format!("the buffer holds {capacity} bytes, {len} are needed");
            return Err((VouchNavfnStatus::BufferTooSmall, msg));
        }
        // SAFETY: `params` is NULL or points to a parameter struct (caller's promise).
        let p = unsafe { params.as_ref() }.copied().unwrap_or_else(default_inflation_params);
        let text = footprint_text(footprint)?;
        let robot = crate::costmap::footprint(robot_radius, text.as_deref(), p.footprint_padding)?;
        let inflated = inflate(costs, width, height, resolution, &robot, &p)?;
        // SAFETY: `out` points to `capacity` ≥ `len` writable bytes (caller's promise); it may
        // be `costs`, which is no longer read, and `inflated` is our own allocation.
        unsafe { std::ptr::copy_nonoverlapping(inflated.as_ptr(), out, inflated.len()) };
        Ok(())
    })
}

/// `n` doubles at `p` (NULL allowed when `n` is 0).
fn doubles<'a>(p: *const f64, n: usize, what: &str) -> Result<&'a [f64], Failure> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(null(what));
    }
    // SAFETY: the caller promises `p` points to `n` readable doubles.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// The robot's body swept along `pose_count` poses (`x`, `y` metres, `yaw` radians; the robot
/// translates with a pose's heading to the next pose and turns there) checked against the
/// lethal cells (254) of the static layer `costs` (`len` = `width`·`height` Costmap2D values,
/// row 0 = bottom; world frame `origin_x`, `origin_y`, `resolution`), as `vouch navfn plan`
/// checks a plan. The body is the `footprint` polygon string as given or, when `footprint` is
/// NULL, the disc of `robot_radius` (no padding: the check is of the robot itself). Lethal cells
/// within `window` metres beyond the body (the command line's default is 2) give the minimum
/// clearance. `*report` receives the verdict, the contact count and the minimum clearance;
/// `contacts`, when not NULL, receives every contact (`capacity` of them at most: a smaller
/// buffer is `BUFFER_TOO_SMALL` with `report->contacts` saying how many are needed). With
/// contacts the status is `OK` and the message names the first.
///
/// # Safety
/// `costs` points to `len` readable bytes; `footprint` is NULL or a NUL-terminated string; `x`,
/// `y`, `yaw` point to `pose_count` readable doubles each (any may be NULL when `pose_count` is
/// 0); `report` points to a writable report; `contacts` is NULL or points to `capacity`
/// writable clearances.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vouch_navfn_check_body(
    costs: *const u8,
    len: usize,
    width: usize,
    height: usize,
    origin_x: f64,
    origin_y: f64,
    resolution: f64,
    robot_radius: f64,
    footprint: *const c_char,
    x: *const f64,
    y: *const f64,
    yaw: *const f64,
    pose_count: usize,
    window: f64,
    report: *mut VouchNavfnBodyReport,
    contacts: *mut VouchNavfnClearance,
    capacity: usize,
) -> VouchNavfnStatus {
    guarded(|| {
        let costs = bytes(costs, len)?;
        // SAFETY: `report` is NULL or writable (caller's promise).
        let report = unsafe { report.as_mut() }.ok_or_else(|| null("report"))?;
        let (xs, ys) = (doubles(x, pose_count, "x")?, doubles(y, pose_count, "y")?);
        let yaws = doubles(yaw, pose_count, "yaw")?;
        let poses: Vec<[f64; 3]> =
            xs.iter().zip(ys).zip(yaws).map(|((&x, &y), &yaw)| [x, y, yaw]).collect();
        let text = footprint_text(footprint)?;
        // no padding: the body checked is the robot as given (the padding is a margin)
        let robot = crate::costmap::footprint(robot_radius, text.as_deref(), 0.0)?;
        let world = WorldParams { origin: [origin_x, origin_y], resolution };
        let map = BodyMap { costs, width, height, world, window };
        let r = check_body(&map, body(robot), &poses)?;
        *report = crate::costmap::report(&r);
        if !contacts.is_null() {
            let found: Vec<VouchNavfnClearance> = r.violations.iter().map(clearance).collect();
            if capacity < found.len() {
                let msg = format!("the buffer holds {capacity} contacts, {} found", found.len());
                return Err((VouchNavfnStatus::BufferTooSmall, msg));
            }
            // SAFETY: `contacts` points to `capacity` ≥ `found.len()` writable clearances
            // (caller's promise), not overlapping our own `found`.
            unsafe { std::ptr::copy_nonoverlapping(found.as_ptr(), contacts, found.len()) };
        }
        if let Some(v) = r.violations.first() {
            // a success with a message: the first contact
            let msg = format!(
                "body contact: pose {} → {} touches lethal cell {},{} at {:.3},{:.3}",
                v.pose,
                v.pose + 1,
                v.cell[0],
                v.cell[1],
                v.cell_xy[0],
                v.cell_xy[1]
            );
            return Err((VouchNavfnStatus::Ok, msg));
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fallback_defaults_are_nav2_defaults() {
        assert_eq!(default_inflation_params(), NAV2_INFLATION_DEFAULTS);
    }
}
