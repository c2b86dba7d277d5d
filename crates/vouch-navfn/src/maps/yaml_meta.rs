//! The map_server YAML file, read like nav2's `loadMapYaml`: a YAML document (block or flow
//! style, `---` document start, comments, anchors) whose keys `image`, `resolution`, `origin`
//! (three numbers), `free_thresh`, `occupied_thresh` and `negate` are required and `mode` is
//! optional. Scalars are converted with yaml-cpp's rules, not YAML 1.2's: a number is what a C++
//! stream reads (`.inf`/`.nan` spelled the YAML way), `negate` is an integer (decimal, `0x` hex,
//! leading-zero octal) or one of yaml-cpp's boolean words, `mode` is case-insensitive.
//!
//! Parsed by saphyr (a maintained YAML 1.2 parser) with scalar resolution turned off, so that
//! every value keeps its text and its position: errors point at the offending node.

use std::path::{Path, PathBuf};

use saphyr::{MarkedYaml, Marker, YamlData, YamlLoader};
use saphyr_parser::{Parser, ScanError};

use super::MapError;

/// map_server's interpretation mode (`mode:`; trinary when absent).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum MapMode {
    /// Occupied, free or unknown by the two thresholds.
    Trinary,
    /// Like trinary, values between the thresholds scaled to 1..99; transparent pixels unknown.
    Scale,
    /// The grey value is the occupancy (0..100), anything else unknown.
    Raw,
}

/// The YAML metadata of a map.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RosMapMeta {
    /// The image file as written in the YAML (relative to the YAML's folder unless absolute).
    pub image: PathBuf,
    /// Metres per cell.
    pub resolution: f64,
    /// `[x, y, yaw]` of the lower-left pixel.
    pub origin: [f64; 3],
    /// White is occupied instead of black.
    pub negate: bool,
    /// Occupancy above (or at) which a pixel is occupied.
    pub occupied_thresh: f64,
    /// Occupancy below (or at) which a pixel is free.
    pub free_thresh: f64,
    /// Interpretation mode.
    pub mode: MapMode,
}

impl Default for RosMapMeta {
    /// The frame an image without YAML gets (nav2_system_tests' planner tester: origin 0, 1 m
    /// cells) and map_server's usual thresholds.
    fn default() -> Self {
        RosMapMeta {
            image: PathBuf::new(),
            resolution: 1.0,
            origin: [0.0; 3],
            negate: false,
            occupied_thresh: 0.65,
            free_thresh: 0.196,
            mode: MapMode::Trinary,
        }
    }
}

/// Parse map_server YAML text; `path` names the file in errors.
pub fn parse_map_yaml(path: &Path, text: &str) -> Result<RosMapMeta, MapError> {
    let doc = load_first_document(path, text)?;
    let at = |node: &MarkedYaml, msg: String| located(path, text, node.span.start, msg);
    let YamlData::Mapping(map) = &doc.data else {
        return Err(at(&doc, "a map YAML must be a mapping of `key: value`".into()));
    };
    let get = |key: &str| -> Result<&MarkedYaml, MapError> {
        map.iter()
            .find(|(k, _)| scalar_text(k) == Some(key))
            .map(|(_, v)| v)
            .ok_or_else(|| at(&doc, format!("missing `{key}:` (map_server requires it)")))
    };
    let number = |key: &str| -> Result<f64, MapError> {
        let node = get(key)?;
        scalar_text(node)
            .and_then(cpp_double)
            .ok_or_else(|| at(node, format!("{key} must be a number, found {}", shown(node))))
    };

    let image_node = get("image")?;
    let image =
        scalar_text(image_node).ok_or_else(|| at(image_node, "image must name a file".into()))?;
    if image.is_empty() {
        return Err(at(image_node, "the image tag is empty".into()));
    }
    let resolution = number("resolution")?;
    if !(resolution.is_finite() && resolution > 0.0) {
        let node = get("resolution")?;
        return Err(at(node, format!("resolution {resolution} must be a finite number > 0")));
    }
    let origin = parse_origin(get("origin")?, &at)?;
    let free_thresh = number("free_thresh")?;
    let occupied_thresh = number("occupied_thresh")?;
    let negate_node = get("negate")?;
    let negate = scalar_text(negate_node)
        .and_then(|s| cpp_int(s).map(|v| v != 0).or_else(|| cpp_bool(s)))
        .ok_or_else(|| {
            at(
                negate_node,
                format!("negate must be an integer or a boolean, found {}", shown(negate_node)),
            )
        })?;
    let mode = match map.iter().find(|(k, _)| scalar_text(k) == Some("mode")) {
        None => MapMode::Trinary,
        Some((_, node)) => parse_mode(node).ok_or_else(|| {
            at(node, format!("mode must be trinary, scale or raw, found {}", shown(node)))
        })?,
    };
    Ok(RosMapMeta {
        image: PathBuf::from(image),
        resolution,
        origin,
        negate,
        occupied_thresh,
        free_thresh,
        mode,
    })
}

