//! CRC-16/MCRF4XX, which MAVLink calls "X.25": the checksum of every frame and the seed of every
//! message's CRC_EXTRA. Below both [`crate::codec`] (frames) and [`crate::dialect`] (CRC_EXTRA
//! of a message definition), so neither imports the other for it.
//!
//! The arithmetic is the `crc` crate's catalogue entry `CRC_16_MCRF4XX` (poly 0x1021 reflected,
//! init 0xFFFF, no final XOR), with its slice-by-16 tables: the tests below check it against
//! MAVLink's own byte formula bit for bit.

use ::crc::{CRC_16_MCRF4XX, Crc, Digest, Table};

/// The algorithm with slice-by-16 tables (8 KiB, built at compile time).
static MCRF4XX: Crc<u16, Table<16>> = Crc::<u16, Table<16>>::new(&CRC_16_MCRF4XX);

/// A running checksum.
#[derive(Clone)]
pub struct X25(Digest<'static, u16, Table<16>>);

impl Default for X25 {
    fn default() -> Self {
        Self::new()
    }
}

impl std::fmt::Debug for X25 {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "X25({:#06x})", self.get())
    }
}

impl X25 {
    /// The register of an empty message (0xFFFF).
    pub fn new() -> Self {
        X25(MCRF4XX.digest())
    }

    /// Continues from a register value computed elsewhere (e.g. a running CRC kept as `u16`).
    pub fn resume(register: u16) -> Self {
        // The crate reflects the initial value of a reflected algorithm; the register of a
        // reflected CRC is already in reflected order, so it is handed over reflected back.
        X25(MCRF4XX.digest_with_initial(register.reverse_bits()))
    }

    /// Adds one byte.
    #[inline]
    pub fn push(&mut self, b: u8) {
        self.0.update(&[b]);
    }

    /// Adds bytes.
    #[inline]
    pub fn update(&mut self, bytes: &[u8]) {
        self.0.update(bytes);
    }

    /// The register now (the checksum of what was added so far).
    pub fn get(&self) -> u16 {
        self.0.clone().finalize()
    }
}

/// CRC of a whole frame body (bytes after the magic up to the end of the payload) plus CRC_EXTRA.
#[inline]
pub fn frame_crc(body: &[u8], crc_extra: u8) -> u16 {
    let mut c = MCRF4XX.digest();
    c.update(body);
    c.update(&[crc_extra]);
    c.finalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// MAVLink's byte step (`crc_accumulate` of its C library), written out as the reference.
    fn mavlink_step(crc: u16, b: u8) -> u16 {
        let mut t = b ^ (crc & 0xFF) as u8;
        t ^= t << 4;
        let t = u16::from(t);
        (crc >> 8) ^ (t << 8) ^ (t << 3) ^ (t >> 4)
    }

    fn data() -> Vec<u8> {
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        (0..4096)
            .map(|_| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                x as u8
            })
            .collect()
    }

    #[test]
    fn check_value_of_mcrf4xx() {
        // Standard check value of CRC-16/MCRF4XX over "123456789".
        let mut c = X25::new();
        c.update(b"123456789");
        assert_eq!(c.get(), 0x6F91);
    }

    #[test]
    fn crate_matches_the_mavlink_byte_formula() {
        let data: Vec<u8> = (0..=255u8).chain((0..=255u8).rev()).chain(data()).collect();
        for n in [0, 1, 2, 15, 16, 17, 31, 280, 511, 1000, data.len()] {
            let want = data[..n].iter().fold(0xFFFF, |c, &b| mavlink_step(c, b));
            let mut a = X25::new();
            a.update(&data[..n]);
            assert_eq!(a.get(), want, "{n} bytes at once");
            let mut b = X25::new();
            data[..n].iter().for_each(|&x| b.push(x));
            assert_eq!(b.get(), want, "{n} bytes one by one");
        }
    }

    #[test]
    fn resume_continues_a_register() {
        let data = data();
        for cut in [0, 1, 7, 100, 2000] {
            let head = data[..cut].iter().fold(0xFFFF, |c, &b| mavlink_step(c, b));
            let want = data.iter().fold(0xFFFF, |c, &b| mavlink_step(c, b));
            let mut r = X25::resume(head);
            r.update(&data[cut..]);
            assert_eq!(r.get(), want, "cut at {cut}");
        }
    }

    #[test]
    fn frame_crc_adds_crc_extra_last() {
        let body = data();
        let want = body.iter().chain([&221u8]).fold(0xFFFF, |c, &b| mavlink_step(c, b));
        assert_eq!(frame_crc(&body, 221), want);
    }
}
