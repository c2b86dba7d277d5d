//! The inflation guarantee: the smallest `inflation_radius` (for a given `cost_scaling_factor`)
//! under which NavFn's plans keep the robot's body off the static map's obstacles.
//!
//! What is exhaustive and what is sampled:
//! * **radii — exhaustive at the map's resolution.** nav2's layer depends on the radius only
//!   through `ceil(inflation_radius / resolution)`, so every radius in `((k−1)·res, k·res]`
//!   gives the same costmap; every `k` from `max_radius` down is tried, and the answer is the
//!   `k·res` above the largest failing `k` (every larger radius up to `max_radius` is then safe
//!   for the sampled goals).
//! * **goals — sampled.** `goals` cells are drawn (SplitMix64 of `seed`) among the end cells
//!   of each inflated costmap, the same stream for every `k`. An end cell has a cost below
//!   inscribed and the body, placed at the cell's world point, clears every lethal cell by
//!   more than `end_clearance` (default one cell): nav2 places a NavFn cell at its corner, half
//!   a cell from where NavFn's costs put it, so a robot started a hair from a wall is touched
//!   by the first step of any plan, whatever the inflation.
//! * **starts — exhaustive** (or every `start_stride`-th column and row): for each goal the
//!   potential is propagated once over the whole map (NavFn Dijkstra from the goal, no early
//!   stop), and the path of every start cell with a finite potential is extracted from it.
//!   This is NavFn without nav2's swap (nav2 propagates from the robot and descends from the
//!   goal): the same planner, with the roles of the two ends as in the paper.
//! * **the body — exact for translations** (see `costmap::body`); segments whose end cells are
//!   far from every lethal cell (centre distance above the body's radius plus 2.5 cells, a
//!   bound no point of a segment of at most √2 cells can beat) are skipped without the exact
//!   test; longer segments always get it.
//!
//! Shards split the goals: shard `I` of `N` runs goal `g` when `g mod N = I`; the merged
//! answer is the largest failing `k` over the shards.

use serde::{Deserialize, Serialize};

use crate::campaign::rng::SplitMix64;
use crate::campaign::shard::Shard;
use crate::core::{COST_OBS, Cell, NavFn, NoObserver, POT_HIGH};
use crate::costmap::{
    Body, BodyCheck, BodyReport, Clearance, CostmapError, Footprint, InflationLayer,
    InflationParams, costmap_resolution,
};
use crate::maps::RosMap;

/// What the search runs.
#[derive(Clone, Debug)]
pub struct SearchConfig {
    /// The footprint (its inscribed radius drives nav2's layer).
    pub footprint: Footprint,
    /// The body checked.
    pub body: Body,
    /// `cost_scaling_factor` and the unknown-space flags; the radius is searched.
    pub params: InflationParams,
    /// Goals sampled.
    pub goals: usize,
    /// Seed of the goal sampling.
    pub seed: u64,
    /// Every `start_stride`-th column and row is a start (1 = every cell).
    pub start_stride: usize,
    /// Largest radius tried (metres).
    pub max_radius: f64,
    /// Smallest radius tried (metres; 0 for the whole search, `max_radius` to check one
    /// radius: a body-check campaign at that inflation radius).
    pub min_radius: f64,
    /// The goals of this shard.
    pub shard: Shard,
    /// Starts and goals are the cells where the body (its circumscribed disc) clears every
    /// lethal cell by more than this (metres; `None`: one cell).
    pub end_clearance: Option<f64>,
}

/// A plan that lets the body touch an obstacle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Counterexample {
    /// The inflation radius (metres, `k·res`).
    pub inflation_radius: f64,
    /// Goal index in the sampled stream.
    pub goal_index: usize,
    /// Start and goal cells (column, row).
    pub start: [usize; 2],
    /// Goal cell.
    pub goal: [usize; 2],
    /// The plan's poses (x, y, yaw), from start to goal.
    pub poses: Vec<[f64; 3]>,
    /// The first contact.
    pub contact: ContactAt,
}

/// Where the body touches.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactAt {
    /// The pose the motion starts from.
    pub pose: usize,
    /// The lethal cell.
    pub cell: [usize; 2],
}

