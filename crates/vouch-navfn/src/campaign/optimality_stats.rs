//! Optimality statistics of a campaign category: NavFn's path costs against the 8-connected
//! optimum (`optimal.rs`), summed as integers in millionths and binned by ratio, so that shard
//! reports merge exactly in any order; with the path-shape counts the paper reports.

use serde::{Deserialize, Serialize};

/// Histogram bins of the optimality ratio `navfn_cost / optimal_cost`.
pub const RATIO_BINS: [f64; 9] = [0.95, 1.0, 1.01, 1.05, 1.0825, 1.10, 1.25, 1.5, 2.0];

/// A non-negative cost in millionths (rounded to nearest).
fn micros(cost: f64) -> u128 {
    (cost.max(0.0) * 1e6).round() as u128
}

/// Optimality statistics over cases where NavFn found a path and start ≠ goal.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct OptimalityStats {
    /// Paths compared with the optimum.
    pub compared: u64,
    /// Sum of NavFn path costs (campaign model), in millionths of a cost unit (each path's
    /// cost rounded once): an integer, so that sums merge exactly in any order.
    pub navfn_cost_micros: u128,
    /// Sum of the optimal costs, in millionths.
    pub optimal_cost_micros: u128,
    /// Largest `navfn − optimal` (the smallest is 0 up to summation order: see `optimal.rs`).
    pub excess_max: f64,
    /// Smallest `navfn − optimal`.
    pub excess_min: f64,
    /// Largest `navfn / optimal`.
    pub ratio_max: f64,
    /// Counts of ratios below each of [`RATIO_BINS`], plus one more for "≥ last".
    pub ratio_hist: Vec<u64>,
    /// Paths with at least one turn sharper than 90° (oscillating paths excluded, as in the paper).
    pub obtuse_paths: u64,
    /// Paths in which NavFn's oscillation test fired (recorded points, found or not).
    pub oscillating_paths: u64,
    /// Found paths that are counterexamples to optimality (ratio above the threshold).
    pub suboptimal_paths: u64,
}

impl OptimalityStats {
    /// Aggregate excess of NavFn over the optimum, percent (0 when nothing was compared).
    pub fn excess_percent(&self) -> f64 {
        if self.optimal_cost_micros == 0 {
            return 0.0;
        }
        100.0 * (self.navfn_cost_micros as f64 / self.optimal_cost_micros as f64 - 1.0)
    }

    /// Counts one compared path.
    pub fn record(&mut self, navfn: f64, optimal: f64) {
        if self.ratio_hist.is_empty() {
            self.ratio_hist = vec![0; RATIO_BINS.len() + 1];
            self.excess_min = f64::INFINITY;
        }
        self.compared += 1;
        self.navfn_cost_micros += micros(navfn);
        self.optimal_cost_micros += micros(optimal);
        let excess = navfn - optimal;
        self.excess_max = self.excess_max.max(excess);
        self.excess_min = self.excess_min.min(excess);
        let ratio = if optimal > 0.0 { navfn / optimal } else { 1.0 };
        // both costs are sums over cell paths in one metric and `navfn ≥ optimal` holds; a ratio
        // a few ulps below 1 is the same cost summed in another order
        let ratio = if ratio < 1.0 && ratio > 1.0 - 1e-9 { 1.0 } else { ratio };
        self.ratio_max = self.ratio_max.max(ratio);
        let bin = RATIO_BINS.iter().position(|&b| ratio < b).unwrap_or(RATIO_BINS.len());
        self.ratio_hist[bin] += 1;
    }

    pub(crate) fn merge(&mut self, o: &OptimalityStats) {
        if o.compared > 0 {
            if self.ratio_hist.is_empty() {
                self.ratio_hist = vec![0; RATIO_BINS.len() + 1];
                self.excess_min = f64::INFINITY;
            }
            for (a, b) in self.ratio_hist.iter_mut().zip(&o.ratio_hist) {
                *a = a.saturating_add(*b);
            }
            self.excess_max = self.excess_max.max(o.excess_max);
            self.excess_min = self.excess_min.min(o.excess_min);
            self.ratio_max = self.ratio_max.max(o.ratio_max);
        }
        self.compared = self.compared.saturating_add(o.compared);
        self.navfn_cost_micros = self.navfn_cost_micros.saturating_add(o.navfn_cost_micros);
        self.optimal_cost_micros = self.optimal_cost_micros.saturating_add(o.optimal_cost_micros);
        self.obtuse_paths = self.obtuse_paths.saturating_add(o.obtuse_paths);
        self.oscillating_paths = self.oscillating_paths.saturating_add(o.oscillating_paths);
        self.suboptimal_paths = self.suboptimal_paths.saturating_add(o.suboptimal_paths);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn optimality_sums_are_exact_integers() {
        let mut a = OptimalityStats::default();
        a.record(0.1, 0.1);
        a.record(0.2, 0.1);
        assert_eq!((a.navfn_cost_micros, a.optimal_cost_micros), (300_000, 200_000));
        assert!((a.excess_percent() - 50.0).abs() < 1e-12);
        let json = serde_json::to_string(&a).expect("json");
        let back: OptimalityStats = serde_json::from_str(&json).expect("reads back");
        assert_eq!(back, a);
        let big = OptimalityStats { navfn_cost_micros: u128::from(u64::MAX) * 7, ..a };
        let back: OptimalityStats =
            serde_json::from_str(&serde_json::to_string(&big).expect("json")).expect("u128");
        assert_eq!(back.navfn_cost_micros, u128::from(u64::MAX) * 7);
    }
}
