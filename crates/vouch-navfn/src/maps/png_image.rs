//! PNG map images (map_server reads them through ImageMagick): grey, grey+alpha, RGB, RGBA,
//! palette; 1 to 16 bit. Colour pixels become grey with ImageMagick's default intensity (Rec. 709
//! luma on the quantum values); a `tRNS` chunk counts as an alpha channel, as for ImageMagick.

use std::path::Path;

use super::grey::{MapImage, quantum_to_char, sample_to_quantum};
use super::pgm::GreyImage;
use super::{MAX_CELLS, MapError};

pub(crate) fn decode_png(path: &Path, data: &[u8]) -> Result<MapImage, MapError> {
    let bad = |e: png::DecodingError| MapError::file(path, format!("bad PNG: {e}"));
    let mut decoder = png::Decoder::new(std::io::Cursor::new(data));
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().map_err(bad)?;
    let info = reader.info();
    let (w, h) = (info.width as usize, info.height as usize);
    if w.checked_mul(h).is_none_or(|c| c > MAX_CELLS || c == 0) {
        return Err(MapError::file(path, format!("image size {w}x{h} is empty or too large")));
    }
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| MapError::file(path, format!("image size {w}x{h} is too large")))?;
    let mut buf = vec![0; size];
    let frame = reader.next_frame(&mut buf).map_err(bad)?;
    let bytes = &buf[..frame.buffer_size()];
    let channels = frame.color_type.samples();
    let wide = frame.bit_depth == png::BitDepth::Sixteen;
    let maxval: u16 = if wide { 65535 } else { 255 };
    let sample = |i: usize| -> u16 {
        if wide { u16::from_be_bytes([bytes[2 * i], bytes[2 * i + 1]]) } else { bytes[i] as u16 }
    };
    let colour =
        !matches!(frame.color_type, png::ColorType::Grayscale | png::ColorType::GrayscaleAlpha);
    let has_alpha =
        matches!(frame.color_type, png::ColorType::GrayscaleAlpha | png::ColorType::Rgba);
    let mut pixels = Vec::with_capacity(w * h);
    let mut alpha = Vec::with_capacity(if has_alpha { w * h } else { 0 });
    for p in 0..w * h {
        let base = p * channels;
        if colour {
            let q = |c: usize| sample_to_quantum(sample(base + c), maxval) as f64;
            let luma = 0.212656 * q(0) + 0.715158 * q(1) + 0.072186 * q(2);
            pixels.push((luma + 0.5).clamp(0.0, 65535.0) as u16);
        } else {
            pixels.push(sample(base));
        }
        if has_alpha {
            alpha.push(quantum_to_char(sample_to_quantum(sample(base + channels - 1), maxval)));
        }
    }
    let grey_max = if colour { 65535 } else { maxval };
    let grey = GreyImage { width: w, height: h, maxval: grey_max, pixels };
    Ok(MapImage { grey, alpha: has_alpha.then_some(alpha) })
}
