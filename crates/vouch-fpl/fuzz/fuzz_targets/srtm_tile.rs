//! SRTM tile files: any content under any of upstream's compression suffixes decodes or is an
//! error, never a panic; a decoded tile answers every lookup.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vouch_fpl::emit::srtm::{decode, Tile};

const NAMES: [&str; 6] = [
    "N0E000.hgt",
    "N0E000.hgt.gz",
    "N0E000.hgt.Z",
    "N0E000.hgt.bz2",
    "N0E000.hgt.zip",
    "N0E000.hgt.ZIP",
];

fuzz_target!(|data: &[u8]| {
    let Some((&pick, rest)) = data.split_first() else { return };
    let name = NAMES[usize::from(pick) % NAMES.len()];
    // A small side keeps every run fast; the index arithmetic is the same for 1201 and 3601.
    let side = 1201;
    if let Ok(bytes) = decode(name, std::io::Cursor::new(rest.to_vec()), side) {
        let tile = Tile::from_bytes(name.into(), side, bytes).expect("decode gives whole tiles");
        for f in [0.0, 0.0004, 0.5, 0.9999, 1.0, -0.1, f64::NAN] {
            let _ = tile.height(f, f);
        }
    }
});
