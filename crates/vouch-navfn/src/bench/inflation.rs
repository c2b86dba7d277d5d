//! The inflation workload: nav2's `InflationLayer` update on a generated static layer, vouch's
//! ([`InflationLayer::inflate`]) and an external one side by side.
//!
//! The static layer of side N (Costmap2D values, SplitMix64 from the seed): a band of unknown
//! cells along the top (a twentieth of the rows), 2 % lethal cells scattered, and one wall of
//! lethal cells every 50 rows, of random length. Parameters: the suite's ROS maps' (resolution
//! 0.05 m as a map message carries it, robot radius 0.22 m with nav2's default padding,
//! inflation radius 0.55 m, cost scaling factor 3.0).
//!
//! Timed on each side: the full-map update, on a fresh copy of the static layer each
//! repetition (the copy untimed), best of `repeat`, thread CPU time; the cost table
//! (`computeCaches` upstream) is built before, as nav2 builds it only when a parameter changes.
//!
//! The external side's contract: `CMD IN.bin W H RESOLUTION radius R INFLATION_RADIUS
//! COST_SCALING_FACTOR INFLATE_UNKNOWN(0|1) INFLATE_AROUND_UNKNOWN(0|1) OUT.bin --time R`
//! reads the static layer (row-major bytes), writes the inflated one and prints
//! `TIME reps=R best_ns=T sum_ns=S maxrss_kb=K`. Both sides' bytes are compared.

use std::path::Path;
use std::process::{Command, Stdio};

use super::side::SideName;
use super::timing::cpu_seconds;
use super::{BenchError, Row, Unit};
use crate::campaign::rng::SplitMix64;
use crate::costmap::{DEFAULT_PADDING, Footprint, InflationLayer, InflationParams};
use crate::costmap::{LETHAL, NO_INFORMATION};

/// Map resolution: 0.05 as the float of a map message, widened (as nav2's costmap holds it).
const RESOLUTION: f32 = 0.05;
const ROBOT_RADIUS: f64 = 0.22;
const PARAMS: InflationParams = InflationParams {
    inflation_radius: 0.55,
    cost_scaling_factor: 3.0,
    inflate_unknown: false,
    inflate_around_unknown: false,
};

/// The generated static layer of a `side`×`side` costmap.
pub(crate) fn static_layer(side: usize, seed: u64) -> Vec<u8> {
    let mut rng = SplitMix64::derive(seed, "bench-inflation", side as u64);
    let mut map = vec![0u8; side * side];
    let unknown_rows = side / 20;
    map[..unknown_rows * side].fill(NO_INFORMATION);
    for cell in map.iter_mut().skip(unknown_rows * side) {
        if rng.range(0, 99) < 2 {
            *cell = LETHAL;
        }
    }
    for y in (unknown_rows..side).step_by(50) {
        let start = rng.range(0, side as u32 - 1) as usize;
        let len = rng.range(0, side as u32) as usize;
        let end = (start + len).min(side);
        map[y * side + start..y * side + end].fill(LETHAL);
    }
    map
}

/// The layer both sides run.
fn layer() -> Result<InflationLayer, BenchError> {
    let footprint = Footprint::from_radius(ROBOT_RADIUS, DEFAULT_PADDING)
        .map_err(|e| BenchError::Inflation(e.to_string()))?;
    InflationLayer::new(PARAMS, f64::from(RESOLUTION), footprint.inscribed_radius())
        .map_err(|e| BenchError::Inflation(e.to_string()))
}

/// vouch's update: best thread CPU milliseconds of `repeat`, and the inflated bytes.
fn vouch_side(layer: &InflationLayer, map: &[u8], side: usize, repeat: usize) -> (f64, Vec<u8>) {
    let mut costs = map.to_vec();
    let mut best = f64::INFINITY;
    for _ in 0..repeat.max(1) {
        costs.copy_from_slice(map);
        best = best.min(cpu_seconds(|| layer.inflate(&mut costs, side, side)) * 1e3);
    }
    (best, costs)
}

