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
    if (-2147483648.0..2147483648.0).contains(&f) {
        f as i32
    } else {
        i32::MIN
    }
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
pub fn potential_fnv(pot: &[f32]) -> u64 {
    let mut h = Fnv1a::default();
    for &p in pot {
        h.f32(p);
    }
    h.0
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

    #[test]
    fn fnv_of_empty_is_offset_basis() {
        assert_eq!(path_fnv(&[]), 0xcbf29ce484222325);
    }
}
