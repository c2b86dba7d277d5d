//! Ids of plan items shared by every phase: blocks and waypoints are numbered once, by the front
//! end, and every later phase refers to them by these numbers.

use serde::Serialize;

/// Index of a block in the plan's block list; equals upstream's block number.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub struct BlockId(pub usize);

/// Index of a waypoint in the plan's waypoint list (0-based, user waypoints only).
/// Upstream's `WP_` number is `index + 1` because upstream prepends the implicit `dummy`
/// waypoint: use [`WpId::upstream_index`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub struct WpId(pub usize);

impl WpId {
    /// The number upstream prints (`WP_<name>`, stage arguments): dummy waypoint is 0.
    pub fn upstream_index(self) -> usize {
        self.0 + 1
    }
}
