//! Cost constants and the ROS Costmap2D value → NavFn cost conversion
//! (`setCostmap(isROS=true)`, SEMANTICS.md §3).

/// Obstacle / border cost; also the ±254 pseudo-gradient.
pub const COST_OBS: u8 = 254;
/// ROS costmap values ≥ 253 are obstacles in the ROS conversion.
pub const COST_OBS_ROS: u8 = 253;
/// ROS "no information".
pub const COST_UNKNOWN_ROS: u8 = 255;
/// ROS free space (the value `clearRobotCell` writes).
pub const FREE_SPACE_ROS: u8 = 0;
/// Free-space cost; success threshold of path extraction; A* heuristic scale.
pub const COST_NEUTRAL: u8 = 50;

/// `trunc(50.0 + 0.8 * f64(v))` for `v < 253`, evaluated in double like the C++ (the int
/// constant widened, `COST_FACTOR` a double literal); the clamp to 253 never triggers for
/// 8-bit input but is kept for fidelity.
const fn formula(v: u8) -> u8 {
    let c = (COST_NEUTRAL as f64 + 0.8 * v as f64) as i32;
    if c >= COST_OBS as i32 { COST_OBS - 1 } else { c as u8 }
}

const fn build_table() -> [u8; 253] {
    let mut t = [0u8; 253];
    let mut v = 0;
    while v < 253 {
        t[v] = formula(v as u8);
        v += 1;
    }
    t
}

/// NavFn cost of every traversable ROS value 0..=252.
pub const ROS_COST_TABLE: [u8; 253] = build_table();

/// One ROS value to its NavFn cost: 0..252 by the formula, 255 → 253 when unknown space is
/// allowed, everything else → 254 (obstacle).
#[inline(always)]
pub fn ros_to_navfn_cost(v: u8, allow_unknown: bool) -> u8 {
    if v < COST_OBS_ROS {
        ROS_COST_TABLE[v as usize]
    } else if v == COST_UNKNOWN_ROS && allow_unknown {
        COST_OBS - 1
    } else {
        COST_OBS
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values listed in SEMANTICS.md §3 (produced by the C++ conversion).
    #[test]
    fn table_matches_reference_values() {
        let first: Vec<u8> = (0..16).map(|v| ros_to_navfn_cost(v, true)).collect();
        assert_eq!(first, [50, 50, 51, 52, 53, 54, 54, 55, 56, 57, 58, 58, 59, 60, 61, 62]);
        assert_eq!(ros_to_navfn_cost(100, true), 130);
        assert_eq!(ros_to_navfn_cost(128, true), 152);
        assert_eq!(ros_to_navfn_cost(200, true), 210);
        assert_eq!(ros_to_navfn_cost(252, true), 251);
        assert_eq!(ros_to_navfn_cost(253, true), 254);
        assert_eq!(ros_to_navfn_cost(254, true), 254);
        assert_eq!(ros_to_navfn_cost(255, true), 253);
        assert_eq!(ros_to_navfn_cost(255, false), 254);
    }
}
