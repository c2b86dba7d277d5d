//! CRC-16/MCRF4XX ("X.25" in MAVLink terms). The byte step is MAVLink's formula; the table form
//! (built from that formula at compile time) does the same per byte with one lookup.

#[derive(Debug, Clone, Copy)]
pub struct X25(u16);

impl Default for X25 {
    fn default() -> Self {
        Self::new()
    }
}

impl X25 {
    pub const fn new() -> Self {
        X25(0xFFFF)
    }

    /// Continues from a register value computed elsewhere (e.g. a running CRC kept as `u16`).
    pub const fn resume(register: u16) -> Self {
        X25(register)
    }

    #[inline]
    pub fn push(&mut self, b: u8) {
        let mut t = b ^ (self.0 & 0xFF) as u8;
        t ^= t << 4;
        let t = u16::from(t);
        self.0 = (self.0 >> 8) ^ (t << 8) ^ (t << 3) ^ (t >> 4);
    }

    #[inline]
    pub fn update(&mut self, bytes: &[u8]) {
        let mut c = self.0;
        for &b in bytes {
            c = (c >> 8) ^ TABLE[usize::from((c as u8) ^ b)];
        }
        self.0 = c;
    }

    pub fn get(&self) -> u16 {
        self.0
    }
}

/// CRC update of a zero register by byte `i`, i.e. the contribution of the low byte.
const fn table() -> [u16; 256] {
    let mut t = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        // Same step as `push` with crc = 0 and b = i: t = i; t ^= t << 4 (8-bit); …
        let mut x = (i as u8) as u16;
        x = (x ^ (x << 4)) & 0xFF;
        t[i] = (x << 8) ^ (x << 3) ^ (x >> 4);
        i += 1;
    }
    t
}

static TABLE: [u16; 256] = table();

/// CRC of a whole frame body (bytes after the magic up to the end of the payload) plus CRC_EXTRA.
#[inline]
pub fn frame_crc(body: &[u8], crc_extra: u8) -> u16 {
    let mut c = X25::new();
    c.update(body);
    c.push(crc_extra);
    c.get()
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn check_value_of_mcrf4xx() {
        // Standard check value of CRC-16/MCRF4XX over "123456789".
        let mut c = X25::new();
        c.update(b"123456789");
        assert_eq!(c.get(), 0x6F91);
    }

    #[test]
    fn table_matches_the_bytewise_formula() {
        let data: Vec<u8> = (0..=255u8).chain((0..=255u8).rev()).collect();
        let mut a = X25::new();
        a.update(&data);
        let mut b = X25::new();
        for &x in &data {
            b.push(x);
        }
        assert_eq!(a.get(), b.get());
    }
}
