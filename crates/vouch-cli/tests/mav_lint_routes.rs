//! `vouch mav lint`'s route check as a user runs it: a protocol that guards the parachute
//! release on COMMAND_LONG alone gets a located warning (`mav::R001`) for each carrier it leaves
//! open, the exit status stays 0, `--json` lists them; the standard library lints clean, alone
//! and beside that protocol.

mod common;

use std::path::{Path, PathBuf};

use common::{code, vouch};
use vouch_mav::dialect::Dialect;

const ONE_CARRIER: &str = "\
// the parachute release, checked on COMMAND_LONG only
protocol chute_on_command_long {
  roles gcs, uav;
  gcs -> uav : COMMAND_LONG when command == MAV_CMD_DO_PARACHUTE && uint16(param1) == PARACHUTE_RELEASE
    where vehicle.armed;
}
";

/// The crafted protocol in a file; `None` (a skip) without the default dialect.
fn crafted() -> Option<PathBuf> {
    if let Err(e) = Dialect::default_dialect() {
        return vouch_testkit::missing(
            vouch_testkit::Need::Shared,
            &format!("no default dialect ({e})"),
        );
    }
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mav_lint_routes");
    std::fs::create_dir_all(&dir).expect("tmp dir");
    let p = dir.join("chute.vproto");
    std::fs::write(&p, ONE_CARRIER).expect("write");
    Some(p)
}

#[test]
fn lint_warns_about_each_carrier_left_open_located_in_the_protocol() {
    let Some(p) = crafted() else { return };
    let file = p.to_str().expect("utf-8");
    let o = vouch(&["--message-format", "short", "mav", "lint", file]);
    assert_eq!(code(&o), 0, "warnings do not reject the file");
    let err = String::from_utf8_lossy(&o.stderr);
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 3, "{err}");
    for (line, carrier) in lines.iter().zip(["COMMAND_INT", "MISSION_ITEM", "MISSION_ITEM_INT"]) {
        assert!(
            line.starts_with(&format!("{file}:4:3: warning[mav::R001]: MAV_CMD_DO_PARACHUTE")),
            "{line}"
        );
        assert!(
            line.contains(&format!("on route {carrier} carrying MAV_CMD_DO_PARACHUTE")),
            "{line}"
        );
    }
    let o = vouch(&["mav", "lint", file, "--json", "-q"]);
    assert_eq!(code(&o), 0);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let open: Vec<&str> = v["unguarded_routes"]
        .as_array()
        .expect("unguarded_routes")
        .iter()
        .map(|r| r["message"].as_str().unwrap_or(""))
        .collect();
    assert_eq!(open, ["COMMAND_INT", "MISSION_ITEM", "MISSION_ITEM_INT"]);
}

#[test]
fn the_standard_library_lints_clean_alone_and_beside_a_partial_guard() {
    let Some(p) = crafted() else { return };
    let o = vouch(&["--message-format", "short", "mav", "lint"]);
    assert_eq!(code(&o), 0);
    assert_eq!(String::from_utf8_lossy(&o.stderr), "", "no warning for the standard library");
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("ok: effect parachute_release (25 routes, every route guarded)"), "{out}");
    let file = p.to_str().expect("utf-8");
    let o = vouch(&["--message-format", "short", "mav", "lint", "--with-stdlib", file]);
    assert_eq!(code(&o), 0);
    assert_eq!(String::from_utf8_lossy(&o.stderr), "", "the library covers the open carriers");
    let o = vouch(&["mav", "lint", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let routes = v["effects"][0]["routes"].as_array().expect("routes");
    assert_eq!(routes.len(), 25);
    assert!(routes.iter().all(|r| !r["guarded_by"].as_array().unwrap().is_empty()), "{v}");
}
