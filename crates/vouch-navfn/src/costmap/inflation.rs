//! nav2's `InflationLayer` (navigation2 `a3a97043ee93`), one full-map update.
//!
//! That version computes the exact Euclidean distance of every cell to the nearest obstacle
//! cell with the Felzenszwalb–Huttenlocher transform (squared distances in `f32`, columns then
//! rows, then `sqrtf`), and maps it to a cost through a table sampled 100 times per cell:
//! `cost(d) = 254` at d = 0, `253` while `d·resolution ≤ inscribed_radius`, else
//! `(unsigned char)(252 · exp(−k·(d·resolution − inscribed_radius)))` in double. A cell farther
//! than `ceil(inflation_radius / resolution)` cells keeps its value; a nearer one takes the
//! larger of its value and the cost, except an unknown cell (255), which takes the cost only
//! when it is inscribed or more (or any non-zero cost with `inflate_unknown`). Obstacles are
//! the lethal cells, and unknown ones too with `inflate_around_unknown`. Every float
//! operation, conversion and comparison below is the one the C++ performs.

use super::CostmapError;

/// Costmap2D values.
pub const FREE_SPACE: u8 = 0;
/// A cell within the inscribed radius of an obstacle.
pub const INSCRIBED: u8 = 253;
/// An obstacle.
pub const LETHAL: u8 = 254;
/// Unknown space.
pub const NO_INFORMATION: u8 = 255;

/// Samples of the cost table per cell of distance (nav2's `COST_LUT_PRECISION`).
pub const LUT_PRECISION: u32 = 100;

/// The inflation layer's parameters (nav2 names and defaults).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InflationParams {
    /// `inflation_radius` in metres (nav2 default 0.55).
    pub inflation_radius: f64,
    /// `cost_scaling_factor` (nav2 default 10.0).
    pub cost_scaling_factor: f64,
    /// `inflate_unknown`: unknown cells take any non-zero inflation cost.
    pub inflate_unknown: bool,
    /// `inflate_around_unknown`: unknown cells are obstacles for the distance transform.
    pub inflate_around_unknown: bool,
}

impl Default for InflationParams {
    fn default() -> Self {
        InflationParams {
            inflation_radius: 0.55,
            cost_scaling_factor: 10.0,
            inflate_unknown: false,
            inflate_around_unknown: false,
        }
    }
}

/// The layer with its cost table for one resolution and inscribed radius.
#[derive(Clone, Debug)]
pub struct InflationLayer {
    params: InflationParams,
    resolution: f64,
    inscribed_radius: f64,
    cell_inflation_radius: u32,
    lut: Vec<u8>,
}

impl InflationLayer {
    /// The layer for a costmap of `resolution` (metres per cell, as the costmap holds it: the
    /// map message's float widened) and a footprint's `inscribed_radius`.
    pub fn new(
        params: InflationParams,
        resolution: f64,
        inscribed_radius: f64,
    ) -> Result<Self, CostmapError> {
        for (name, value) in [
            ("inflation_radius", params.inflation_radius),
            ("cost_scaling_factor", params.cost_scaling_factor),
            ("resolution", resolution),
        ] {
            // nav2 refuses negative parameter updates; a huge radius would make the table huge
            if !value.is_finite() || value < 0.0 || (name == "resolution" && value == 0.0) {
                return Err(CostmapError::Parameter { name, value });
            }
        }
        let cells = (params.inflation_radius / resolution).ceil().max(0.0);
        if cells > f64::from(MAX_CELL_RADIUS) {
            return Err(CostmapError::Parameter {
                name: "inflation_radius",
                value: params.inflation_radius,
            });
        }
        let cell_inflation_radius = cells as u32;
        let mut layer = InflationLayer {
            params,
            resolution,
            inscribed_radius,
            cell_inflation_radius,
            lut: Vec::new(),
        };
        if cell_inflation_radius > 0 {
            let max_scaled = cell_inflation_radius * LUT_PRECISION + 1;
            layer.lut = (0..=max_scaled)
                .map(|d| layer.cost_at(f64::from(d) / f64::from(LUT_PRECISION)))
                .collect();
        }
        Ok(layer)
    }

