//! Latency samples summarised as percentiles: the one place the bench computes them.

use serde::Serialize;

/// One-way latencies of one phase, microseconds: the median and the spread around it.
///
/// Two paths are compared by their spreads, not by a difference of medians: the medians of two
/// paths measured one after the other on a shared machine can differ by more than what a relay
/// adds (a burst of other load during one of them), and their difference can then come out
/// negative. Where the middle halves (25th–75th percentile) of two paths overlap, they differ
/// by less than the noise of the run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Latency {
    /// Messages that arrived and were timed.
    pub samples: usize,
    /// 25th percentile, µs.
    pub p25_us: f64,
    /// Median, µs.
    pub median_us: f64,
    /// 75th percentile, µs.
    pub p75_us: f64,
    /// 99th percentile, µs.
    pub p99_us: f64,
}

impl Default for Latency {
    fn default() -> Self {
        Latency::of(vec![])
    }
}

impl Latency {
    /// The percentiles of `samples` (nearest rank on the sorted samples; NaN when there are
    /// none, which JSON shows as `null`).
    pub fn of(mut samples: Vec<f64>) -> Latency {
        samples.sort_by(f64::total_cmp);
        let at = |p: f64| percentile(&samples, p);
        Latency {
            samples: samples.len(),
            p25_us: at(0.25),
            median_us: at(0.5),
            p75_us: at(0.75),
            p99_us: at(0.99),
        }
    }
}

/// The `p` quantile (0..=1) of sorted samples, nearest rank; NaN when there are none.
fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let rank = ((sorted.len() - 1) as f64 * p).round() as usize;
    sorted[rank.min(sorted.len() - 1)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_by_nearest_rank() {
        // 1..=101 shuffled: the p-quantile of 101 values is the value at rank 100·p.
        let v: Vec<f64> = (0..101).map(|i| f64::from((i * 37) % 101 + 1)).collect();
        let l = Latency::of(v);
        assert_eq!(l.samples, 101);
        assert_eq!((l.p25_us, l.median_us, l.p75_us, l.p99_us), (26.0, 51.0, 76.0, 100.0));
    }

    #[test]
    fn no_samples_give_no_figures() {
        let l = Latency::of(vec![]);
        assert_eq!(l.samples, 0);
        assert!(l.median_us.is_nan() && l.p99_us.is_nan());
        assert_eq!(serde_json::to_value(l).unwrap()["median_us"], serde_json::Value::Null);
    }

    #[test]
    fn one_sample_is_every_percentile() {
        let l = Latency::of(vec![4.5]);
        assert_eq!((l.p25_us, l.median_us, l.p75_us, l.p99_us), (4.5, 4.5, 4.5, 4.5));
    }
}
