//! The *drop-in* header of the bundled demo (README's first command) compiles as it is with
//! `cc -std=c99 -Wall -Wextra -Werror` against the stub runtime plus a no-op navigation API
//! (`tests/stub/nav_api_stub.*`) and the demo's own functions (`tests/stub/demo/`), and runs.

mod common;

use std::path::Path;
use std::process::Command;

use vouch_fpl::emit::EmitOptions;
use vouch_fpl::pipeline::compile_file;

#[test]
fn demo_dropin_header_compiles_and_runs() {
    let Some(cc) = common::c_compiler() else { return };
    let plan = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/fpl/demo.xml");
    let header =
        compile_file(&plan, &EmitOptions::default()).map_err(|e| e.listing()).expect("compiles");
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("dropin_demo");
    std::fs::create_dir_all(&work).expect("tmp dir");
    std::fs::write(work.join("flight_plan.h"), header).expect("write header");
    let stub = common::stub_dir();
    let exe = work.join("demo");
    let out = Command::new(cc)
        .args(["-std=c99", "-Wall", "-Wextra", "-Werror"])
        .arg("-I")
        .arg(stub.join("include"))
        .arg("-I")
        .arg(stub.join("demo"))
        .arg("-I")
        .arg(&work)
        .arg(stub.join("fp_stub.c"))
        .arg(stub.join("nav_api_stub.c"))
        .arg(stub.join("demo/demo_main.c"))
        .arg("-o")
        .arg(&exe)
        .output()
        .expect("cc runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let run = Command::new(&exe).output().expect("demo runs");
    // GPS fix at once: block 0 ends in call 1 (next block Takeoff); in call 2 Takeoff's
    // exception (altitude 200 > 150 + 40) derouts to Standby (block 2), which then circles.
    assert_eq!(String::from_utf8_lossy(&run.stdout).trim(), "2 0");
}
