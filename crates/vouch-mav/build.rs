//! Embeds the default MAVLink dialect (ardupilotmega.xml and its includes) into the library, as a
//! digest: the XML is read here, at build time, with the same reader the library uses for
//! `--dialect` (`src/dialect/raw.rs`), and only the records (messages, fields, enums) are embedded.
//! Start-up then builds no XML DOM, which is what kept the guard's peak RSS above 8 MB.
//!
//! The XML is not committed to this repository: it is taken from the `mavlink` crate package that
//! cargo downloaded as a build-dependency (`mavlink/message_definitions/v1.0/` inside the package).
//! `VOUCH_MAV_DEFINITIONS` (a folder) overrides the lookup. When nothing is found the build still
//! succeeds with an empty table; the default dialect then reports a clear error at run time and
//! `--dialect FILE` must be used.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};

#[path = "src/dialect/raw.rs"]
#[allow(dead_code)]
mod raw;

const ROOT: &str = "ardupilotmega.xml";
const REL: &str = "mavlink/message_definitions/v1.0";

fn registry_candidates() -> Vec<PathBuf> {
    let mut homes = Vec::new();
    if let Ok(h) = env::var("CARGO_HOME") {
        homes.push(PathBuf::from(h));
    }
    if let Ok(h) = env::var("HOME") {
        homes.push(Path::new(&h).join(".cargo"));
    }
    let mut out = Vec::new();
    for home in homes {
        let src = home.join("registry").join("src");
        let Ok(indexes) = fs::read_dir(&src) else {
            continue;
        };
        for index in indexes.flatten() {
            let Ok(pkgs) = fs::read_dir(index.path()) else {
                continue;
            };
            let mut found: Vec<PathBuf> = pkgs
                .flatten()
                .map(|p| p.path())
                .filter(|p| {
                    p.file_name()
                        .and_then(|n| n.to_str())
                        .is_some_and(|n| n.starts_with("mavlink-0.21"))
                })
                .map(|p| p.join(REL))
                .filter(|p| p.join(ROOT).is_file())
                .collect();
            found.sort();
            out.extend(found.into_iter().rev());
        }
    }
    out
}

/// Collects `name` and, recursively, every file it `<include>`s (relative names only).
fn collect(dir: &Path, name: &str, out: &mut Vec<(String, String)>) {
    if out.iter().any(|(n, _)| n == name) {
        return;
    }
    let Ok(text) = fs::read_to_string(dir.join(name)) else {
        return;
    };
    let includes: Vec<String> = text
        .split("<include>")
        .skip(1)
        .filter_map(|s| s.split("</include>").next())
        .map(|s| s.trim().to_string())
        .collect();
    out.push((name.to_string(), text));
    for inc in includes {
        collect(dir, &inc, out);
    }
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=src/dialect/raw.rs");
    println!("cargo:rerun-if-env-changed=VOUCH_MAV_DEFINITIONS");
    let mut dirs = Vec::new();
    if let Ok(d) = env::var("VOUCH_MAV_DEFINITIONS") {
        dirs.push(PathBuf::from(d));
    }
    dirs.extend(registry_candidates());
    let mut files = Vec::new();
    let mut origin = String::from("none");
    for dir in dirs {
        if dir.join(ROOT).is_file() {
            collect(&dir, ROOT, &mut files);
            origin = dir.display().to_string();
            break;
        }
    }
    let mut digest = String::new();
    if files.is_empty() {
        println!("cargo:warning=vouch-mav: no MAVLink definitions found; the default dialect will be unavailable (use --dialect)");
    } else {
        let read = |name: &str| -> Result<String, String> {
            files
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, t)| t.clone())
                .ok_or_else(|| format!("include {name} not found"))
        };
        match raw::read_xml(ROOT, &read).ok().and_then(|d| raw::write_digest(&d)) {
            Some(d) => digest = d,
            None => println!("cargo:warning=vouch-mav: the MAVLink definitions in {origin} could not be digested; the default dialect will be unavailable (use --dialect)"),
        }
    }
    let out_dir = PathBuf::from(env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let digest_path = out_dir.join("ardupilotmega.digest");
    fs::write(&digest_path, &digest).expect("write dialect digest into OUT_DIR");
    let table = format!(
        "/// Records of the embedded default dialect (see `raw.rs` for the format; empty if none).\n\
         pub static EMBEDDED_DIGEST: &str = include_str!({:?});\n\
         /// Root file name of the embedded dialect.\n\
         pub static EMBEDDED_ROOT: &str = {ROOT:?};\n\
         /// Where the embedded definitions were taken from at build time.\n\
         pub static EMBEDDED_ORIGIN: &str = {origin:?};\n",
        digest_path.display().to_string()
    );
    fs::write(out_dir.join("embedded_dialect.rs"), table).expect("write embedded_dialect.rs");
}
