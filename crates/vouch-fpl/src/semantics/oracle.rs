//! Oracles answer what the semantics cannot compute: the value of a C condition (the paper's
//! `evalc`) and of an integer expression (a `for` bound): a scripted sequence of numbers (shared
//! with the C driver) or a seeded random one.
//!
//! Number convention (same as `tests/stub/fp_stub.c`): a condition consumes one number and is
//! true iff it is odd; a value that is not a plain decimal literal consumes one number `n` and
//! is `n / 2` (truncated). An exhausted sequence answers 0.
//!
//! Seeded answers come from SplitMix64 (`rand_xoshiro`), seeded with the seed itself: a pinned
//! algorithm, so a seed printed by `vouch fpl validate` replays the same answers on every
//! platform and release.

use rand_core::{Rng, SeedableRng};
use rand_xoshiro::SplitMix64;

/// Answers the questions of one run.
pub trait Oracle {
    /// The value of the C condition `text`.
    fn cond(&mut self, text: &str) -> bool;
    /// The value of the integer expression `text`.
    fn value(&mut self, text: &str) -> i64;
}

/// A plain decimal literal (optionally negative) is its own value, as in the C stub.
pub fn literal_value(text: &str) -> Option<i64> {
    let first = text.chars().next()?;
    if first != '-' && !first.is_ascii_digit() {
        return None;
    }
    text.parse::<i64>().ok()
}

/// An answer file with something that is not an integer.
#[derive(Debug, Clone, thiserror::Error, miette::Diagnostic)]
#[error("not an integer: '{word}'")]
#[diagnostic(
    code(fpl::E041),
    help(
        "answers are whitespace-separated integers: a condition is true when its number is odd, a value is the number / 2"
    )
)]
pub struct AnswerError {
    /// The offending word, as quoted (escaped, cut at 40 characters).
    pub word: String,
    /// The whole answer text.
    #[source_code]
    pub text: String,
    /// Where the word is.
    #[label("here")]
    pub at: miette::SourceSpan,
}

/// Answers from a fixed sequence of numbers.
#[derive(Debug, Clone, Default)]
pub struct Scripted {
    numbers: Vec<i64>,
    next: usize,
}

impl Scripted {
    pub fn new(numbers: Vec<i64>) -> Self {
        Scripted { numbers, next: 0 }
    }
    /// Parses whitespace-separated integers (the C driver's answer-file format).
    pub fn parse(text: &str) -> Result<Self, AnswerError> {
        let mut numbers = Vec::new();
        let mut rest = text;
        while let Some(start) = rest.find(|c: char| !c.is_whitespace()) {
            let word = &rest[start..];
            let len = word.find(char::is_whitespace).unwrap_or(word.len());
            let word = &word[..len];
            let offset = text.len() - rest.len() + start;
            match word.parse::<i64>() {
                Ok(n) => numbers.push(n),
                Err(_) => {
                    return Err(AnswerError {
                        word: crate::diag::quote(word),
                        text: text.to_string(),
                        at: (offset, len).into(),
                    });
                }
            }
            rest = &rest[start + len..];
        }
        Ok(Scripted::new(numbers))
    }
    fn next_number(&mut self) -> i64 {
        let v = self.numbers.get(self.next).copied().unwrap_or(0);
        self.next += 1;
        v
    }
    /// How many numbers were consumed so far.
    pub fn consumed(&self) -> usize {
        self.next
    }
}

impl Oracle for Scripted {
    fn cond(&mut self, _text: &str) -> bool {
        self.next_number() & 1 != 0
    }
    fn value(&mut self, text: &str) -> i64 {
        literal_value(text).unwrap_or_else(|| self.next_number() / 2)
    }
}

/// A reproducible answer sequence: each number is odd (a true condition) with probability
/// `percent_true`/100, and carries a small magnitude 0..=7 for values (`n / 2` in -0..=7).
pub fn seeded_sequence(seed: u64, len: usize, percent_true: u64) -> Vec<i64> {
    let mut g = SplitMix64::seed_from_u64(seed);
    (0..len)
        .map(|_| {
            let r = g.next_u64();
            let odd = (r % 100) < percent_true;
            let magnitude = ((r >> 32) % 8) as i64;
            magnitude * 2 + i64::from(odd)
        })
        .collect()
}

/// Seeded random answers (an endless [`Scripted`] stream).
#[derive(Debug, Clone)]
pub struct Seeded {
    rng: SplitMix64,
    percent_true: u64,
}

impl Seeded {
    pub fn new(seed: u64, percent_true: u64) -> Self {
        Seeded { rng: SplitMix64::seed_from_u64(seed), percent_true }
    }
    fn next_number(&mut self) -> i64 {
        let r = self.rng.next_u64();
        let odd = (r % 100) < self.percent_true;
        (((r >> 32) % 8) as i64) * 2 + i64::from(odd)
    }
}

impl Oracle for Seeded {
    fn cond(&mut self, _text: &str) -> bool {
        self.next_number() & 1 != 0
    }
    fn value(&mut self, text: &str) -> i64 {
        literal_value(text).unwrap_or_else(|| self.next_number() / 2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seeded_answers_are_pinned() {
        // SplitMix64 of seed 0, first outputs (Steele, Lea and Flood's published values):
        // 0xe220a8397b1dcdaf, 0x6e789e6aa1b965f4, 0x06c45d188009454f.
        let mut g = SplitMix64::seed_from_u64(0);
        assert_eq!(g.next_u64(), 0xe220_a839_7b1d_cdaf);
        assert_eq!(g.next_u64(), 0x6e78_9e6a_a1b9_65f4);
        assert_eq!(g.next_u64(), 0x06c4_5d18_8009_454f);
        // The answer convention on top: odd with probability percent/100, magnitude 0..=7.
        let seq = seeded_sequence(7, 1000, 30);
        let odd = seq.iter().filter(|n| *n & 1 == 1).count();
        assert!((250..350).contains(&odd), "{odd}");
        assert!(seq.iter().all(|n| (0..16).contains(n)));
        assert_eq!(seeded_sequence(7, 20, 30), seeded_sequence(7, 20, 30));
    }
}
