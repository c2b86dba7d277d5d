//! The few numeric primitives whose C/x86-64 behaviour must be reproduced exactly
//! (SEMANTICS.md §7). Kept in one place so every rounding decision is visible.

/// glibc `hypotf(a, b)`: the exact double sum of squares, one double square root, one
/// rounding to float. Squares of floats are exact in double, so only the sum, the root and
/// the final narrowing round; this matched glibc on 4·10⁷ random pairs (SEMANTICS.md §7).
#[inline(always)]
pub fn hypotf(a: f32, b: f32) -> f32 {
    let a = a as f64;
    let b = b as f64;
    (a * a + b * b).sqrt() as f32
}

/// The A* heuristic `f32(hypot(f64(dx), f64(dy)) * 50.0)` of `navfn.cpp`.
///
/// For |dx|, |dy| ≤ 4096 the exact integer sum of squares and one `sqrt` give the same float
/// as glibc's double `hypot` after `* 50.0` and rounding (checked exhaustively upstream of this
/// project, SEMANTICS.md §7); beyond that we call the platform `hypot` (glibc on Linux).
#[inline(always)]
pub fn astar_heuristic(dx: i64, dy: i64) -> f32 {
    if dx.abs() <= 4096 && dy.abs() <= 4096 {
        (((dx * dx + dy * dy) as f64).sqrt() * 50.0) as f32
    } else {
        ((dx as f64).hypot(dy as f64) * 50.0) as f32
    }
}

/// C's `int(f)` for a potential on x86-64 (`cvttss2si`): truncation toward zero, and the
/// "integer indefinite" value `INT_MIN` when the float does not fit. Rust's `as i32` saturates
/// to `INT_MAX` instead, which would change grid following on unreached start cells.
#[inline(always)]
pub fn c_float_to_int(f: f32) -> i32 {
    if (-2147483648.0..2147483648.0).contains(&f) { f as i32 } else { i32::MIN }
}

/// `int(roundf(v))` (half away from zero) for the small offsets of path extraction
/// (|v| < 2^31). Written out because `f32::round` is a libm call on baseline x86-64.
#[inline(always)]
pub fn round_half_away(v: f32) -> i64 {
    let t = v as i64; // truncation toward zero
    let frac = v - t as f32; // exact for |v| < 2^23
    if frac >= 0.5 {
        t + 1
    } else if frac <= -0.5 {
        t - 1
    } else {
        t
    }
}

/// FNV-1a 64-bit offset basis (also the hash of an empty byte stream).
pub const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
const FNV_PRIME: u64 = 0x0000_0100_0000_01b3;

/// FNV-1a-64 over a byte stream, incrementally.
#[derive(Clone, Copy, Debug)]
pub struct Fnv1a(pub u64);

impl Default for Fnv1a {
    fn default() -> Self {
        Fnv1a(FNV_OFFSET)
    }
}

impl Fnv1a {
    #[inline(always)]
    pub fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ b as u64).wrapping_mul(FNV_PRIME);
        }
    }
    #[inline(always)]
    pub fn f32(&mut self, v: f32) {
        self.bytes(&v.to_bits().to_le_bytes());
    }
}

/// `pot_fnv`: FNV-1a-64 of the potential array as little-endian float32 bytes.
///
/// Byte-wise FNV is a serial chain of multiplications (16 per cell). Unreached cells all hold
/// [`POT_HIGH_BITS`], and runs of them are hashed in O(log run) steps with [`HIGH_RUN_JUMPS`]
/// (same result as [`potential_fnv_bytewise`], tested).
pub fn potential_fnv(pot: &[f32]) -> u64 {
    let mut h = FNV_OFFSET;
    let mut i = 0;
    while i < pot.len() {
        let bits = pot[i].to_bits();
        if bits != POT_HIGH_BITS {
            h = fnv_word(h, bits);
            i += 1;
            continue;
        }
        let run = pot[i..].iter().take_while(|p| p.to_bits() == POT_HIGH_BITS).count();
        h = skip_high_run(h, run);
        i += run;
    }
    h
}

