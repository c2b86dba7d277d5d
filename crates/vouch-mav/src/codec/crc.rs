//! CRC-16/MCRF4XX ("X.25" in MAVLink terms), bitwise; 1–2 ns per byte is far below our budget.

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

    #[inline]
    pub fn push(&mut self, b: u8) {
        let mut t = b ^ (self.0 & 0xFF) as u8;
        t ^= t << 4;
        let t = u16::from(t);
        self.0 = (self.0 >> 8) ^ (t << 8) ^ (t << 3) ^ (t >> 4);
    }

    #[inline]
    pub fn update(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.push(b);
        }
    }

    pub fn get(&self) -> u16 {
        self.0
    }
}

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
}
