//! Snapshots of the drop-in header for a handful of corpus plans (and the bundled demo). Each
//! snapshot was reviewed against GENERATOR_FACTS.md (layout §4, stages §6-§7, exceptions and
//! sectors §8, numbers §10) before being accepted; a change shows up as a diff to review.

mod common;

use vouch_fpl::emit::EmitOptions;
use vouch_fpl::pipeline::compile_file;

fn snap(rel: &str) -> Option<String> {
    let dir = common::corpus_dir()?;
    let opts =
        EmitOptions { source_path: format!("conf/flight_plans/{rel}"), ..EmitOptions::default() };
    Some(compile_file(&dir.join(rel), &opts).map_err(|e| e.listing()).expect("compiles"))
}

macro_rules! snapshot_test {
    ($name:ident, $rel:expr_2021) => {
        #[test]
        fn $name() {
            let Some(h) = snap($rel) else { return };
            insta::assert_snapshot!(stringify!($name), h);
        }
    };
}

snapshot_test!(basic, "basic.xml");
snapshot_test!(versatile_for_loops, "versatile.xml");
snapshot_test!(emav2006_relative_waypoints, "competitions/EMAV2006.xml");
snapshot_test!(oneloop_cyberzoo_on_enter_exit, "tudelft/oneloop_cyberzoo.xml");
snapshot_test!(aggieair_includes, "AGGIEAIR/CachJct_Gallo_temp_rect_survey.xml");

#[test]
fn demo() {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/fpl/demo.xml");
    let opts =
        EmitOptions { source_path: "examples/fpl/demo.xml".into(), ..EmitOptions::default() };
    let h = compile_file(&p, &opts).map_err(|e| e.listing()).expect("demo compiles");
    insta::assert_snapshot!("demo", h);
}
