//! Embeds the default MAVLink dialect (ardupilotmega.xml and its includes) into the library.
//!
//! The XML is not committed to this repository: it is taken from the `mavlink` crate package that
//! cargo downloaded as a build-dependency (`mavlink/message_definitions/v1.0/` inside the package).
//! `VOUCH_MAV_DEFINITIONS` (a folder) overrides the lookup. When nothing is found the build still
//! succeeds with an empty table; the default dialect then reports a clear error at run time and
//! `--dialect FILE` must be used.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};

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
    if files.is_empty() {
        println!("cargo:warning=vouch-mav: no MAVLink definitions found; the default dialect will be unavailable (use --dialect)");
    }
    let out_dir = PathBuf::from(env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let mut table = String::from("/// (file name, XML text) of the embedded default dialect.\npub static EMBEDDED_XML: &[(&str, &str)] = &[\n");
    for (name, text) in &files {
        let path = out_dir.join(name);
        fs::write(&path, text).expect("write definition into OUT_DIR");
        table.push_str(&format!(
            "    ({name:?}, include_str!({:?})),\n",
            path.display().to_string()
        ));
    }
    table.push_str("];\n");
    table.push_str(&format!("/// Where the embedded definitions were taken from at build time.\npub static EMBEDDED_ORIGIN: &str = {origin:?};\n"));
    fs::write(out_dir.join("embedded_dialect.rs"), table).expect("write embedded_dialect.rs");
}
