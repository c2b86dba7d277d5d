//! The map YAML reader never panics; what it accepts has a usable frame (finite origin,
//! resolution > 0) and a located error otherwise points inside the text.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    match vouch_navfn::maps::parse_map_yaml(std::path::Path::new("fuzz.yaml"), &text) {
        Ok(m) => {
            assert!(m.resolution.is_finite() && m.resolution > 0.0);
            assert!(m.origin.iter().all(|o| o.is_finite()));
        }
        Err(vouch_navfn::maps::MapError::Syntax(e)) => {
            assert!(e.span.offset() + e.span.len() <= text.len());
        }
        Err(_) => {}
    }
});