impl From<Clearance> for ContactAt {
    fn from(c: Clearance) -> Self {
        ContactAt { pose: c.pose, cell: c.cell }
    }
}

/// The answer (for one shard, or merged).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SearchReport {
    /// Costmap resolution (metres).
    pub resolution: f64,
    /// The footprint's inscribed radius (metres).
    pub inscribed_radius: f64,
    /// `cost_scaling_factor`.
    pub cost_scaling_factor: f64,
    /// Goals sampled in all, seed, start stride, largest radius tried.
    pub goals: usize,
    /// Seed.
    pub seed: u64,
    /// Start stride.
    pub start_stride: usize,
    /// Largest radius tried (metres).
    pub max_radius: f64,
    /// Smallest radius tried (metres).
    #[serde(default)]
    pub min_radius: f64,
    /// Shards merged (`I/N` specs).
    pub shards: Vec<String>,
    /// Smallest safe radius `k·res` (None: even `max_radius` fails).
    pub smallest_safe_radius: Option<f64>,
    /// The plan that fails at the largest failing radius.
    pub counterexample: Option<Counterexample>,
    /// The clearance required at starts and goals (metres).
    pub end_clearance: f64,
    /// Paths extracted and checked.
    pub paths: u64,
    /// Radii tried.
    pub radii_tried: usize,
}

/// Run the search on the static layer of `map`.
pub fn search(map: &RosMap, cfg: &SearchConfig) -> Result<SearchReport, CostmapError> {
    let res = costmap_resolution(map);
    let inscribed = cfg.footprint.inscribed_radius();
    let kmax = (cfg.max_radius / res).ceil().max(0.0) as u32;
    let kmin = ((cfg.min_radius / res).ceil().max(0.0) as u32).min(kmax);
    let mut report = SearchReport {
        resolution: res,
        inscribed_radius: inscribed,
        cost_scaling_factor: cfg.params.cost_scaling_factor,
        goals: cfg.goals,
        seed: cfg.seed,
        start_stride: cfg.start_stride.max(1),
        max_radius: f64::from(kmax) * res,
        min_radius: f64::from(kmin) * res,
        shards: vec![cfg.shard.spec()],
        smallest_safe_radius: None,
        counterexample: None,
        end_clearance: cfg.end_clearance.unwrap_or(res),
        paths: 0,
        radii_tried: 0,
    };
    let mut nav = NavFn::new(map.width, map.height).map_err(|_| CostmapError::Parameter {
        name: "map size",
        value: (map.width * map.height) as f64,
    })?;
    let margin = cfg.end_clearance.unwrap_or(res);
    if !margin.is_finite() || margin < 0.0 {
        return Err(CostmapError::Parameter { name: "end_clearance", value: margin });
    }
    let near = near_lethal(map, &cfg.body, margin, res);
    let fits = body_fits(map, &cfg.body, report.end_clearance, &near);
    for k in (kmin..=kmax).rev() {
        // a radius inside the class of k: ceil(r / res) = k whatever the rounding
        let radius = if k == 0 { 0.0 } else { (f64::from(k) - 0.5) * res };
        let params = InflationParams { inflation_radius: radius, ..cfg.params };
        let layer = InflationLayer::new(params, res, inscribed)?;
        let mut costs = map.costmap.clone();
        layer.inflate(&mut costs, map.width, map.height);
        report.radii_tried += 1;
        let found = run_radius(map, cfg, &costs, &near, &fits, &mut nav, &mut report.paths);
        if let Some(mut cx) = found {
            cx.inflation_radius = f64::from(k) * res;
            report.smallest_safe_radius = (k < kmax).then(|| f64::from(k + 1) * res);
            report.counterexample = Some(cx);
            return Ok(report);
        }
    }
    report.smallest_safe_radius = Some(f64::from(kmin) * res);
    Ok(report)
}

