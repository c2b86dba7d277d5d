//! The `extern "C"` entry points. Each one runs its body under `catch_unwind` (a test checks
//! every one); those that can fail turn a failure into a status and a per-thread message. Raw
//! pointers are touched only in short `unsafe` blocks whose `SAFETY:` comments state what the
//! caller promises (the header says the same).

use std::cell::RefCell;
use std::ffi::{CStr, CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};

use vouch_navfn::maps::WorldParams;
use vouch_navfn::planner::PlannerParams;

use crate::planner::{Failure, VouchNavfnPlanner, from_pose, plan_status, to_pose};
use crate::{
    VouchNavfnCostKind, VouchNavfnParams, VouchNavfnPlanStatus, VouchNavfnPose, VouchNavfnStatus,
};

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_error(msg: &str) {
    let text = CString::new(msg.replace('\0', " ")).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = text);
}

/// Runs `body`, catching panics; records the message of a failure.
pub(crate) fn guarded(body: impl FnOnce() -> Result<(), Failure>) -> VouchNavfnStatus {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => {
            set_error("");
            VouchNavfnStatus::Ok
        }
        Ok(Err((status, msg))) => {
            set_error(&msg);
            status
        }
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown".into());
            set_error(&format!("internal error (panic caught at the C boundary): {what}"));
            VouchNavfnStatus::Panic
        }
    }
}

pub(crate) fn null(what: &str) -> Failure {
    (VouchNavfnStatus::NullArgument, format!("{what} is NULL"))
}

/// The message of the last failed call on this thread ("" after a success). The pointer stays
/// valid until the next call on this thread.
#[unsafe(no_mangle)]
pub extern "C" fn vouch_navfn_last_error() -> *const c_char {
    // Under `catch_unwind` like every entry point; while the thread's storage is being torn
    // down (or after a caught panic) the answer is a static "".
    catch_unwind(|| LAST_ERROR.try_with(|e| e.borrow().as_ptr()).ok())
        .ok()
        .flatten()
        .unwrap_or(c"".as_ptr())
}

/// nav2's default planner parameters (the values `PlannerParams::default` holds; a test ties
/// the two), the answer should the conversion ever panic.
const NAV2_DEFAULTS: VouchNavfnParams = VouchNavfnParams {
    tolerance: 0.5,
    use_astar: false,
    allow_unknown: true,
    max_cycles_factor: 4,
    use_final_approach_orientation: false,
};

/// nav2's default planner parameters.
#[unsafe(no_mangle)]
pub extern "C" fn vouch_navfn_default_params() -> VouchNavfnParams {
    catch_unwind(|| PlannerParams::default().into()).unwrap_or(NAV2_DEFAULTS)
}

/// Creates a planner over a copy of `width`·`height` costs (row 0 first, cell (x, y) at
/// `y·width + x`) with the world frame `origin_x`, `origin_y`, `resolution` and `params`
/// (NULL: nav2's defaults). On success `*out` holds the planner; free it with
/// [`vouch_navfn_planner_free`].
///
/// # Safety
/// `costs` points to `width`·`height` readable bytes; `params` is NULL or points to a
/// parameter struct; `out` points to writable storage for a pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vouch_navfn_planner_new(
    costs: *const u8,
    width: usize,
    height: usize,
    kind: VouchNavfnCostKind,
    origin_x: f64,
    origin_y: f64,
    resolution: f64,
    params: *const VouchNavfnParams,
    out: *mut *mut VouchNavfnPlanner,
) -> VouchNavfnStatus {
    guarded(|| {
        if costs.is_null() {
            return Err(null("costs"));
        }
        if out.is_null() {
            return Err(null("out"));
        }
        let cells = width.checked_mul(height).ok_or_else(|| {
            (VouchNavfnStatus::InvalidArgument, format!("a {width}x{height} map is too large"))
        })?;
        // SAFETY: the caller promises `costs` points to `width·height` readable bytes.
        let costs = unsafe { std::slice::from_raw_parts(costs, cells) };
        // SAFETY: `params` is NULL or points to a parameter struct (caller's promise).
        let params =
            unsafe { params.as_ref() }.map_or_else(PlannerParams::default, |p| (*p).into());
        let world = WorldParams { origin: [origin_x, origin_y], resolution };
        let planner = VouchNavfnPlanner::new(costs, width, height, kind, world, params)?;
        // SAFETY: `out` is non-NULL and writable (caller's promise).
        unsafe { *out = Box::into_raw(Box::new(planner)) };
        Ok(())
    })
}