/// The plain definition of `pot_fnv` (reference for [`potential_fnv`]).
pub fn potential_fnv_bytewise(pot: &[f32]) -> u64 {
    let mut h = Fnv1a::default();
    for &p in pot {
        h.f32(p);
    }
    h.0
}

/// Bits of the unreached potential 1e10 (`0x501502f9`).
pub const POT_HIGH_BITS: u32 = 0x5015_02f9;

/// One FNV-1a step per byte of `w`, little-endian.
#[inline(always)]
fn fnv_word(mut h: u64, w: u32) -> u64 {
    for b in w.to_le_bytes() {
        h = (h ^ b as u64).wrapping_mul(FNV_PRIME);
    }
    h
}

/// Why runs can be skipped: `h ^ b = h + δ` with `δ = (s ^ b) − s`, `s` = the low byte of `h`,
/// so one step is `h·P + δ·P`, and the next low byte `((s ^ b)·P) mod 256` depends on `s`
/// alone. Hashing `n` copies of one word therefore maps `h` to `h·Pⁿ' + A(s)` (`n' = 4n`, `A`
/// depending only on the low byte `s`). `HIGH_RUN_JUMPS[j]` holds, for runs of `2^j` unreached
/// cells, the multiplier and the 256 addends; a run is the composition of the jumps of the set
/// bits of its length.
pub struct RunJump {
    mul: u64,
    add: [u64; 256],
}

const JUMP_LEVELS: usize = 32;

/// Jumps over `2^j` unreached cells, `j < 32` (see [`RunJump`]).
pub static HIGH_RUN_JUMPS: [RunJump; JUMP_LEVELS] = build_jumps();

const fn build_jumps() -> [RunJump; JUMP_LEVELS] {
    let mut t = [const { RunJump { mul: 0, add: [0; 256] } }; JUMP_LEVELS];
    // level 0: one word, bytes applied to h = s (the high bits contribute h·P⁴ only)
    let bytes = POT_HIGH_BITS.to_le_bytes();
    let mut mul = 1u64;
    let mut k = 0;
    while k < 4 {
        mul = mul.wrapping_mul(FNV_PRIME);
        k += 1;
    }
    t[0].mul = mul;
    let mut s = 0;
    while s < 256 {
        let mut h = s as u64;
        let mut k = 0;
        while k < 4 {
            h = (h ^ bytes[k] as u64).wrapping_mul(FNV_PRIME);
            k += 1;
        }
        // h = s·P⁴ + A(s)
        t[0].add[s] = h.wrapping_sub((s as u64).wrapping_mul(mul));
        s += 1;
    }
    // level j+1: two jumps of level j; the second one's low byte is that of the first result
    let mut j = 0;
    while j + 1 < JUMP_LEVELS {
        let m = t[j].mul;
        t[j + 1].mul = m.wrapping_mul(m);
        let mut s = 0;
        while s < 256 {
            let a = t[j].add[s];
            let first = (s as u64).wrapping_mul(m).wrapping_add(a);
            let s2 = (first & 0xff) as usize;
            t[j + 1].add[s] = a.wrapping_mul(m).wrapping_add(t[j].add[s2]);
            s += 1;
        }
        j += 1;
    }
    t
}

/// FNV-1a state after `run` more unreached cells.
#[inline]
fn skip_high_run(mut h: u64, run: usize) -> u64 {
    let mut j = 0;
    let mut r = run;
    while r != 0 {
        if r & 1 == 1 {
            let jump = &HIGH_RUN_JUMPS[j];
            h = h.wrapping_mul(jump.mul).wrapping_add(jump.add[(h & 0xff) as usize]);
        }
        r >>= 1;
        j += 1;
    }
    h
}

/// `path_fnv`: FNV-1a-64 of the path, x then y of each point, little-endian float32 bytes.
pub fn path_fnv(path: &[[f32; 2]]) -> u64 {
    let mut h = Fnv1a::default();
    for p in path {
        h.f32(p[0]);
        h.f32(p[1]);
    }
    h.0
}