/// The sampled goals and every start on one costmap; the first contact found.
fn run_radius(
    map: &RosMap,
    cfg: &SearchConfig,
    costs: &[u8],
    near: &[bool],
    fits: &[bool],
    nav: &mut NavFn,
    paths: &mut u64,
) -> Option<Counterexample> {
    let (w, h) = (map.width, map.height);
    let open: Vec<usize> = (0..w * h)
        .filter(|&i| costs[i] < crate::costmap::INSCRIBED && interior(i, w, h) && fits[i])
        .collect();
    if open.is_empty() || nav.set_costs_ros(costs, true).is_err() {
        return None;
    }
    let mut rng = SplitMix64::new(cfg.seed);
    let check = BodyCheck {
        costs: &map.costmap,
        width: w,
        height: h,
        world: map.world(),
        body: cfg.body.clone(),
        window: 0.0,
    };
    let stride = cfg.start_stride.max(1);
    for g in 0..cfg.goals {
        let goal = open[rng.index(open.len())];
        if g % cfg.shard.count as usize != cfg.shard.index as usize {
            continue;
        }
        let goal_cell = Cell::new(goal % w, goal / w);
        nav.set_goal(goal_cell).ok()?;
        nav.setup();
        // the whole map: no early stop, a cycle limit no propagation reaches
        nav.propagate_dijkstra(w * h * 4, false, &mut NoObserver);
        for &s in open.iter().filter(|&&s| (s % w) % stride == 0 && (s / w) % stride == 0) {
            if nav.potential()[s] >= POT_HIGH || nav.costs()[s] >= COST_OBS {
                continue;
            }
            nav.set_start(Cell::new(s % w, s / w)).ok()?;
            let n = nav.calc_path(4 * w.max(h), &mut NoObserver);
            *paths += 1;
            if n == 0 {
                continue;
            }
            let poses = to_poses(map, nav.path());
            if !touches_near(&poses, map, near) {
                continue;
            }
            let report = check.check(&poses);
            if let Some(first) = report.violations.first() {
                return Some(Counterexample {
                    inflation_radius: 0.0,
                    goal_index: g,
                    start: [s % w, s / w],
                    goal: [goal % w, goal / w],
                    poses,
                    contact: (*first).into(),
                });
            }
        }
    }
    None
}

/// The counterexample's plan once more, to be shown: the costmap of its radius inflated as the
/// search inflated it (`params` with the report's resolution and inscribed radius), the goal's
/// potential field over the whole map and the descent from its start — the same calls as the
/// search, so the same path. Returns the NavFn after the descent (costs, potential, path) and
/// the body check of the plan's poses against the static layer; `None` without a
/// counterexample.
pub fn replay_counterexample(
    map: &RosMap,
    report: &SearchReport,
    params: InflationParams,
    body: &Body,
) -> Result<Option<(NavFn, BodyReport)>, CostmapError> {
    let Some(cx) = &report.counterexample else { return Ok(None) };
    let (w, h, res) = (map.width, map.height, report.resolution);
    let k = (cx.inflation_radius / res).round();
    let radius = if k <= 0.0 { 0.0 } else { (k - 0.5) * res };
    let params = InflationParams { inflation_radius: radius, ..params };
    let layer = InflationLayer::new(params, res, report.inscribed_radius)?;
    let mut costs = map.costmap.clone();
    layer.inflate(&mut costs, w, h);
    let size_error = || CostmapError::Parameter { name: "map size", value: (w * h) as f64 };
    let mut nav = NavFn::new(w, h).map_err(|_| size_error())?;
    nav.set_costs_ros(&costs, true).map_err(|_| size_error())?;
    let cell = |c: [usize; 2]| Cell::new(c[0], c[1]);
    nav.set_goal(cell(cx.goal)).map_err(|_| size_error())?;
    nav.setup();
    nav.propagate_dijkstra(w * h * 4, false, &mut NoObserver);
    nav.set_start(cell(cx.start)).map_err(|_| size_error())?;
    nav.calc_path(4 * w.max(h), &mut NoObserver);
    let check = BodyCheck {
        costs: &map.costmap,
        width: w,
        height: h,
        world: map.world(),
        body: body.clone(),
        window: 0.0,
    };
    let body_report = check.check(&to_poses(map, nav.path()));
    Ok(Some((nav, body_report)))
}

fn interior(i: usize, w: usize, h: usize) -> bool {
    let (x, y) = (i % w, i / w);
    x > 0 && y > 0 && x + 1 < w && y + 1 < h
}

