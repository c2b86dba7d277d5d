//! Embeds the default MAVLink dialect (ardupilotmega.xml and its includes) into the library, as a
//! digest: the XML is read here, at build time, with the same reader the library uses for
//! `--dialect` (`src/dialect/raw.rs`), and only the records (messages, fields, enums) are embedded.
//! Start-up then builds no XML DOM, which keeps the guard's peak RSS low.
//!
//! The XML is not committed to this repository: it is the copy that the `mavlink` crate package
//! (a build-dependency, pinned to 0.21) carries in `mavlink/message_definitions/v1.0/`. Where
//! that package is depends on how cargo got it, so these places are searched, in order:
//!
//! 1. `VOUCH_MAV_DEFINITIONS`, a folder holding `ardupilotmega.xml` (explicit choice);
//! 2. beside this package (`../mavlink-0.21.*`): both live in one registry or vendor folder
//!    when vouch-mav itself comes from a registry or is vendored;
//! 3. `vendor/` folders of this package's ancestors (`cargo vendor` in a workspace);
//! 4. the registry sources under `$CARGO_HOME` (default `~/.cargo`).
//!
//! When none holds the XML, or it cannot be digested, the build fails and says so. A build that
//! deliberately goes without a default dialect sets `VOUCH_MAV_NO_DEFAULT_DIALECT=1`; the
//! library then reports `DialectError::NoEmbedded` at run time and `--dialect FILE.xml` must be
//! used.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};

#[path = "src/dialect/raw.rs"]
#[allow(dead_code)]
mod raw;

const ROOT: &str = "ardupilotmega.xml";
const REL: &str = "mavlink/message_definitions/v1.0";
/// Package folders that may hold the definitions: `mavlink-0.21.x` (registry, versioned vendor)
/// or `mavlink` (plain vendor).
fn is_mavlink_package(name: &str) -> bool {
    name == "mavlink" || name.starts_with("mavlink-0.21.")
}

/// Definition folders inside the mavlink packages directly in `dir`, newest version first.
fn packages_in(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = fs::read_dir(dir) else { return Vec::new() };
    let mut found: Vec<PathBuf> = entries
        .flatten()
        .filter(|e| e.file_name().to_str().is_some_and(is_mavlink_package))
        .map(|e| e.path().join(REL))
        .filter(|p| p.join(ROOT).is_file())
        .collect();
    found.sort();
    found.reverse();
    found
}

/// Every folder that may hold the XML, in search order (see the file's documentation), and a
/// description of the places searched for the error message.
fn candidates() -> (Vec<PathBuf>, Vec<String>) {
    let (mut out, mut places) = (Vec::new(), Vec::new());
    match env::var_os("VOUCH_MAV_DEFINITIONS") {
        Some(d) => {
            places.push(format!("VOUCH_MAV_DEFINITIONS={}", Path::new(&d).display()));
            out.push(PathBuf::from(d));
        }
        None => places.push("VOUCH_MAV_DEFINITIONS (not set)".into()),
    }
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    if let Some(parent) = manifest.parent() {
        places.push(format!("{}/mavlink-0.21.*", parent.display()));
        out.extend(packages_in(parent));
    }
    places.push(format!("vendor/mavlink* in the ancestors of {}", manifest.display()));
    for ancestor in manifest.ancestors() {
        out.extend(packages_in(&ancestor.join("vendor")));
    }
    let homes = [
        env::var_os("CARGO_HOME").map(PathBuf::from),
        env::var_os("HOME").map(|h| Path::new(&h).join(".cargo")),
    ];
    for home in homes.into_iter().flatten() {
        let src = home.join("registry").join("src");
        places.push(format!("{}/*/mavlink-0.21.*", src.display()));
        let Ok(indexes) = fs::read_dir(&src) else { continue };
        for index in indexes.flatten() {
            out.extend(packages_in(&index.path()));
        }
    }
    (out, places)
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

/// The digest of the first folder holding the XML, and that folder.
fn digest() -> Result<(String, String), String> {
    let (found, places) = candidates();
    let Some(dir) = found.iter().find(|d| d.join(ROOT).is_file()) else {
        return Err(format!(
            "the MAVLink definitions ({ROOT} in {REL} of the `mavlink` 0.21 package) were not \
             found. Searched:\n  {}\nSet VOUCH_MAV_DEFINITIONS to a folder holding {ROOT} and \
             its includes, or set VOUCH_MAV_NO_DEFAULT_DIALECT=1 to build without a default \
             dialect (every command then needs --dialect FILE.xml).",
            places.join("\n  ")
        ));
    };
    let mut files = Vec::new();
    collect(dir, ROOT, &mut files);
    let read = |name: &str| -> Result<String, String> {
        files
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, t)| t.clone())
            .ok_or_else(|| format!("include {name} not found"))
    };
    let origin = dir.display().to_string();
    let raw = raw::read_xml(ROOT, &read).map_err(|e| match e {
        raw::RawError::Read(e) => format!("{origin}: {e}"),
        raw::RawError::Xml { file, line, col, message } => {
            format!("{origin}/{file}:{line}:{col}: {message}")
        }
        raw::RawError::Message { file, message, problem, .. } => {
            format!("{origin}/{file}: message {message}: {problem}")
        }
    })?;
    let digest = raw::write_digest(&raw)
        .ok_or_else(|| format!("{origin}: a name in the definitions cannot be digested"))?;
    Ok((digest, origin))
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=src/dialect/raw.rs");
    println!("cargo:rerun-if-env-changed=VOUCH_MAV_DEFINITIONS");
    println!("cargo:rerun-if-env-changed=VOUCH_MAV_NO_DEFAULT_DIALECT");
    let (digest, origin) = if env::var("VOUCH_MAV_NO_DEFAULT_DIALECT").is_ok_and(|v| v == "1") {
        println!(
            "cargo:warning=vouch-mav: built without a default dialect (VOUCH_MAV_NO_DEFAULT_DIALECT=1)"
        );
        (String::new(), "none".to_string())
    } else {
        match digest() {
            Ok(found) => found,
            Err(why) => {
                eprintln!("error: vouch-mav: {why}");
                std::process::exit(1);
            }
        }
    };
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
