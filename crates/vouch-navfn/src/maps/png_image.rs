//! PNG map images (map_server also reads PNG): grey, grey+alpha, RGB, RGBA; 8 or 16 bit.
//! Colour pixels are averaged over their channels as map_server does.

use std::path::Path;

use super::pgm::GreyImage;
use super::{MapError, MAX_CELLS};

pub(crate) fn decode_png(
    path: &Path,
    data: &[u8],
) -> Result<(GreyImage, Option<Vec<bool>>), MapError> {
    let bad = |e: png::DecodingError| MapError::file(path, format!("bad PNG: {e}"));
    let mut decoder = png::Decoder::new(data);
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().map_err(bad)?;
    let info = reader.info();
    let (w, h) = (info.width as usize, info.height as usize);
    if w.checked_mul(h).is_none_or(|c| c > MAX_CELLS || c == 0) {
        return Err(MapError::file(path, format!("image size {w}x{h} is empty or too large")));
    }
    let mut buf = vec![0; reader.output_buffer_size()];
    let frame = reader.next_frame(&mut buf).map_err(bad)?;
    let bytes = &buf[..frame.buffer_size()];
    let channels = frame.color_type.samples();
    let wide = frame.bit_depth == png::BitDepth::Sixteen;
    let maxval: u16 = if wide { 65535 } else { 255 };
    let sample = |i: usize| -> u16 {
        if wide {
            u16::from_be_bytes([bytes[2 * i], bytes[2 * i + 1]])
        } else {
            bytes[i] as u16
        }
    };
    let colour = match frame.color_type {
        png::ColorType::Grayscale | png::ColorType::GrayscaleAlpha => 1,
        _ => 3,
    };
    let has_alpha =
        matches!(frame.color_type, png::ColorType::GrayscaleAlpha | png::ColorType::Rgba);
    let mut pixels = Vec::with_capacity(w * h);
    let mut alpha = Vec::with_capacity(if has_alpha { w * h } else { 0 });
    for p in 0..w * h {
        let base = p * channels;
        let sum: u32 = (0..colour).map(|c| sample(base + c) as u32).sum();
        pixels.push((sum / colour as u32) as u16);
        if has_alpha {
            alpha.push(sample(base + channels - 1) == maxval);
        }
    }
    let img = GreyImage { width: w, height: h, maxval, pixels };
    Ok((img, has_alpha.then_some(alpha)))
}