    /// `ceil(inflation_radius / resolution)`: how far (in cells) costs are written.
    pub fn cell_inflation_radius(&self) -> u32 {
        self.cell_inflation_radius
    }

    /// The inscribed radius in use (metres).
    pub fn inscribed_radius(&self) -> f64 {
        self.inscribed_radius
    }

    /// The parameters.
    pub fn params(&self) -> InflationParams {
        self.params
    }

    /// The cost of a cell `distance` cells from the nearest obstacle (nav2's `computeCost`).
    pub fn cost_at(&self, distance: f64) -> u8 {
        if distance == 0.0 {
            LETHAL
        } else if distance * self.resolution <= self.inscribed_radius {
            INSCRIBED
        } else {
            // `-1.0 * k` in the C++: a sign flip, exact
            let factor = (-self.params.cost_scaling_factor
                * (distance * self.resolution - self.inscribed_radius))
                .exp();
            // C's double → unsigned char: truncation; the value is in [0, 252]
            (f64::from(INSCRIBED - 1) * factor) as u8
        }
    }

    /// Inflate a whole costmap in place (`width × height`, row-major, Costmap2D values).
    pub fn inflate(&self, costmap: &mut [u8], width: usize, height: usize) {
        if self.cell_inflation_radius == 0 || costmap.len() != width * height {
            return;
        }
        let around_unknown = self.params.inflate_around_unknown;
        let mut dist: Vec<f32> = costmap
            .iter()
            .map(|&c| {
                let obstacle = c == LETHAL || (around_unknown && c == NO_INFORMATION);
                if obstacle { 0.0 } else { f32::MAX }
            })
            .collect();
        squared_distances(&mut dist, width, height, true);
        eigen_sqrt(&mut dist);
        self.apply(costmap, &dist);
    }

    fn apply(&self, costmap: &mut [u8], dist: &[f32]) {
        let radius = self.cell_inflation_radius as f32;
        let lut_max = (self.lut.len() - 1) as u32;
        let inflate_unknown = self.params.inflate_unknown;
        for (cell, &d) in costmap.iter_mut().zip(dist) {
            if d > radius {
                continue;
            }
            // float product and sum, then C's float → unsigned conversion (truncation)
            let scaled = (d * LUT_PRECISION as f32 + 0.5f32) as u32;
            let cost = self.lut[scaled.min(lut_max) as usize];
            let old = *cell;
            let takes = if inflate_unknown { cost > FREE_SPACE } else { cost >= INSCRIBED };
            *cell = if old == NO_INFORMATION && takes { cost } else { old.max(cost) };
        }
    }
}

/// Largest `ceil(inflation_radius / resolution)` accepted: the cost table has 100 entries per
/// cell (6.5 MB here), and 2^16 cells is 3.3 km at 5 cm, beyond any inflation radius in use.
pub const MAX_CELL_RADIUS: u32 = 1 << 16;

/// Columns transformed together in the generic column pass (one 64-byte cache line of floats).
const COLUMN_BLOCK: usize = 16;

/// Tallest column for which [`column_pass_binary`] is exact (see there): below it every
/// `q² − v²` of the transform is an integer that `f32` holds exactly.
const EXACT_BINARY_HEIGHT: usize = 4096;

/// Euclidean distance transform in place: input 0 at obstacles and `f32::MAX` elsewhere,
/// output the distance in cells (`f32::MAX`-ish where no obstacle exists). The bytes are
/// nav2's: the column pass, then the row pass, then Eigen's square root.
pub fn distance_transform_2d(img: &mut [f32], width: usize, height: usize) {
    // (a fold without early exit, so that the test vectorises)
    let binary = img.iter().fold(true, |all, &x| all & ((x == 0.0) | (x == f32::MAX)));
    squared_distances(img, width, height, binary);
    eigen_sqrt(img);
}

