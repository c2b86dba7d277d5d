//! nav2's inflation layer byte for byte: the five nav2 system-test maps × six parameter sets
//! (`tests/data/inflation/`, goldens of nav2's layer built stand-alone; see the README there).

mod common;

use std::path::Path;

use vouch_navfn::costmap::{
    Footprint, InflationParams, costmap_resolution, inflated_costmap, sha256_hex,
};
use vouch_navfn::maps::load_ros_map;

struct Set {
    name: String,
    footprint: Footprint,
    params: InflationParams,
}

fn sets() -> Vec<Set> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/inflation");
    let text = std::fs::read_to_string(dir.join("params.txt")).unwrap();
    text.lines()
        .map(|l| {
            let f: Vec<&str> = l.split('|').collect();
            let footprint = match f[1] {
                "radius" => Footprint::from_radius(f[2].parse().unwrap(), 0.01f32 as f64),
                _ => Footprint::from_polygon_str(f[2], 0.01f32 as f64),
            }
            .unwrap();
            let params = InflationParams {
                inflation_radius: f[3].parse().unwrap(),
                cost_scaling_factor: f[4].parse().unwrap(),
                inflate_unknown: f[5] == "1",
                inflate_around_unknown: f[6] == "1",
            };
            Set { name: f[0].to_string(), footprint, params }
        })
        .collect()
}

/// The square roots of the squared cell distances 0..4096 as this CPU's `rsqrtps` gives them,
/// folded into one number (FNV-1a over the bits).
fn rsqrt_fingerprint() -> u64 {
    let mut d: Vec<f32> = (0..4096).map(|i| i as f32).collect();
    vouch_navfn::costmap::inflation::eigen_sqrt(&mut d);
    d.iter()
        .flat_map(|v| v.to_bits().to_le_bytes())
        .fold(0xcbf2_9ce4_8422_2325u64, |h, b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3))
}

/// The goldens per CPU: nav2's layer built and run on that CPU (see the README there), keyed
/// by its `rsqrtps` fingerprint. nav2's bytes follow the CPU's reciprocal-square-root table, so
/// the goldens of one CPU are not nav2's answer on a CPU with another table.
const GOLDENS: &[(&str, u64, &str)] = &[
    ("AMD EPYC", 0x067b_7223_7cac_00e5, "goldens-amd-epyc.txt"),
    ("Intel Xeon", 0x5b4d_0258_af9a_a36f, "goldens-intel-xeon.txt"),
];

fn golden_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/inflation")
}

#[test]
fn inflation_is_bit_exact_on_nav2_maps() {
    let Some(shared) = common::shared_navfn() else { return };
    let fingerprint = rsqrt_fingerprint();
    let Some((cpu, _, file)) = GOLDENS.iter().find(|g| g.1 == fingerprint) else {
        eprintln!(
            "skipped: this CPU's rsqrtps table (fingerprint {fingerprint:#x}) is none of those \
             the goldens were made on ({}); nav2's layer gives other bytes here",
            GOLDENS.iter().map(|g| format!("{} {:#x}", g.0, g.1)).collect::<Vec<_>>().join(", ")
        );
        return;
    };
    eprintln!("comparing with the goldens of nav2's layer on {cpu} ({file})");
    let goldens = std::fs::read_to_string(golden_dir().join(file)).unwrap();
    let sets = sets();
    let mut checked = 0;
    let mut failures = Vec::new();
    for line in goldens.lines() {
        let g: Vec<&str> = line.split(' ').collect();
        let (map_name, set_name) = (g[0], g[1]);
        let path = match map_name {
            "map" => shared.join("nav2_maps/map.pgm"),
            m => shared.join(format!("nav2_maps/{m}.yaml")),
        };
        let map = load_ros_map(&path, true).unwrap();
        assert_eq!(sha256_hex(&map.costmap), g[4], "{map_name}: static layer input changed");
        let set = sets.iter().find(|s| s.name == set_name).unwrap();
        let inscribed = set.footprint.inscribed_radius();
        assert_eq!(format!("{inscribed:?}").parse::<f64>().unwrap(), g[2].parse::<f64>().unwrap());
        let cells = (set.params.inflation_radius / costmap_resolution(&map)).ceil();
        assert_eq!(cells.to_string(), g[3], "{map_name} {set_name}: cell radius");
        let out = inflated_costmap(&map, &set.footprint, set.params).unwrap();
        if sha256_hex(&out) != g[5] {
            failures.push(format!("{map_name} {set_name}"));
        }
        checked += 1;
    }
    assert_eq!(checked, 30);
    assert!(failures.is_empty(), "inflation differs from nav2's layer: {failures:?}");
}

/// The goldens of the different CPUs come from the same inputs (maps, sets, inscribed and cell
/// radii, static layers) and differ only in nav2's inflated bytes, and there on some cases: the
/// CPU's square-root table is the only thing that moves nav2's answer. Needs no `../shared`.
#[test]
fn goldens_of_two_cpus_differ_only_where_the_square_root_does() {
    let read = |file: &str| -> Vec<Vec<String>> {
        let text = std::fs::read_to_string(golden_dir().join(file)).unwrap();
        text.lines().map(|l| l.split(' ').map(str::to_string).collect()).collect()
    };
    let first = read(GOLDENS[0].2);
    assert_eq!(first.len(), 30, "5 maps x 6 parameter sets");
    for (cpu, _, file) in &GOLDENS[1..] {
        let other = read(file);
        assert_eq!(other.len(), first.len(), "{cpu}: same cases");
        let mut differing = vec![];
        for (a, b) in first.iter().zip(&other) {
            assert_eq!(a.len(), 6, "{a:?}");
            assert_eq!(a[..5], b[..5], "{cpu}: same map, set, radii and static layer");
            if a[5] != b[5] {
                differing.push(format!("{} {}", a[0], a[1]));
            }
        }
        assert!(!differing.is_empty(), "{cpu}: nav2's bytes are expected to follow the CPU");
        assert!(differing.len() < first.len(), "{cpu}: differs on every case: {differing:?}");
    }
}

/// Independent reasoning, no oracle: a single lethal cell in a free 41×41 map at 0.05 m/cell,
/// radius 0.22 (padded), inflation 0.55, k = 3: cells within the inscribed radius are 253,
/// cells beyond 11 cells stay free, and costs fall with distance.
#[test]
fn one_obstacle_costs_by_distance() {
    let (w, h) = (41usize, 41usize);
    let mut costs = vec![0u8; w * h];
    costs[20 * w + 20] = 254;
    let fp = Footprint::from_radius(0.22, 0.01f32 as f64).unwrap();
    let params =
        InflationParams { inflation_radius: 0.55, cost_scaling_factor: 3.0, ..Default::default() };
    let layer = vouch_navfn::costmap::InflationLayer::new(
        params,
        f64::from(0.05f32),
        fp.inscribed_radius(),
    )
    .unwrap();
    layer.inflate(&mut costs, w, h);
    assert_eq!(costs[20 * w + 20], 254);
    assert_eq!(costs[20 * w + 24], 253); // 0.20 m < 0.2255 m
    assert_eq!(costs[20 * w + 32], 0); // 12 cells: beyond the inflation radius
    let along: Vec<u8> = (25..=31).map(|x| costs[20 * w + x]).collect();
    assert!(along.windows(2).all(|p| p[0] >= p[1]), "{along:?}");
    // 5 cells = 0.25 m: 252·exp(−3·(0.25 − 0.2255)) = 252·0.9291 ≈ 234.1
    assert_eq!(costs[20 * w + 25], 234);
}
