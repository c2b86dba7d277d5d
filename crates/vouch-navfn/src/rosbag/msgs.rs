//! The ROS 2 messages `check-bag` reads, decoded from CDR (XCDR1 plain, little or big endian,
//! after the 4-byte encapsulation header) with `cdr-encoding`'s serde deserializer: the wire
//! structs mirror the `.msg` definitions field by field; [`decode`] turns them into the few
//! facts the checker needs.

use byteorder::{BigEndian, LittleEndian};
use serde::Deserialize;
use serde::de::DeserializeOwned;

use super::{BagError, BagMessage};
use crate::maps::MAX_CELLS;

/// `builtin_interfaces/Time`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, serde::Serialize)]
pub struct Time {
    /// Seconds.
    pub sec: i32,
    /// Nanoseconds.
    pub nanosec: u32,
}

/// `std_msgs/Header`.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
pub struct Header {
    /// Time stamp.
    pub stamp: Time,
    /// Frame.
    pub frame_id: String,
}

/// `geometry_msgs/Point` (also `Vector3`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
pub struct Point {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
}

/// `geometry_msgs/Quaternion`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
pub struct Quaternion {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
    /// w.
    pub w: f64,
}

/// `geometry_msgs/Pose` (also `Transform`: translation, rotation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
pub struct PoseMsg {
    /// Position.
    pub position: Point,
    /// Orientation.
    pub orientation: Quaternion,
}

/// `geometry_msgs/PoseStamped`.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
pub struct PoseStamped {
    /// Header.
    pub header: Header,
    /// Pose.
    pub pose: PoseMsg,
}

/// `geometry_msgs/PoseWithCovarianceStamped` (the 36 covariance doubles read as 32 + 4: a CDR
/// fixed array has no length, and serde's arrays stop at 32).
#[derive(Clone, Debug, Deserialize)]
struct PoseWithCovarianceStamped {
    header: Header,
    pose: PoseMsg,
    _covariance_a: [f64; 32],
    _covariance_b: [f64; 4],
}

/// `nav_msgs/MapMetaData`.
#[derive(Clone, Debug, Deserialize)]
struct MapMetaData {
    _map_load_time: Time,
    resolution: f32,
    width: u32,
    height: u32,
    origin: PoseMsg,
}

/// `nav_msgs/OccupancyGrid`.
#[derive(Clone, Debug, Deserialize)]
struct OccupancyGrid {
    header: Header,
    info: MapMetaData,
    data: Vec<i8>,
}

/// `nav2_msgs/CostmapMetaData`.
#[derive(Clone, Debug, Deserialize)]
struct CostmapMetaData {
    _map_load_time: Time,
    _update_time: Time,
    _layer: String,
    resolution: f32,
    size_x: u32,
    size_y: u32,
    origin: PoseMsg,
}

/// `nav2_msgs/Costmap` (the global costmap's raw bytes, `costmap_raw`).
#[derive(Clone, Debug, Deserialize)]
struct Costmap {
    header: Header,
    metadata: CostmapMetaData,
    data: Vec<u8>,
}

/// `map_msgs/OccupancyGridUpdate`.
#[derive(Clone, Debug, Deserialize)]
struct OccupancyGridUpdate {
    _header: Header,
    x: i32,
    y: i32,
    width: u32,
    height: u32,
    data: Vec<i8>,
}

/// `nav_msgs/Path`.
#[derive(Clone, Debug, Deserialize)]
struct PathMsg {
    header: Header,
    poses: Vec<PoseStamped>,
}

/// `geometry_msgs/TransformStamped`.
#[derive(Clone, Debug, Deserialize)]
struct TransformStamped {
    header: Header,
    child_frame_id: String,
    transform: PoseMsg,
}

/// `tf2_msgs/TFMessage`.
#[derive(Clone, Debug, Deserialize)]
struct TfMessage {
    transforms: Vec<TransformStamped>,
}

/// Cell values of a grid message.
#[derive(Clone, Debug, PartialEq)]
pub enum GridCells {
    /// `nav_msgs/OccupancyGrid` data: −1 unknown, 0..100 (map_server's map, or a costmap
    /// translated by nav2's costmap publisher).
    Occupancy(Vec<i8>),
    /// `nav2_msgs/Costmap` data: Costmap2D values.
    Costs(Vec<u8>),
}

/// A whole grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// Frame of the grid.
    pub frame_id: String,
    /// Metres per cell (float in the message).
    pub resolution: f32,
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Pose of cell (0, 0)'s corner.
    pub origin: PoseMsg,
    /// The cells, row 0 first.
    pub cells: GridCells,
}

/// A rectangle of new occupancy values (`map_msgs/OccupancyGridUpdate`).
#[derive(Clone, Debug, PartialEq)]
pub struct GridUpdate {
    /// Column of the rectangle's first cell.
    pub x: i64,
    /// Row of the rectangle's first cell.
    pub y: i64,
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Values, row by row.
    pub data: Vec<i8>,
}

/// A transform between two frames (`geometry_msgs/TransformStamped`).
#[derive(Clone, Debug, PartialEq)]
pub struct Transform {
    /// Parent frame.
    pub parent: String,
    /// Child frame.
    pub child: String,
    /// Child pose in the parent frame.
    pub pose: PoseMsg,
}