/// The two passes of the transform (squared distances); `binary`: the input holds only 0 and
/// `f32::MAX`.
fn squared_distances(img: &mut [f32], width: usize, height: usize, binary: bool) {
    if img.len() != width * height || width == 0 {
        return;
    }
    if binary && height <= EXACT_BINARY_HEIGHT {
        column_pass_binary(img, width);
    } else {
        column_pass(img, width, height);
    }
    let mut d = vec![0f32; width];
    let mut sites = vec![Site::default(); width];
    let mut z = vec![0f32; width + 1];
    for row in img.chunks_exact_mut(width) {
        transform_1d(row, &mut d, &mut sites, &mut z);
        row.copy_from_slice(&d);
    }
}

/// The column pass as nav2 computes it, one column's transform after another. The columns
/// are read a block at a time: a block's cells of one row are one cache line, copied into a
/// column-major scratch block, transformed and copied back (reading one column at a time
/// touches a cache line per cell and a new page every few rows on a large map).
fn column_pass(img: &mut [f32], width: usize, height: usize) {
    let mut d = vec![0f32; height];
    let mut sites = vec![Site::default(); height];
    let mut z = vec![0f32; height + 1];
    let mut block = vec![0f32; COLUMN_BLOCK * height];
    for x0 in (0..width).step_by(COLUMN_BLOCK) {
        let cols = COLUMN_BLOCK.min(width - x0);
        for (y, row) in img.chunks_exact(width).enumerate() {
            for (j, &value) in row[x0..x0 + cols].iter().enumerate() {
                block[j * height + y] = value;
            }
        }
        for column in block.chunks_exact_mut(height).take(cols) {
            transform_1d(column, &mut d, &mut sites, &mut z);
            column.copy_from_slice(&d);
        }
        for (y, row) in img.chunks_exact_mut(width).enumerate() {
            for (j, value) in row[x0..x0 + cols].iter_mut().enumerate() {
                *value = block[j * height + y];
            }
        }
    }
}

/// The column pass for a binary input (0 at obstacles, `f32::MAX` elsewhere) of at most
/// [`EXACT_BINARY_HEIGHT`] rows, with the same result bit for bit: each cell gets the squared
/// row distance to the nearest obstacle of its column, `f32::MAX` in a column without one.
/// Computed as two sweeps over the rows (nearest obstacle above, then below), which run
/// along memory and vectorise, instead of a transform per column.
///
/// Why the transform gives exactly that on such input. Every `q² − v²` is an integer below
/// 2^24, so held exactly. Between two obstacle sites `a < b` the envelope boundary
/// `(b² − a²) / (2(b − a))` is the midpoint `(a + b)/2`, exactly (a multiple of ½, and the
/// division rounds correctly); between two free sites likewise. Between a free and an
/// obstacle site, `f` differs by `f32::MAX`, which absorbs the integer part (its ulp is
/// 2^104), so the boundary is `±f32::MAX / (2(q − v))`, beyond ±4·10^34: outside the column.
/// A free site therefore never wins a cell while the column has an obstacle, the boundaries
/// between obstacles are the exact midpoints, and each cell takes `(q − v)² + 0` for a
/// nearest obstacle `v` (at a tie either one: same value). Without an obstacle every cell
/// takes its own site, `0 + f32::MAX`. Tested against the transform on random and edge
/// columns below.
fn column_pass_binary(img: &mut [f32], width: usize) {
    // rows are below 4096, so `i32` rows and `f32` squares are exact; -1: no obstacle yet
    let square = |from: i32, to: i32| {
        let d = (to - from) as f32;
        if from < 0 { f32::MAX } else { d * d }
    };
    // down the rows: the squared distance to the nearest obstacle at or above
    let mut last = vec![-1i32; width];
    for (y, row) in img.chunks_exact_mut(width).enumerate() {
        let y = y as i32;
        for (cell, last) in row.iter_mut().zip(last.iter_mut()) {
            *last = if *cell == 0.0 { y } else { *last };
            *cell = square(*last, y);
        }
    }
    // up the rows: the nearer of that and the nearest obstacle at or below (the obstacles
    // still read 0.0)
    last.fill(-1);
    for (y, row) in img.chunks_exact_mut(width).enumerate().rev() {
        let y = y as i32;
        for (cell, next) in row.iter_mut().zip(last.iter_mut()) {
            *next = if *cell == 0.0 { y } else { *next };
            *cell = cell.min(square(*next, y));
        }
    }
}