/// Creates a planner over a map_server map: a YAML file naming a PGM or PNG image (or an
/// image, with resolution 1 and origin 0), read exactly as map_server reads it, with nav2's
/// static layer costs.
///
/// # Safety
/// `path` is a NUL-terminated string; `params` is NULL or points to a parameter struct; `out`
/// points to writable storage for a pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vouch_navfn_planner_from_map(
    path: *const c_char,
    params: *const VouchNavfnParams,
    out: *mut *mut VouchNavfnPlanner,
) -> VouchNavfnStatus {
    guarded(|| {
        if path.is_null() {
            return Err(null("path"));
        }
        if out.is_null() {
            return Err(null("out"));
        }
        // SAFETY: `path` is a NUL-terminated string (caller's promise).
        let path = unsafe { CStr::from_ptr(path) }.to_string_lossy().into_owned();
        // SAFETY: `params` is NULL or points to a parameter struct (caller's promise).
        let params =
            unsafe { params.as_ref() }.map_or_else(PlannerParams::default, |p| (*p).into());
        let planner = VouchNavfnPlanner::from_map(std::path::Path::new(&path), params)?;
        // SAFETY: `out` is non-NULL and writable (caller's promise).
        unsafe { *out = Box::into_raw(Box::new(planner)) };
        Ok(())
    })
}

/// Frees a planner (NULL is ignored).
///
/// # Safety
/// `planner` is NULL or a pointer returned by a `vouch_navfn_planner_*` constructor, not yet
/// freed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vouch_navfn_planner_free(planner: *mut VouchNavfnPlanner) {
    if !planner.is_null() {
        // SAFETY: the pointer came from `Box::into_raw` and is freed once (caller's promise).
        let owned = unsafe { Box::from_raw(planner) };
        // A panic while dropping stops here, not in the caller's C frames (nothing to report:
        // the function returns nothing, and the memory is gone either way).
        let _ = catch_unwind(AssertUnwindSafe(move || drop(owned)));
    }
}

/// Borrows the planner behind a handle.
fn handle<'a>(p: *mut VouchNavfnPlanner) -> Result<&'a mut VouchNavfnPlanner, Failure> {
    // SAFETY: every entry point documents that a non-NULL handle is a live planner used by one
    // thread at a time.
    unsafe { p.as_mut() }.ok_or_else(|| null("planner"))
}

/// Width and height of the planner's map.
///
/// # Safety
/// `planner` is a live planner; `width` and `height` point to writable `size_t`s.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vouch_navfn_size(
    planner: *mut VouchNavfnPlanner,
    width: *mut usize,
    height: *mut usize,
) -> VouchNavfnStatus {
    guarded(|| {
        let (w, h) = handle(planner)?.size();
        // SAFETY: both pointers are writable when non-NULL (caller's promise).
        let (wr, hr) = unsafe { (width.as_mut(), height.as_mut()) };
        *wr.ok_or_else(|| null("width"))? = w;
        *hr.ok_or_else(|| null("height"))? = h;
        Ok(())
    })
}