/// A decoded message.
#[derive(Clone, Debug, PartialEq)]
pub enum NavMessage {
    /// `nav_msgs/OccupancyGrid` or `nav2_msgs/Costmap`.
    Grid(Grid),
    /// `map_msgs/OccupancyGridUpdate`.
    GridUpdate(GridUpdate),
    /// `nav_msgs/Path`: frame and poses.
    Path(String, Vec<PoseMsg>),
    /// `geometry_msgs/PoseStamped` or `PoseWithCovarianceStamped`: frame and pose.
    Pose(String, PoseMsg),
    /// `tf2_msgs/TFMessage`.
    Transforms(Vec<Transform>),
}

/// The message types [`decode`] knows.
pub const KNOWN_TYPES: [&str; 7] = [
    "nav_msgs/msg/OccupancyGrid",
    "nav2_msgs/msg/Costmap",
    "map_msgs/msg/OccupancyGridUpdate",
    "nav_msgs/msg/Path",
    "geometry_msgs/msg/PoseStamped",
    "geometry_msgs/msg/PoseWithCovarianceStamped",
    "tf2_msgs/msg/TFMessage",
];

/// Decodes a recorded message by its type name.
pub fn decode(m: &BagMessage) -> Result<NavMessage, BagError> {
    let fail = |why: String| BagError::Decode {
        topic: m.topic.clone(),
        type_name: m.type_name.clone(),
        log_time: m.log_time,
        why,
    };
    let d = &m.data;
    match m.type_name.as_str() {
        "nav_msgs/msg/OccupancyGrid" => {
            let g: OccupancyGrid = cdr(d).map_err(fail)?;
            let (w, h) = grid_size(g.info.width, g.info.height, g.data.len()).map_err(fail)?;
            Ok(NavMessage::Grid(Grid {
                frame_id: g.header.frame_id,
                resolution: g.info.resolution,
                width: w,
                height: h,
                origin: g.info.origin,
                cells: GridCells::Occupancy(g.data),
            }))
        }
        "nav2_msgs/msg/Costmap" => {
            let c: Costmap = cdr(d).map_err(fail)?;
            let md = c.metadata;
            let (w, h) = grid_size(md.size_x, md.size_y, c.data.len()).map_err(fail)?;
            Ok(NavMessage::Grid(Grid {
                frame_id: c.header.frame_id,
                resolution: md.resolution,
                width: w,
                height: h,
                origin: md.origin,
                cells: GridCells::Costs(c.data),
            }))
        }
        "map_msgs/msg/OccupancyGridUpdate" => {
            let u: OccupancyGridUpdate = cdr(d).map_err(fail)?;
            let (w, h) = grid_size(u.width, u.height, u.data.len()).map_err(fail)?;
            Ok(NavMessage::GridUpdate(GridUpdate {
                x: u.x.into(),
                y: u.y.into(),
                width: w,
                height: h,
                data: u.data,
            }))
        }
        "nav_msgs/msg/Path" => {
            let p: PathMsg = cdr(d).map_err(fail)?;
            Ok(NavMessage::Path(p.header.frame_id, p.poses.into_iter().map(|s| s.pose).collect()))
        }
        "geometry_msgs/msg/PoseStamped" => {
            let p: PoseStamped = cdr(d).map_err(fail)?;
            Ok(NavMessage::Pose(p.header.frame_id, p.pose))
        }
        "geometry_msgs/msg/PoseWithCovarianceStamped" => {
            let p: PoseWithCovarianceStamped = cdr(d).map_err(fail)?;
            Ok(NavMessage::Pose(p.header.frame_id, p.pose))
        }
        "tf2_msgs/msg/TFMessage" => {
            let t: TfMessage = cdr(d).map_err(fail)?;
            Ok(NavMessage::Transforms(
                t.transforms
                    .into_iter()
                    .map(|s| Transform {
                        parent: s.header.frame_id,
                        child: s.child_frame_id,
                        pose: s.transform,
                    })
                    .collect(),
            ))
        }
        _ => Err(fail(format!("unsupported message type (known: {})", KNOWN_TYPES.join(", ")))),
    }
}

/// Decodes a CDR payload: the encapsulation header (`00 00` big endian, `00 01` little endian,
/// two option bytes) and the plain CDR body.
pub fn cdr<T: DeserializeOwned>(data: &[u8]) -> Result<T, String> {
    let (head, body) = data
        .split_at_checked(4)
        .ok_or_else(|| format!("{} bytes, shorter than the CDR header", data.len()))?;
    let decoded = match (head[0], head[1]) {
        (0, 1) => cdr_encoding::from_bytes::<T, LittleEndian>(body),
        (0, 0) => cdr_encoding::from_bytes::<T, BigEndian>(body),
        (a, b) => return Err(format!("encapsulation {a:02x} {b:02x} is not plain CDR")),
    };
    decoded.map(|(v, _)| v).map_err(|e| format!("bad CDR: {e}"))
}

/// Checks that a width × height grid holds `len` cells and is not absurdly large.
fn grid_size(width: u32, height: u32, len: usize) -> Result<(usize, usize), String> {
    let (w, h) = (width as usize, height as usize);
    match w.checked_mul(h) {
        Some(n) if n == len && n <= MAX_CELLS => Ok((w, h)),
        Some(n) if n <= MAX_CELLS => {
            Err(format!("a {w}x{h} grid needs {n} cells, the message holds {len}"))
        }
        _ => Err(format!("a {w}x{h} grid exceeds {MAX_CELLS} cells")),
    }
}
