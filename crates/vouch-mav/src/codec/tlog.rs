//! .tlog reader: records of an 8-byte big-endian UNIX timestamp (µs) followed by one raw frame.
//!
//! There is no record length, so after a broken record the reader resynchronises: it moves one
//! byte on and accepts a record again only where a plausible timestamp precedes a valid frame.

use super::frame::{CodecStats, Frame, Parse, is_magic, parse_frame};
use crate::dialect::Dialect;

/// One record of a tlog.
#[derive(Debug, Clone, Copy)]
pub struct TlogRecord<'a> {
    pub time_us: u64,
    /// Byte offset of the record (its timestamp) in the file.
    pub offset: usize,
    pub frame: Frame<'a>,
}

/// Iterator over the records of an in-memory tlog; counts what it had to skip.
pub struct TlogReader<'a> {
    data: &'a [u8],
    pos: usize,
    dialect: &'a Dialect,
    last_time: Option<u64>,
    stats: CodecStats,
    /// Records whose timestamp was implausible or whose frame was broken, skipped by resync.
    pub skipped_records: u64,
}

/// Timestamps between 2000-01-01 and 2100-01-01 in µs.
const MIN_TIME: u64 = 946_684_800_000_000;
const MAX_TIME: u64 = 4_102_444_800_000_000;
/// A jump larger than this (one day) between consecutive records is treated as a misread.
const MAX_JUMP_US: u64 = 86_400_000_000;

impl<'a> TlogReader<'a> {
    pub fn new(data: &'a [u8], dialect: &'a Dialect) -> Self {
        TlogReader {
            data,
            pos: 0,
            dialect,
            last_time: None,
            stats: CodecStats::default(),
            skipped_records: 0,
        }
    }

    /// What was counted so far.
    pub fn stats(&self) -> CodecStats {
        self.stats
    }

    fn plausible(&self, t: u64) -> bool {
        if !(MIN_TIME..MAX_TIME).contains(&t) {
            return false;
        }
        match self.last_time {
            Some(last) => t.abs_diff(last) < MAX_JUMP_US,
            None => true,
        }
    }

    fn time_at(&self, at: usize) -> Option<u64> {
        let b = self.data.get(at..at + 8)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Some(u64::from_be_bytes(a))
    }

    /// Whether a record could start at `at` (end of data counts as yes).
    fn record_starts_at(&self, at: usize) -> bool {
        if at >= self.data.len() {
            return true;
        }
        match (self.time_at(at), self.data.get(at + 8)) {
            (Some(t), Some(&m)) => self.plausible(t) && is_magic(m),
            _ => false,
        }
    }

    fn skip_byte(&mut self, resyncing: &mut bool) {
        if !*resyncing {
            self.skipped_records += 1;
            *resyncing = true;
        }
        self.stats.garbage_bytes += 1;
        self.pos += 1;
    }
}

impl<'a> Iterator for TlogReader<'a> {
    type Item = TlogRecord<'a>;

    fn next(&mut self) -> Option<TlogRecord<'a>> {
        let mut resyncing = false;
        loop {
            let rest = self.data.len().saturating_sub(self.pos);
            if rest == 0 {
                return None;
            }
            if rest < 9 {
                // A few trailing bytes cannot hold a record: a truncated tail.
                self.stats.truncated += 1;
                self.stats.garbage_bytes += rest as u64;
                self.pos = self.data.len();
                return None;
            }
            let time = self.time_at(self.pos).unwrap_or(0);
            if !self.plausible(time) {
                self.skip_byte(&mut resyncing);
                continue;
            }
            let frame_at = self.pos + 8;
            match parse_frame(&self.data[frame_at..], self.dialect, true) {
                Parse::Frame(f) => {
                    let end = frame_at + f.bytes.len();
                    if f.msg.is_none() && !self.record_starts_at(end) {
                        self.stats.unknown_id += 1;
                        self.skip_byte(&mut resyncing);
                        continue;
                    }
                    let rec = TlogRecord { time_us: time, offset: self.pos, frame: f };
                    self.stats.count(&f);
                    self.last_time = Some(time);
                    self.pos = end;
                    return Some(rec);
                }
                Parse::Incomplete if resyncing => self.skip_byte(&mut resyncing),
                Parse::Incomplete => {
                    self.stats.truncated += 1;
                    self.stats.garbage_bytes += (self.data.len() - self.pos) as u64;
                    self.pos = self.data.len();
                    return None;
                }
                Parse::Invalid(kind) => {
                    // A plausible timestamp followed by a frame start is a broken frame, also
                    // while resynchronising.
                    self.stats.reject(kind);
                    self.skip_byte(&mut resyncing);
                }
            }
        }
    }
}