/// The first document of the stream (yaml-cpp's `LoadFile` reads only that one).
fn load_first_document<'t>(path: &Path, text: &'t str) -> Result<MarkedYaml<'t>, MapError> {
    let scan_error = |e: &ScanError| located(path, text, *e.marker(), e.info().to_string());
    let mut parser = Parser::new_from_str(text);
    let mut loader: YamlLoader<MarkedYaml> = YamlLoader::default();
    loader.early_parse(false);
    parser.load(&mut loader, true).map_err(|e| scan_error(&e))?;
    if let Some(e) = loader.error() {
        return Err(scan_error(e));
    }
    loader
        .into_documents()
        .into_iter()
        .next()
        .ok_or_else(|| MapError::file(path, "empty YAML file: no map metadata"))
}

/// An error at `mark` (a character position of the parser).
fn located(path: &Path, text: &str, mark: Marker, msg: String) -> MapError {
    let byte = text.char_indices().nth(mark.index()).map_or(text.len(), |(b, _)| b);
    let rest = &text[byte..];
    let len = rest.find(['\n', ',', ']', '}', '#']).unwrap_or(rest.len());
    MapError::spanned(path, text, mark.line().max(1), (byte, rest[..len].trim_end().len()), msg)
}

/// The text of a scalar node (through a tag), `None` for collections and aliases.
fn scalar_text<'a>(node: &'a MarkedYaml) -> Option<&'a str> {
    match &node.data {
        YamlData::Representation(s, _, _) => Some(s),
        YamlData::Tagged(_, inner) => scalar_text(inner),
        _ => None,
    }
}

/// A node as the user wrote it, for messages.
fn shown(node: &MarkedYaml) -> String {
    match &node.data {
        YamlData::Sequence(_) => "a list".into(),
        YamlData::Mapping(_) => "a mapping".into(),
        _ => format!("`{}`", crate::diag::quote(scalar_text(node).unwrap_or(""))),
    }
}

fn parse_origin(
    node: &MarkedYaml,
    at: &impl Fn(&MarkedYaml, String) -> MapError,
) -> Result<[f64; 3], MapError> {
    let YamlData::Sequence(items) = &node.data else {
        return Err(at(
            node,
            format!("origin must be a list `[x, y, yaw]`, found {}", shown(node)),
        ));
    };
    if items.len() != 3 {
        return Err(at(node, format!("origin should have 3 elements, not {}", items.len())));
    }
    let mut origin = [0.0; 3];
    for (slot, item) in origin.iter_mut().zip(items) {
        *slot =
            scalar_text(item).and_then(cpp_double).filter(|v| v.is_finite()).ok_or_else(|| {
                at(item, format!("origin element {} is not a finite number", shown(item)))
            })?;
    }
    Ok(origin)
}

fn parse_mode(node: &MarkedYaml) -> Option<MapMode> {
    match scalar_text(node)?.to_ascii_lowercase().as_str() {
        "trinary" => Some(MapMode::Trinary),
        "scale" => Some(MapMode::Scale),
        "raw" => Some(MapMode::Raw),
        _ => None,
    }
}

