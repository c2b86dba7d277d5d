//! Upstream's readings of numeric attribute texts.

/// OCaml's `float_of_string`: underscores ignored, leading blanks skipped (strtod), nothing
/// may follow the number. Accepts `185`, `185.`, `1e3`, `-0.5`, `inf`, `nan`.
pub fn ocaml_float(s: &str) -> Option<f64> {
    let cleaned: String = s.chars().filter(|&c| c != '_').collect();
    let t = cleaned.trim_start_matches([' ', '\t', '\n', '\r', '\x0b', '\x0c']);
    if t.is_empty() {
        return None;
    }
    t.parse::<f64>().ok()
}

/// Upstream's `Latlong.deg_of_string`: a decimal number, or `D M S`, or `D M S H` with the
/// hemisphere `N`/`E` (positive) or `S`/`W` (negative). Blanks separate the fields.
pub fn degrees(s: &str) -> Option<f64> {
    let parts: Vec<&str> = s.split([' ', '\t']).filter(|p| !p.is_empty()).collect();
    let dms = |d: &str, m: &str, sec: &str| -> Option<f64> {
        let d: i64 = d.parse().ok()?;
        let m: i64 = m.parse().ok()?;
        let sec = ocaml_float(sec)?;
        let mag = d.abs() as f64 + m as f64 / 60.0 + sec / 3600.0;
        Some(if d < 0 || s.trim_start().starts_with('-') { -mag } else { mag })
    };
    match parts.as_slice() {
        [one] => ocaml_float(one),
        [d, m, sec] => dms(d, m, sec),
        [d, m, sec, h] => {
            let sign = match *h {
                "N" | "E" => 1.0,
                "S" | "W" => -1.0,
                _ => return None,
            };
            dms(d, m, sec).map(|v| sign * v)
        }
        _ => None,
    }
}

/// `TRUE`/`FALSE`, case-insensitive (upstream's call `loop`/`break`).
pub fn bool_text(s: &str) -> Option<bool> {
    if s.eq_ignore_ascii_case("true") {
        Some(true)
    } else if s.eq_ignore_ascii_case("false") {
        Some(false)
    } else {
        None
    }
}
