//! De-duplication of received frames, as mavlink-router's `DeduplicationPeriod`: a frame whose
//! bytes (header with sequence number, payload, checksum) were received within the period is
//! dropped, and seeing it again restarts its period. For parallel links that carry the same
//! frames. Bounded: at most [`MAX_TRACKED`] frames are remembered; when full and nothing has
//! expired, new frames pass unremembered.

use std::collections::HashMap;
use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::time::{Duration, Instant};

/// Most frames remembered at once.
pub const MAX_TRACKED: usize = 16 * 1024;

pub(super) struct Dedup {
    period: Duration,
    seen: HashMap<u64, Instant>,
    last_sweep: Instant,
}

impl Dedup {
    pub(super) fn new(period: Duration) -> Self {
        Dedup { period, seen: HashMap::new(), last_sweep: Instant::now() }
    }

    /// Whether `frame` is a copy of one received less than the period ago (then its period
    /// restarts).
    pub(super) fn is_duplicate(&mut self, frame: &[u8], now: Instant) -> bool {
        let mut h = DefaultHasher::new();
        frame.hash(&mut h);
        let key = h.finish();
        if now.duration_since(self.last_sweep) >= self.period || self.seen.len() >= MAX_TRACKED {
            let period = self.period;
            self.seen.retain(|_, t| now.duration_since(*t) < period);
            self.last_sweep = now;
        }
        match self.seen.get_mut(&key) {
            Some(t) => {
                let dup = now.duration_since(*t) < self.period;
                *t = now;
                dup
            }
            None => {
                if self.seen.len() < MAX_TRACKED {
                    self.seen.insert(key, now);
                }
                false
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn copies_within_the_period_are_duplicates_and_restart_it() {
        let mut d = Dedup::new(Duration::from_millis(100));
        let t0 = Instant::now();
        let ms = |n| t0 + Duration::from_millis(n);
        assert!(!d.is_duplicate(b"frame-a", ms(0)));
        assert!(!d.is_duplicate(b"frame-b", ms(1)));
        assert!(d.is_duplicate(b"frame-a", ms(50)));
        assert!(d.is_duplicate(b"frame-a", ms(140)), "the copy at 50 ms restarted the period");
        assert!(!d.is_duplicate(b"frame-a", ms(300)));
        assert!(!d.is_duplicate(b"frame-b", ms(301)), "expired");
    }

    #[test]
    fn memory_is_bounded() {
        let mut d = Dedup::new(Duration::from_secs(60));
        let t0 = Instant::now();
        for i in 0..(MAX_TRACKED + 100) as u32 {
            assert!(!d.is_duplicate(&i.to_le_bytes(), t0));
        }
        assert!(d.seen.len() <= MAX_TRACKED);
    }
}