/// The square root nav2's layer takes: Eigen 3.4's `cwiseSqrt` on a float array, which (with
/// its default `EIGEN_FAST_MATH` on SSE) does four elements at a time as `rsqrtps` and one
/// Newton step, `x · r·((−x/2)·r² + 1.5)`, zero below `FLT_MIN`, and `sqrtf` for the last
/// `len % 4` elements (the array is 16-byte aligned, so packets start at element 0). The
/// approximation is not correctly rounded (√49 = 7.00000048 on the machine of the goldens)
/// and `rsqrtps` is the CPU's own table, so nav2's bytes are those of the CPU it runs on; so
/// are ours, through the same instruction.
pub fn eigen_sqrt(img: &mut [f32]) {
    let packets = img.len() / 4 * 4;
    let (head, tail) = img.split_at_mut(packets);
    for chunk in head.chunks_exact_mut(4) {
        let r = rsqrt4([chunk[0], chunk[1], chunk[2], chunk[3]]);
        for (x, r) in chunk.iter_mut().zip(r) {
            let refined = r * ((*x * -0.5f32) * (r * r) + 1.5f32);
            let denormal = *x < f32::MIN_POSITIVE && *x >= 0.0;
            *x = if denormal { 0.0 } else { *x * refined };
        }
    }
    for x in tail {
        *x = x.sqrt();
    }
}

/// `rsqrtps` on four floats.
#[cfg(target_arch = "x86_64")]
fn rsqrt4(x: [f32; 4]) -> [f32; 4] {
    safe_arch::reciprocal_sqrt_m128(safe_arch::m128::from_array(x)).to_array()
}

/// Without SSE the reciprocal square root is exact (nav2 there uses no `rsqrtps` either; its
/// NEON path differs and is not reproduced).
#[cfg(not(target_arch = "x86_64"))]
fn rsqrt4(x: [f32; 4]) -> [f32; 4] {
    x.map(|v| 1.0 / v.sqrt())
}

/// A parabola of the lower envelope: its site `v`, `v²` as the C++'s `int` product, and `f[v]`
/// (kept with the site so that an envelope step does not wait on a load through `v`).
#[derive(Clone, Copy, Default)]
struct Site {
    v: i32,
    square: i32,
    f: f32,
}

