//! The map YAML reader never panics and only accepts thresholds in [0, 1], free ≤ occupied.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(m) = vouch_navfn::maps::parse_map_yaml(std::path::Path::new("fuzz.yaml"), &text) {
        assert!(m.resolution > 0.0);
        assert!((0.0..=1.0).contains(&m.free_thresh) && (0.0..=1.0).contains(&m.occupied_thresh));
        assert!(m.free_thresh <= m.occupied_thresh);
    }
});
