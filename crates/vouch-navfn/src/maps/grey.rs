//! Images as map_server sees them: grey samples exported to 8 bits the way ImageMagick (Q16,
//! non-HDRI) does, and the alpha channel when there is one.

use super::pgm::GreyImage;

/// An image as map_server sees it: grey samples and, for images with an alpha channel, the
/// 8-bit alpha of every pixel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MapImage {
    /// Grey samples with their maxval (row 0 = top).
    pub grey: GreyImage,
    /// 8-bit alpha per pixel, when the image has an alpha channel.
    pub alpha: Option<Vec<u8>>,
}

/// ImageMagick's (Q16, non-HDRI) `ScaleQuantumToChar`.
pub fn quantum_to_char(q: u16) -> u8 {
    let q = q as u32 + 128;
    ((q - (q >> 8)) >> 8) as u8
}

/// ImageMagick's `ScaleAnyToQuantum`: a sample of a `maxval` image to a 16-bit quantum.
pub fn sample_to_quantum(v: u16, maxval: u16) -> u16 {
    if maxval == u16::MAX {
        return v;
    }
    (65535.0 * v as f64 / maxval as f64 + 0.5) as u16
}

/// The 8-bit grey value map_server reads for a sample (`"I"` exported as `CharPixel`).
pub fn grey8(v: u16, maxval: u16) -> u8 {
    if maxval == 255 { v as u8 } else { quantum_to_char(sample_to_quantum(v, maxval)) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn imagemagick_scaling_keeps_8_bit_values_and_rounds_16_bit_ones() {
        for v in 0..=255u16 {
            assert_eq!(quantum_to_char(v * 257), v as u8);
        }
        assert_eq!(grey8(65535, 65535), 255);
        assert_eq!(grey8(128, 65535), 0);
        assert_eq!(grey8(129, 65535), 1);
        assert_eq!(grey8(1, 1), 255);
        assert_eq!(grey8(50, 100), 128);
    }
}
