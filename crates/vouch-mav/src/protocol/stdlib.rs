//! The standard library of protocols, shipped inside the binary.

/// (file name, text) of every standard protocol file.
pub const STDLIB: &[(&str, &str)] = &[
    ("mission.vproto", include_str!("../../protocols/mission.vproto")),
    ("param.vproto", include_str!("../../protocols/param.vproto")),
    ("command.vproto", include_str!("../../protocols/command.vproto")),
    ("datum.vproto", include_str!("../../protocols/datum.vproto")),
];

pub fn sources() -> Vec<(String, String)> {
    STDLIB.iter().map(|(n, t)| (format!("stdlib/{n}"), t.to_string())).collect()
}