/// A double as yaml-cpp converts a scalar: what `std::istream >> double` reads in full
/// (optional sign, digits with an optional point, optional exponent; trailing blanks allowed),
/// or YAML's `.inf`, `-.inf`, `.nan` spellings. An overflowing literal is refused (the stream
/// fails on it).
pub fn cpp_double(s: &str) -> Option<f64> {
    let t = s.trim_end_matches([' ', '\t', '\n', '\r']);
    match t {
        ".inf" | ".Inf" | ".INF" | "+.inf" | "+.Inf" | "+.INF" => return Some(f64::INFINITY),
        "-.inf" | "-.Inf" | "-.INF" => return Some(f64::NEG_INFINITY),
        ".nan" | ".NaN" | ".NAN" => return Some(f64::NAN),
        _ => {}
    }
    let b = t.as_bytes();
    let mut i = usize::from(matches!(b.first(), Some(b'+' | b'-')));
    let digits_from = |mut j: usize| {
        while j < b.len() && b[j].is_ascii_digit() {
            j += 1;
        }
        j
    };
    let int_end = digits_from(i);
    let mut mantissa_digits = int_end - i;
    i = int_end;
    if b.get(i) == Some(&b'.') {
        let frac_end = digits_from(i + 1);
        mantissa_digits += frac_end - i - 1;
        i = frac_end;
    }
    if mantissa_digits == 0 {
        return None;
    }
    if matches!(b.get(i), Some(b'e' | b'E')) {
        let mut j = i + 1;
        if matches!(b.get(j), Some(b'+' | b'-')) {
            j += 1;
        }
        let exp_end = digits_from(j);
        if exp_end == j {
            return None;
        }
        i = exp_end;
    }
    if i != b.len() {
        return None;
    }
    t.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// An `int` as yaml-cpp converts a scalar (a stream with the base taken from the prefix:
/// `0x` hexadecimal, a leading `0` octal), in range of a 32-bit int.
pub fn cpp_int(s: &str) -> Option<i64> {
    let t = s.trim_end_matches([' ', '\t']);
    let (neg, body) = match t.as_bytes().first() {
        Some(b'-') => (true, &t[1..]),
        Some(b'+') => (false, &t[1..]),
        _ => (false, t),
    };
    let (radix, digits) = if let Some(h) = body.strip_prefix("0x").or(body.strip_prefix("0X")) {
        (16, h)
    } else if body.len() > 1 && body.starts_with('0') {
        (8, &body[1..])
    } else {
        (10, body)
    };
    if digits.is_empty() || !digits.chars().all(|c| c.is_digit(radix)) {
        return None;
    }
    let v = i64::from_str_radix(digits, radix).ok()?;
    let v = if neg { -v } else { v };
    (i32::MIN as i64..=i32::MAX as i64).contains(&v).then_some(v)
}

/// A bool as yaml-cpp converts a scalar: y/yes/true/on and n/no/false/off, each all lower
/// case, all upper case or capitalised.
pub fn cpp_bool(s: &str) -> Option<bool> {
    const WORDS: [(&str, bool); 8] = [
        ("y", true),
        ("yes", true),
        ("true", true),
        ("on", true),
        ("n", false),
        ("no", false),
        ("false", false),
        ("off", false),
    ];
    WORDS
        .iter()
        .find_map(|&(w, v)| (s == w || s == w.to_uppercase() || s == capitalised(w)).then_some(v))
}

fn capitalised(w: &str) -> String {
    let mut c = w.chars();
    match c.next() {
        Some(f) => f.to_uppercase().chain(c).collect(),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_follow_the_cpp_stream() {
        assert_eq!(cpp_double("0.05"), Some(0.05));
        assert_eq!(cpp_double("-10"), Some(-10.0));
        assert_eq!(cpp_double("+1e-2"), Some(0.01));
        assert_eq!(cpp_double(".5"), Some(0.5));
        assert_eq!(cpp_double("5."), Some(5.0));
        assert_eq!(cpp_double(".inf"), Some(f64::INFINITY));
        assert_eq!(cpp_double("-.Inf"), Some(f64::NEG_INFINITY));
        assert!(cpp_double(".NaN").is_some_and(f64::is_nan));
        for bad in ["", "fast", "0x10", "1e", "1e999", "inf", "nan", "1,5", " 1", "--1", "."] {
            assert_eq!(cpp_double(bad), None, "{bad}");
        }
    }

    #[test]
    fn ints_and_bools_follow_yaml_cpp() {
        assert_eq!(cpp_int("0"), Some(0));
        assert_eq!(cpp_int("0x10"), Some(16));
        assert_eq!(cpp_int("010"), Some(8));
        assert_eq!(cpp_int("-3"), Some(-3));
        assert_eq!(cpp_int("08"), None);
        assert_eq!(cpp_int("99999999999"), None);
        assert_eq!(cpp_bool("Yes"), Some(true));
        assert_eq!(cpp_bool("OFF"), Some(false));
        assert_eq!(cpp_bool("oFF"), None);
        assert_eq!(cpp_bool("1"), None);
    }
}
