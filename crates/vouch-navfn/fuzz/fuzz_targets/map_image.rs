//! Map images (PGM or PNG by content) never panic; a decoded image converts to an occupancy
//! grid of its size in every map_server mode.
#![no_main]
use libfuzzer_sys::fuzz_target;
use vouch_navfn::maps::{decode_image, occupancy_grid, MapMode, RosMapMeta};

fuzz_target!(|data: &[u8]| {
    if let Ok(image) = decode_image(std::path::Path::new("fuzz.img"), data) {
        let cells = image.grey.width * image.grey.height;
        for mode in [MapMode::Trinary, MapMode::Scale, MapMode::Raw] {
            let meta = RosMapMeta { mode, ..RosMapMeta::default() };
            let grid = occupancy_grid(&meta, &image);
            assert_eq!(grid.len(), cells);
            assert!(grid.iter().all(|&v| (-1..=100).contains(&v)));
        }
    }
});