/// The external update: its `TIME` line's best, milliseconds (its output in `out`).
fn oracle_side(
    words: &[String],
    input: &Path,
    out: &Path,
    side: usize,
    repeat: usize,
) -> Result<f64, BenchError> {
    let failed = |message: String| BenchError::Side {
        side: SideName::Oracle,
        target: input.to_path_buf(),
        message,
    };
    let (program, fixed) = words.split_first().ok_or(BenchError::OracleCommand(String::new()))?;
    let s = side.to_string();
    let bool01 = |b: bool| if b { "1" } else { "0" };
    let args = [
        input.to_string_lossy().into_owned(),
        s.clone(),
        s,
        format!("{:?}", f64::from(RESOLUTION)),
        "radius".into(),
        format!("{ROBOT_RADIUS:?}"),
        format!("{:?}", PARAMS.inflation_radius),
        format!("{:?}", PARAMS.cost_scaling_factor),
        bool01(PARAMS.inflate_unknown).into(),
        bool01(PARAMS.inflate_around_unknown).into(),
        out.to_string_lossy().into_owned(),
        "--time".into(),
        repeat.max(1).to_string(),
    ];
    let output = Command::new(program)
        .args(fixed)
        .args(&args)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| failed(format!("cannot start `{program}`: {e}")))?;
    if !output.status.success() {
        let err = String::from_utf8_lossy(&output.stderr);
        return Err(failed(format!(
            "{}: {}",
            output.status,
            err.lines().take(3).collect::<Vec<_>>().join(" | ")
        )));
    }
    let text = String::from_utf8_lossy(&output.stdout);
    text.lines()
        .filter_map(|l| l.strip_prefix("TIME "))
        .flat_map(str::split_whitespace)
        .find_map(|kv| kv.strip_prefix("best_ns=")?.parse::<f64>().ok())
        .map(|ns| ns / 1e6)
        .ok_or_else(|| failed("no `TIME … best_ns=` line for `--time`".into()))
}

/// One row per side length: the update's time on both sides, alternating pass by pass; `note`
/// says whether the bytes were identical.
pub(crate) fn rows(
    root: &Path,
    sides: &[usize],
    oracle: Option<&[String]>,
    (passes, repeat, seed): (usize, usize, u64),
    note: &mut dyn FnMut(String),
) -> Result<Vec<Row>, BenchError> {
    let layer = layer()?;
    let mut rows = Vec::new();
    for &side in sides.iter().filter(|&&s| s >= 3) {
        let map = static_layer(side, seed);
        let input = root.join(format!("inflation_{side}.bin"));
        let out = root.join(format!("inflation_{side}.oracle.bin"));
        std::fs::write(&input, &map).map_err(|e| BenchError::io(&input, e))?;
        note(format!("bench: inflation {side}x{side}"));
        let label = format!("inflation {side}x{side} (robot 0.22 m, inflation 0.55 m, k 3)");
        let mut row = Row::new(label, (side * side) as u64, Unit::MsPerUpdate);
        let mut ours = Vec::new();
        for pass in 0..passes.max(1) {
            let oracle_first = pass % 2 == 1;
            if let (Some(words), true) = (oracle, oracle_first) {
                row.oracle.push(oracle_side(words, &input, &out, side, repeat)?);
            }
            let (ms, bytes) = vouch_side(&layer, &map, side, repeat);
            row.vouch.push(ms);
            ours = bytes;
            if let (Some(words), false) = (oracle, oracle_first) {
                row.oracle.push(oracle_side(words, &input, &out, side, repeat)?);
            }
        }
        if oracle.is_some() {
            let theirs = std::fs::read(&out).map_err(|e| BenchError::io(&out, e))?;
            let same = if theirs == ours { "identical" } else { "DIFFERENT" };
            note(format!("bench: inflation {side}x{side}: costmap bytes {same}"));
        }
        rows.push(row);
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn static_layers_hold_every_kind_of_cell() {
        let m = static_layer(200, 1);
        assert_eq!(m.len(), 40_000);
        assert!(m[..2000].iter().all(|&c| c == NO_INFORMATION), "unknown band");
        let lethal = m.iter().filter(|&&c| c == LETHAL).count();
        assert!((700..2500).contains(&lethal), "{lethal} lethal cells");
        assert!(m.contains(&0));
        assert_eq!(m, static_layer(200, 1), "deterministic");
        assert_ne!(m, static_layer(200, 2), "seeded");
    }
}