/// Replaces the costmap (same size) and forgets the last plan.
///
/// # Safety
/// `planner` is a live planner; `costs` points to `len` readable bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vouch_navfn_set_costmap(
    planner: *mut VouchNavfnPlanner,
    costs: *const u8,
    len: usize,
    kind: VouchNavfnCostKind,
) -> VouchNavfnStatus {
    guarded(|| {
        let p = handle(planner)?;
        if costs.is_null() {
            return Err(null("costs"));
        }
        // SAFETY: `costs` points to `len` readable bytes (caller's promise).
        let costs = unsafe { std::slice::from_raw_parts(costs, len) };
        p.set_costs(costs, kind)
    })
}

/// nav2's `createPlan(start, goal)` in world coordinates (metres, map frame). `*pose_count`
/// receives the number of poses (0 when there is no plan). Returns `NO_PLAN` when the planner
/// found none; [`vouch_navfn_plan_status`] says why.
///
/// # Safety
/// `planner` is a live planner; `start`, `goal` point to poses; `pose_count` is NULL or
/// writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vouch_navfn_plan_world(
    planner: *mut VouchNavfnPlanner,
    start: *const VouchNavfnPose,
    goal: *const VouchNavfnPose,
    pose_count: *mut usize,
) -> VouchNavfnStatus {
    guarded(|| {
        let p = handle(planner)?;
        // SAFETY: `start` and `goal` point to poses when non-NULL (caller's promise).
        let (s, g) = unsafe { (start.as_ref(), goal.as_ref()) };
        let (s, g) = (s.ok_or_else(|| null("start"))?, g.ok_or_else(|| null("goal"))?);
        p.plan_world(&to_pose(s), &to_pose(g))?;
        finish_plan(p, pose_count)
    })
}

/// A plan between two cells (column, row; row 0 first). With ROS costs: nav2's `createPlan`
/// between the cells' corners; with NavFn costs: the planner's cell-level call sequence.
///
/// # Safety
/// `planner` is a live planner; `pose_count` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vouch_navfn_plan_cells(
    planner: *mut VouchNavfnPlanner,
    start_x: u32,
    start_y: u32,
    goal_x: u32,
    goal_y: u32,
    pose_count: *mut usize,
) -> VouchNavfnStatus {
    guarded(|| {
        let p = handle(planner)?;
        p.plan_cells([start_x, start_y], [goal_x, goal_y])?;
        finish_plan(p, pose_count)
    })
}

fn finish_plan(p: &VouchNavfnPlanner, pose_count: *mut usize) -> Result<(), Failure> {
    let n = p.last.poses.len();
    // SAFETY: `pose_count` is NULL or writable (caller's promise).
    if let Some(c) = unsafe { pose_count.as_mut() } {
        *c = n;
    }
    match p.last.status {
        Some(_) if n > 0 => Ok(()),
        Some(s) => Err((VouchNavfnStatus::NoPlan, format!("no plan: {}", s.name()))),
        None => Err((VouchNavfnStatus::NoResult, "nothing planned".into())),
    }
}

/// The status of the last plan.
///
/// # Safety
/// `planner` is a live planner; `status` points to writable storage.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vouch_navfn_plan_status(
    planner: *mut VouchNavfnPlanner,
    status: *mut VouchNavfnPlanStatus,
) -> VouchNavfnStatus {
    guarded(|| {
        let s = handle(planner)?
            .last
            .status
            .ok_or((VouchNavfnStatus::NoResult, "nothing planned".into()))?;
        // SAFETY: `status` is writable when non-NULL (caller's promise).
        *unsafe { status.as_mut() }.ok_or_else(|| null("status"))? = plan_status(s);
        Ok(())
    })
}

/// Copies items into a caller's buffer of `capacity`; `*count` receives how many there are.
fn copy_out<T: Copy>(
    items: &[T],
    out: *mut T,
    capacity: usize,
    count: *mut usize,
) -> Result<(), Failure> {
    // SAFETY: `count` is NULL or writable (caller's promise).
    if let Some(c) = unsafe { count.as_mut() } {
        *c = items.len();
    }
    if items.is_empty() {
        return Ok(());
    }
    if out.is_null() {
        // a NULL buffer asks for the count, as documented; with no count either it asks nothing
        return if count.is_null() { Err(null("out")) } else { Ok(()) };
    }
    if capacity < items.len() {
        let msg = format!("the buffer holds {capacity} items, {} are needed", items.len());
        return Err((VouchNavfnStatus::BufferTooSmall, msg));
    }
    // SAFETY: `out` points to `capacity` ≥ `items.len()` writable items (caller's promise),
    // and cannot overlap the planner's own storage.
    unsafe { std::ptr::copy_nonoverlapping(items.as_ptr(), out, items.len()) };
    Ok(())
}

