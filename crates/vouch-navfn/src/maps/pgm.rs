//! PGM reader (P5 binary and P2 ASCII, maxval up to 65535), the image format of nav2's maps.
//! Hand-written because the format is a dozen lines of header parsing and we need located,
//! specific errors (truncated data, bad maxval) rather than a generic image-decoder failure.

use std::path::Path;

use super::{MAX_CELLS, MapError};
use crate::diag::quote;

/// A grey image, row 0 = top row of the file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GreyImage {
    pub width: usize,
    pub height: usize,
    pub maxval: u16,
    /// `width*height` samples, row-major from the top.
    pub pixels: Vec<u16>,
}

/// Parse a PGM file's bytes; `path` only locates errors.
pub fn parse_pgm(path: &Path, data: &[u8]) -> Result<GreyImage, MapError> {
    let mut pos = 0usize;
    let magic = header_token(path, data, &mut pos)?;
    let binary = match magic.as_str() {
        "P5" => true,
        "P2" => false,
        other => {
            return Err(MapError::file(
                path,
                format!("not a PGM image (magic `{}`, expected P5 or P2)", quote(other)),
            ));
        }
    };
    let width = header_number(path, data, &mut pos, "width")?;
    let height = header_number(path, data, &mut pos, "height")?;
    let maxval = header_number(path, data, &mut pos, "maxval")?;
    if width == 0 || height == 0 {
        return Err(MapError::file(path, format!("image size {width}x{height} is empty")));
    }
    if !(1..=65535).contains(&maxval) {
        return Err(MapError::file(path, format!("maxval {maxval} outside 1..65535")));
    }
    let cells = width.checked_mul(height).filter(|&c| c <= MAX_CELLS).ok_or_else(|| {
        MapError::file(path, format!("image size {width}x{height} exceeds {MAX_CELLS} cells"))
    })?;
    let mut pixels = Vec::with_capacity(cells);
    if binary {
        // exactly one whitespace byte separates the header from the samples
        pos += 1;
        let bytes_per = if maxval < 256 { 1 } else { 2 };
        let need = cells * bytes_per;
        let avail = data.len().saturating_sub(pos);
        if avail < need {
            return Err(MapError::file(
                path,
                format!("truncated PGM: {width}x{height} needs {need} data bytes, found {avail}"),
            ));
        }
        let body = &data[pos..pos + need];
        if bytes_per == 1 {
            pixels.extend(body.iter().map(|&b| b as u16));
        } else {
            pixels.extend(body.chunks_exact(2).map(|c| u16::from_be_bytes([c[0], c[1]])));
        }
    } else {
        for i in 0..cells {
            let v = match next_token(data, &mut pos) {
                Some(t) => t,
                None => {
                    return Err(MapError::file(
                        path,
                        format!("truncated PGM: {cells} samples expected, found {i}"),
                    ));
                }
            };
            let v: usize = v.parse().map_err(|_| {
                MapError::file(path, format!("sample {i}: `{}` is not a number", quote(&v)))
            })?;
            pixels.push(u16::try_from(v).ok().filter(|&v| v as usize <= maxval).ok_or_else(
                || MapError::file(path, format!("sample {i}: value {v} exceeds maxval {maxval}")),
            )?);
        }
    }
    if binary && let Some(&bad) = pixels.iter().find(|&&p| p as usize > maxval) {
        return Err(MapError::file(path, format!("sample value {bad} exceeds maxval {maxval}")));
    }
    Ok(GreyImage { width, height, maxval: maxval as u16, pixels })
}

fn header_token(path: &Path, data: &[u8], pos: &mut usize) -> Result<String, MapError> {
    next_token(data, pos).ok_or_else(|| MapError::file(path, "truncated PGM header"))
}

fn header_number(path: &Path, data: &[u8], pos: &mut usize, what: &str) -> Result<usize, MapError> {
    let t = header_token(path, data, pos)?;
    t.parse()
        .map_err(|_| MapError::file(path, format!("PGM {what} `{}` is not a number", quote(&t))))
}

/// Next whitespace-separated token, skipping `#` comments; leaves `pos` on the byte after it.
fn next_token(data: &[u8], pos: &mut usize) -> Option<String> {
    loop {
        while *pos < data.len() && data[*pos].is_ascii_whitespace() {
            *pos += 1;
        }
        if *pos < data.len() && data[*pos] == b'#' {
            while *pos < data.len() && data[*pos] != b'\n' {
                *pos += 1;
            }
            continue;
        }
        break;
    }
    let start = *pos;
    while *pos < data.len() && !data[*pos].is_ascii_whitespace() && data[*pos] != b'#' {
        *pos += 1;
    }
    if *pos == start {
        None
    } else {
        Some(String::from_utf8_lossy(&data[start..*pos]).into_owned())
    }
}