/// `n / d` and `n % d` for the map width, by a multiplication (Lemire, Kaser, Kurz 2019:
/// `M = ⌊(2^64−1)/d⌋ + 1`, quotient = high 64 bits of `M·n`, exact for every 32-bit `n` and
/// `2 ≤ d < 2^32`); the A* update and path extraction need a cell's column and row, and a
/// hardware division per update costs more than the rest of the index arithmetic.
#[derive(Clone, Copy)]
pub(crate) struct WidthDiv {
    d: u64,
    m: u64,
}

impl WidthDiv {
    pub(crate) fn new(d: usize) -> Self {
        let d = d as u64;
        WidthDiv { d, m: if d >= 2 { u64::MAX / d + 1 } else { 0 } }
    }
    /// `(n % d, n / d)` for `n < 2^32`.
    #[inline(always)]
    pub(crate) fn col_row(self, n: usize) -> (u64, u64) {
        let n = n as u64;
        let q = if self.d >= 2 { ((self.m as u128 * n as u128) >> 64) as u64 } else { n };
        (n - q * self.d, q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn int_conversion_matches_x86() {
        assert_eq!(c_float_to_int(1.0e10), i32::MIN);
        assert_eq!(c_float_to_int(812.9), 812);
        assert_eq!(c_float_to_int(2147483520.0), 2147483520);
        assert_eq!(c_float_to_int(2147483648.0), i32::MIN);
    }

    #[test]
    fn rounding_matches_roundf() {
        for v in [-1.5f32, -1.0, -0.5, -0.49999997, 0.0, 0.49999997, 0.5, 1.4999999, 1.5, 2.5, -2.5]
        {
            assert_eq!(round_half_away(v), v.round() as i64, "{v}");
        }
    }

    /// The run-skipping hash equals byte-wise FNV-1a on arrays mixing runs of every length
    /// with other values (including 1e10's neighbours in float order).
    /// Marsaglia's xorshift64: test inputs, fixed by the seed.
    fn xorshift(mut state: u64) -> impl FnMut() -> u64 {
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        }
    }

    #[test]
    fn run_skipping_fnv_equals_bytewise() {
        let mut next = xorshift(0x9e37_79b9_7f4a_7c15);
        let high = f32::from_bits(POT_HIGH_BITS);
        for _ in 0..300 {
            let mut pot = Vec::new();
            while pot.len() < 3000 {
                let r = next();
                let len = (r >> 8) as usize % if r & 3 == 0 { 600 } else { 9 };
                let v = match r & 7 {
                    0 => f32::from_bits(POT_HIGH_BITS - 1),
                    1 => f32::from_bits(POT_HIGH_BITS + 1),
                    2 => 0.0,
                    _ => (r >> 40) as f32 * 0.37,
                };
                pot.extend(std::iter::repeat_n(high, len));
                pot.push(v);
            }
            assert_eq!(potential_fnv(&pot), potential_fnv_bytewise(&pot));
            assert_eq!(potential_fnv(&pot[1..]), potential_fnv_bytewise(&pot[1..]));
        }
        for n in [0usize, 1, 2, 3, 255, 256, 257, 1 << 16, (1 << 20) + 7] {
            let pot = vec![high; n];
            assert_eq!(potential_fnv(&pot), potential_fnv_bytewise(&pot), "{n}");
        }
    }

    #[test]
    fn fnv_of_empty_is_offset_basis() {
        assert_eq!(path_fnv(&[]), 0xcbf29ce484222325);
    }

    /// The multiplication gives the hardware quotient and remainder (widths and indices at the
    /// ends of their ranges, and a sample in between).
    #[test]
    fn width_division_is_exact() {
        let mut rnd = xorshift(0x2545_f491_4f6c_dd1d);
        let mut widths: Vec<usize> = (1..=70).chain([4095, 4096, 4097, 46_340, 65_535]).collect();
        widths.extend((0..200).map(|_| 1 + (rnd() % (i32::MAX as u64)) as usize));
        for d in widths {
            let w = WidthDiv::new(d);
            let mut ns: Vec<usize> = (0..300).chain([i32::MAX as usize - 1, d, d - 1]).collect();
            ns.extend((0..300).map(|_| (rnd() % (i32::MAX as u64)) as usize));
            for n in ns {
                assert_eq!(w.col_row(n), ((n % d) as u64, (n / d) as u64), "{n} / {d}");
            }
        }
    }
}
