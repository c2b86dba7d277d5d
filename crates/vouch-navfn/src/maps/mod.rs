//! Map front ends: the paper's suite format (`test.txt` + `map.bin`) and ROS map_server maps
//! (YAML + PGM/PNG, read as map_server reads them). Every reader returns located [`MapError`]s, never panics on input.

pub mod error;
pub mod grey;
pub mod pgm;
mod png_image;
pub mod ros_yaml;
pub mod suite;
pub mod world;
pub mod yaml_meta;

pub use error::{MapError, SyntaxError, read_text};
pub use grey::MapImage;
pub use ros_yaml::{RosMap, decode_image, load_ros_map, occupancy_grid, static_layer_value};
pub use suite::{
    SuiteCase, SuiteFile, find_test_files, parse_suite_text, parse_world_params, read_suite_file,
    read_world_params,
};
pub use world::WorldParams;
pub use yaml_meta::{MapMode, RosMapMeta, parse_map_yaml};

/// Largest map we accept (cells). Far above any nav2 map in practice, low enough that a
/// corrupt header cannot make us allocate gigabytes.
pub const MAX_CELLS: usize = 1 << 28;