/// The lower envelope of parabolas in one dimension, squared distances in `f32`; the integer
/// part `q² − v²` in `i32` as the C++ computes it. `d` and `sites` hold at least `f.len()`
/// elements and `z` one more.
///
/// Same operations and order as nav2's; the envelope's end marker `z[k+1] = ∞` is written
/// once after the envelope is built instead of at every site: the envelope loop reads `z`
/// only at indices up to `k`, which it has written itself, so only the last marker is read.
fn transform_1d(f: &[f32], d: &mut [f32], sites: &mut [Site], z: &mut [f32]) {
    let n = f.len();
    if n == 0 || d.len() < n || sites.len() < n || z.len() <= n {
        return;
    }
    let (d, sites, z) = (&mut d[..n], &mut sites[..n], &mut z[..=n]);
    let inf = f32::MAX;
    let parabola = |q: i32, fq: f32, qq: i32, site: Site| {
        (fq - site.f + qq.wrapping_sub(site.square) as f32) / (2.0f32 * (q - site.v) as f32)
    };
    let mut k = 0usize;
    sites[0] = Site { v: 0, square: 0, f: f[0] };
    z[0] = -inf;
    for (q, &fq) in f.iter().enumerate().skip(1) {
        let q = q as i32;
        let qq = q.wrapping_mul(q);
        let mut s = parabola(q, fq, qq, sites[k]);
        // s > −FLT_MAX always (f ≥ 0), so k never passes 0; the guard keeps that visible
        while k > 0 && s <= z[k] {
            k -= 1;
            s = parabola(q, fq, qq, sites[k]);
        }
        k += 1;
        sites[k] = Site { v: q, square: qq, f: fq };
        z[k] = s;
    }
    z[k + 1] = inf;
    k = 0;
    for (q, out) in d.iter_mut().enumerate() {
        while z[k + 1] < q as f32 {
            k += 1;
        }
        let site = sites[k];
        let diff = q as i32 - site.v;
        *out = diff.wrapping_mul(diff) as f32 + site.f;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute-force Euclidean distance in cells, for comparison on small grids.
    fn brute(obst: &[bool], w: usize, h: usize) -> Vec<f64> {
        (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f64, (i / w) as f64);
                obst.iter()
                    .enumerate()
                    .filter(|(_, o)| **o)
                    .map(|(j, _)| ((j % w) as f64 - x).hypot((j / w) as f64 - y))
                    .fold(f64::INFINITY, f64::min)
            })
            .collect()
    }

    #[test]
    fn distance_transform_matches_brute_force() {
        let (w, h) = (13, 9);
        let obst: Vec<bool> = (0..w * h).map(|i| (i * 7919) % 23 == 0).collect();
        let mut img: Vec<f32> = obst.iter().map(|&o| if o { 0.0 } else { f32::MAX }).collect();
        distance_transform_2d(&mut img, w, h);
        for (a, b) in img.iter().zip(brute(&obst, w, h)) {
            assert!((f64::from(*a) - b).abs() < 1e-5, "{a} vs {b}");
        }
    }

    /// The two sweeps of the binary column pass give the transform's bytes: columns with no,
    /// one and many obstacles, obstacles at both ends, ties between two obstacles, and the
    /// tallest exact column, against nav2's per-column transform (`column_pass`).
    #[test]
    fn binary_column_pass_is_the_transform() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        for (w, h, per_mille) in
            [(1, 1, 500), (7, 1, 500), (5, 9, 0), (13, 17, 1000), (31, 64, 120), (9, 4096, 3)]
        {
            for _ in 0..4 {
                let img: Vec<f32> = (0..w * h)
                    .map(|_| if next() % 1000 < per_mille { 0.0 } else { f32::MAX })
                    .collect();
                let mut expected = img.clone();
                column_pass(&mut expected, w, h);
                let mut got = img.clone();
                column_pass_binary(&mut got, w);
                let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&got), bits(&expected), "{w}x{h} at {per_mille}‰");
            }
        }
        // obstacles at both ends of a column, and two equidistant from its middle cell
        let mut img = vec![f32::MAX; 9];
        (img[0], img[8], img[2], img[6]) = (0.0, 0.0, 0.0, 0.0);
        let mut expected = img.clone();
        column_pass(&mut expected, 1, 9);
        column_pass_binary(&mut img, 1);
        assert_eq!(img, expected);
        assert_eq!(img, [0.0, 1.0, 0.0, 1.0, 4.0, 1.0, 0.0, 1.0, 0.0]);
    }

    #[test]
    fn cost_formula_edges() {
        let p = InflationParams {
            inflation_radius: 0.55,
            cost_scaling_factor: 3.0,
            ..Default::default()
        };
        let l = InflationLayer::new(p, 0.05, 0.22).unwrap();
        assert_eq!(l.cell_inflation_radius(), 11);
        assert_eq!(l.cost_at(0.0), LETHAL);
        assert_eq!(l.cost_at(4.0), INSCRIBED); // 0.2 m ≤ 0.22 m
        // 0.25 m: 252·exp(−3·0.03) = 230.3…
        assert_eq!(l.cost_at(5.0), 230);
    }
}
