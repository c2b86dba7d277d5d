//! The costmap nav2 gives NavFn: the static layer (from `maps`) inflated by nav2's
//! `InflationLayer` for a robot footprint (`footprint.rs`, `inflation.rs`), and the checks of
//! the robot's body along a plan against the static map (`body.rs`).

pub mod body;
pub mod footprint;
pub mod inflation;

pub use body::{Body, BodyCheck, BodyReport, Clearance};
pub use footprint::{DEFAULT_PADDING, Footprint, FootprintSpec};
pub use inflation::{INSCRIBED, InflationLayer, InflationParams, LETHAL, NO_INFORMATION};

use crate::maps::RosMap;

/// A footprint or inflation parameter nav2 would not take.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum CostmapError {
    /// A `footprint` string that is not `[[x, y], [x, y], [x, y], …]`.
    #[error("footprint `{text}`: {msg} (at character {offset})")]
    #[diagnostic(code(navfn::E120))]
    Footprint {
        /// The string given.
        text: String,
        /// Byte offset of the problem.
        offset: usize,
        /// What is wrong.
        msg: String,
    },
    /// A parameter out of its range (negative, not finite, too large for the map).
    #[error(
        "{name} = {value} is out of range (finite, ≥ 0; an inflation radius of at most 2^16 cells)"
    )]
    #[diagnostic(code(navfn::E121))]
    Parameter {
        /// The parameter's nav2 name.
        name: &'static str,
        /// The value given.
        value: f64,
    },
}

/// The costmap resolution nav2 uses for a map: the YAML value as the `OccupancyGrid` message
/// carries it (a float) widened to double by the static layer.
pub fn costmap_resolution(map: &RosMap) -> f64 {
    f64::from(map.meta.resolution as f32)
}

/// The static layer of `map` inflated for `footprint` (nav2's master costmap after the static
/// and inflation layers, as on the first update after the map arrives).
pub fn inflated_costmap(
    map: &RosMap,
    footprint: &Footprint,
    params: InflationParams,
) -> Result<Vec<u8>, CostmapError> {
    let layer = InflationLayer::new(params, costmap_resolution(map), footprint.inscribed_radius())?;
    let mut costs = map.costmap.clone();
    layer.inflate(&mut costs, map.width, map.height);
    Ok(costs)
}

/// SHA-256 of costmap bytes, lower-case hex (how goldens and summaries name a costmap).
pub fn sha256_hex(costs: &[u8]) -> String {
    use sha2::Digest as _;
    hex::encode(sha2::Sha256::digest(costs))
}
