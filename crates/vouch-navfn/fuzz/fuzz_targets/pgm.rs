//! The PGM reader never panics and returns exactly width·height samples ≤ maxval.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(img) = vouch_navfn::maps::pgm::parse_pgm(std::path::Path::new("fuzz.pgm"), data) {
        assert_eq!(img.pixels.len(), img.width * img.height);
        assert!(img.pixels.iter().all(|&p| p <= img.maxval));
    }
});