/// NavFn path points as world poses, each facing the next point (the last keeps the heading
/// before it), as nav2 orients a plan.
fn to_poses(map: &RosMap, path: &[[f32; 2]]) -> Vec<[f64; 3]> {
    let world = map.world();
    let pts: Vec<[f64; 2]> = path.iter().map(|p| world.navfn_to_world(*p)).collect();
    let mut yaw = 0.0;
    pts.iter()
        .enumerate()
        .map(|(i, p)| {
            if let Some(q) = pts.get(i + 1) {
                yaw = (q[1] - p[1]).atan2(q[0] - p[0]);
            }
            [p[0], p[1], yaw]
        })
        .collect()
}

/// Cells whose centre lies within the body's radius (plus the end margin) plus 2.5 cells of a
/// lethal cell's centre. A segment of at most √2 cells (NavFn's half-cell steps, a grid step,
/// the final step onto the goal) whose end cells are both outside stays farther than the body's
/// radius from every lethal square: a point of it is within √2/2 of an end, which is within
/// √2/2 of its cell's centre, and a lethal square's points are within √2/2 of its centre
/// (3·√2/2 < 2.5). Longer segments always get the exact test.
fn near_lethal(map: &RosMap, body: &Body, margin: f64, res: f64) -> Vec<bool> {
    let (w, h) = (map.width, map.height);
    let mut dist: Vec<f32> = map
        .costmap
        .iter()
        .map(|&c| if c == crate::costmap::LETHAL { 0.0 } else { f32::MAX })
        .collect();
    crate::costmap::inflation::distance_transform_2d(&mut dist, w, h);
    let limit = (body.circumscribed() + margin) / res + 2.5;
    // the square root above is approximate to a few ulps: a margin of 1e-3 cell covers it
    dist.iter().map(|&d| f64::from(d) <= limit + 1e-3).collect()
}

/// Cells where the robot can stand: the body's circumscribed disc grown by `margin`, at the
/// cell's world point (as nav2 places a NavFn cell: its corner), clears every lethal cell. A
/// start where the body already touches an obstacle says nothing about the plan, and one a
/// hair from it is touched by NavFn's first step along the wall, whatever the inflation.
fn body_fits(map: &RosMap, body: &Body, margin: f64, near: &[bool]) -> Vec<bool> {
    let disc = BodyCheck {
        costs: &map.costmap,
        width: map.width,
        height: map.height,
        world: map.world(),
        body: Body::Disc(body.circumscribed() + margin),
        window: 0.0,
    };
    let world = map.world();
    (0..map.width * map.height)
        .map(|i| {
            if !near[i] {
                return true;
            }
            let p = world.navfn_to_world([(i % map.width) as f32, (i / map.width) as f32]);
            disc.check(&[[p[0], p[1], 0.0]]).is_ok()
        })
        .collect()
}

fn touches_near(poses: &[[f64; 3]], map: &RosMap, near: &[bool]) -> bool {
    let world = map.world();
    let longest = std::f64::consts::SQRT_2 * world.resolution;
    let long_step =
        poses.windows(2).any(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]) > longest);
    long_step
        || poses.iter().any(|p| {
            world
                .costmap_world_to_map([p[0], p[1]], map.width, map.height)
                .is_none_or(|c| near[c.y * map.width + c.x])
        })
}

/// Merge shard reports of one search: the largest failing radius wins.
pub fn merge(reports: Vec<SearchReport>) -> Option<SearchReport> {
    let mut it = reports.into_iter();
    let mut acc = it.next()?;
    for r in it {
        acc.paths += r.paths;
        acc.radii_tried = acc.radii_tried.max(r.radii_tried);
        acc.shards.extend(r.shards);
        let worse = match (&acc.counterexample, &r.counterexample) {
            (None, Some(_)) => true,
            (Some(a), Some(b)) => b.inflation_radius > a.inflation_radius,
            _ => false,
        };
        if worse {
            acc.counterexample = r.counterexample;
            acc.smallest_safe_radius = r.smallest_safe_radius;
        }
    }
    acc.shards.sort();
    Some(acc)
}
