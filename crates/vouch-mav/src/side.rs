//! Which end of a MAVLink link a message comes from or goes to: the ground station or the
//! vehicle. Protocol roles have one of these kinds, the monitor learns the side of each sender,
//! and the guard reads and writes one socket per side.

/// The ground-station side or the vehicle side of a link.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// Ground control station(s).
    Gcs,
    /// The vehicle (autopilot and its components).
    Vehicle,
}

impl Side {
    /// The opposite side.
    pub fn other(self) -> Side {
        match self {
            Side::Gcs => Side::Vehicle,
            Side::Vehicle => Side::Gcs,
        }
    }

    /// `gcs` or `vehicle`, as in logs and JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            Side::Gcs => "gcs",
            Side::Vehicle => "vehicle",
        }
    }

    /// 0 for the ground station, 1 for the vehicle (per-side tables).
    pub fn index(self) -> usize {
        self as usize
    }
}
