//! Oracles answer what the semantics cannot compute: the value of a C condition (the paper's
//! `evalc`) and of an integer expression (a `for` bound). Three kinds: a scripted sequence of
//! numbers (shared with the C driver), a seeded random one, and a callback.
//!
//! Number convention (same as `tests/stub/fp_stub.c`): a condition consumes one number and is
//! true iff it is odd; a value that is not a plain decimal literal consumes one number `n` and
//! is `n / 2` (truncated). An exhausted sequence answers 0.

/// What is being asked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Query<'a> {
    Cond(&'a str),
    Value(&'a str),
}

pub trait Oracle {
    fn cond(&mut self, text: &str) -> bool;
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
    pub fn parse(text: &str) -> Result<Self, String> {
        let numbers = text
            .split_whitespace()
            .map(|w| w.parse::<i64>().map_err(|_| format!("not an integer: '{w}'")))
            .collect::<Result<Vec<_>, _>>()?;
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

/// A small deterministic generator (SplitMix64), so sequences are reproducible from a seed on
/// every platform without a dependency.
#[derive(Debug, Clone)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    pub fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

/// A reproducible answer sequence: each number is odd (a true condition) with probability
/// `percent_true`/100, and carries a small magnitude 0..=7 for values (`n / 2` in -0..=7).
pub fn seeded_sequence(seed: u64, len: usize, percent_true: u64) -> Vec<i64> {
    let mut g = SplitMix64::new(seed);
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
    gen: SplitMix64,
    percent_true: u64,
}

impl Seeded {
    pub fn new(seed: u64, percent_true: u64) -> Self {
        Seeded { gen: SplitMix64::new(seed), percent_true }
    }
    fn next_number(&mut self) -> i64 {
        let r = self.gen.next_u64();
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

/// Answers through a closure (for model checkers and exhaustive exploration).
pub struct Callback<F: FnMut(Query<'_>) -> i64>(pub F);

impl<F: FnMut(Query<'_>) -> i64> Oracle for Callback<F> {
    fn cond(&mut self, text: &str) -> bool {
        (self.0)(Query::Cond(text)) != 0
    }
    fn value(&mut self, text: &str) -> i64 {
        literal_value(text).unwrap_or_else(|| (self.0)(Query::Value(text)))
    }
}
