//! Inputs of the scale benchmark, written as suite files so that both sides read them under the
//! oracle contract: random-cost maps (every interior cell uniform in 50..=253, a 254 border;
//! SplitMix64, so a seed gives the same bytes everywhere) with one corner-to-corner case, and, on
//! one of them, cases from the centre to points at growing distance (growing explored area).

use std::path::{Path, PathBuf};

use super::BenchError;
use crate::campaign::rng::SplitMix64;

/// One generated test file.
pub(crate) struct ScaleInput {
    /// What the row is called.
    pub label: String,
    /// The `test.txt`.
    pub test: PathBuf,
}

/// The bytes of a `side`×`side` random-cost map.
fn random_map(side: usize, seed: u64) -> Vec<u8> {
    let mut rng = SplitMix64::derive(seed, "bench-scale", side as u64);
    let mut map = vec![254u8; side * side];
    for y in 1..side.saturating_sub(1) {
        for x in 1..side - 1 {
            map[y * side + x] = rng.range(50, 253) as u8;
        }
    }
    map
}

fn write(path: &Path, bytes: &[u8]) -> Result<(), BenchError> {
    std::fs::write(path, bytes).map_err(|e| BenchError::io(path, e))
}

fn test_file(
    dir: &Path,
    side: usize,
    map: &str,
    cases: &[[usize; 4]],
) -> Result<PathBuf, BenchError> {
    std::fs::create_dir_all(dir).map_err(|e| BenchError::io(dir, e))?;
    let mut text = format!("{side} {side}\n{map}\n\n");
    for c in cases {
        text.push_str(&format!("{} {} {} {}\n", c[0], c[1], c[2], c[3]));
    }
    let test = dir.join("test.txt");
    write(&test, text.as_bytes())?;
    Ok(test)
}

/// Writes the maps of `sides` below `root`: `size_N/` with the corner-to-corner case, and
/// `explore_N_dD/` (cases from the centre of the map of side `explore_side` to `D` cells right).
pub(crate) fn generate(
    root: &Path,
    sides: &[usize],
    explore_side: Option<usize>,
    seed: u64,
) -> Result<(Vec<ScaleInput>, Vec<ScaleInput>), BenchError> {
    let mut by_size = Vec::new();
    for &side in sides {
        let dir = root.join(format!("size_{side}"));
        std::fs::create_dir_all(&dir).map_err(|e| BenchError::io(&dir, e))?;
        write(&dir.join("map.bin"), &random_map(side, seed))?;
        let test = test_file(&dir, side, "map.bin", &[[1, 1, side - 2, side - 2]])?;
        by_size.push(ScaleInput { label: format!("{side}x{side}"), test });
    }
    let mut by_distance = Vec::new();
    if let Some(side) = explore_side {
        let c = side / 2;
        let mut d = 4;
        while c + d < side - 1 {
            let dir = root.join(format!("explore_{side}_d{d}"));
            let map = format!("../size_{side}/map.bin");
            let test = test_file(&dir, side, &map, &[[c, c, c + d, c]])?;
            by_distance.push(ScaleInput { label: format!("{side}x{side} d={d}"), test });
            d *= 4;
        }
    }
    Ok((by_size, by_distance))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_have_a_border_and_navfn_costs() {
        let m = random_map(9, 1);
        assert_eq!(m.len(), 81);
        for y in 0..9 {
            for x in 0..9 {
                let v = m[y * 9 + x];
                if x == 0 || y == 0 || x == 8 || y == 8 {
                    assert_eq!(v, 254);
                } else {
                    assert!((50..=253).contains(&v), "{v}");
                }
            }
        }
        assert_eq!(m, random_map(9, 1), "deterministic");
        assert_ne!(m, random_map(9, 2), "seeded");
    }
}