/// The poses of the last plan (robot start to goal), with nav2's orientations.
///
/// # Safety
/// `planner` is a live planner; `out` points to `capacity` writable poses (or is NULL when
/// only the count is wanted); `count` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vouch_navfn_get_poses(
    planner: *mut VouchNavfnPlanner,
    out: *mut VouchNavfnPose,
    capacity: usize,
    count: *mut usize,
) -> VouchNavfnStatus {
    guarded(|| {
        let poses: Vec<VouchNavfnPose> =
            handle(planner)?.last.poses.iter().map(from_pose).collect();
        copy_out(&poses, out, capacity, count)
    })
}

/// The NavFn path of the last plan as `x, y` float pairs in cell units, from NavFn's start
/// (the robot goal) to its goal (the robot start), as `calcPath` produced it. `capacity` and
/// `*count` count points (two floats each).
///
/// # Safety
/// `planner` is a live planner; `out` points to `2·capacity` writable floats (or is NULL when
/// only the count is wanted); `count` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vouch_navfn_get_navfn_path(
    planner: *mut VouchNavfnPlanner,
    out: *mut f32,
    capacity: usize,
    count: *mut usize,
) -> VouchNavfnStatus {
    guarded(|| {
        let path = &handle(planner)?.last.path;
        copy_out(path, out.cast::<[f32; 2]>(), capacity, count)
    })
}

/// The potential of the last plan (`width`·`height` floats, 1e10 where not reached).
///
/// # Safety
/// `planner` is a live planner; `out` points to `capacity` writable floats (or is NULL when
/// only the count is wanted); `count` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vouch_navfn_get_potential(
    planner: *mut VouchNavfnPlanner,
    out: *mut f32,
    capacity: usize,
    count: *mut usize,
) -> VouchNavfnStatus {
    guarded(|| {
        let p = handle(planner)?;
        if !p.last.ran {
            return Err((VouchNavfnStatus::NoResult, "NavFn did not run".into()));
        }
        copy_out(&p.last.potential, out, capacity, count)
    })
}

/// Runs the plan checks (PositionSafe, Progress, ValidPath, FinitePotentialPath, end points)
/// on the last plan; `*violations` receives how many failed (0: the plan is checked) and the
/// message names the first.
///
/// # Safety
/// `planner` is a live planner; `violations` points to a writable `size_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vouch_navfn_check(
    planner: *mut VouchNavfnPlanner,
    violations: *mut usize,
) -> VouchNavfnStatus {
    guarded(|| {
        let report = handle(planner)?
            .check()
            .ok_or((VouchNavfnStatus::NoResult, "NavFn did not run".to_string()))?;
        // SAFETY: `violations` is writable when non-NULL (caller's promise).
        *unsafe { violations.as_mut() }.ok_or_else(|| null("violations"))? = report.count();
        if let Some(first) = report.violations.first() {
            // a success with a message: the first violation
            return Err((VouchNavfnStatus::Ok, first.to_string()));
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fallback_defaults_are_nav2_defaults() {
        let d: VouchNavfnParams = PlannerParams::default().into();
        let f = NAV2_DEFAULTS;
        assert_eq!(
            (d.tolerance, d.use_astar, d.allow_unknown, d.max_cycles_factor),
            (f.tolerance, f.use_astar, f.allow_unknown, f.max_cycles_factor)
        );
        assert_eq!(d.use_final_approach_orientation, f.use_final_approach_orientation);
    }
}
