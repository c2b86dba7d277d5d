//! Translation validation of the crafted plans (forbidden deroutes, ping-pong) and the static
//! bound of a plan whose bound is computed by hand.

use std::path::Path;

use vouch_fpl::evidence::validate::{Options, validate};

fn plan(name: &str) -> vouch_fpl::ast::FlightPlan {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/evidence_plans").join(name);
    vouch_fpl::front::parse_file(&p).expect("crafted plan parses")
}

#[test]
fn crafted_plans_validate() {
    let Some(_cc) = vouch_testkit::c_compiler() else { return };
    for name in
        ["pingpong.xml", "forbidden.xml", "mutation.xml", "lint_misc.xml", "wcet.xml", "deep.xml"]
    {
        let r = validate(
            &plan(name),
            &Options { random_runs: 2, random_steps: 300, ..Options::default() },
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(r.passed(), "{name}: {:?}", r.counterexample);
        assert!(r.cut.is_none() && r.fixpoint, "{name}");
        assert!(r.max_events_seen <= r.bound.max_events);
    }
}

#[test]
fn hand_computed_bound() {
    let fp = vouch_fpl::passes::lower::lower(&plan("wcet.xml")).expect("lowers");
    let b = vouch_fpl::evidence::wcet::bound(&fp);
    let seq = &b.blocks[0];
    assert_eq!(seq.name, "Seq");
    // from stage 0: set, set, set, call_once, deroute = 5 stage items in one call;
    // events: 1 global exception condition + 4 statements (the deroute has no hooks)
    assert_eq!((seq.stages, seq.events), (5, 5));
    let lp = &b.blocks[1];
    // Loop: while test (1 cond) exits past the loop-back to the end of block (NextBlock):
    // starting at the loop-back: loop-back, test, default = 3 items; events 1 + 1 (global)
    // or, starting at set: set (1), loop-back, test (1), default = 4 items, 3 events
    assert_eq!((lp.stages, lp.events), (4, 3));
}

#[test]
fn upstreams_exceeding_time_text_is_a_disagreement_with_the_semantics() {
    use vouch_fpl::emit::{EmitOptions, Flavor, compile_plan};
    use vouch_fpl::evidence::validate::validate_header;
    let Some(_cc) = vouch_testkit::c_compiler() else { return };
    let xml = r#"<flight_plan name="t" lat0="43.46" lon0="1.27" alt="200" ground_alt="150" security_height="25" max_dist_from_home="1000">
<waypoints><waypoint name="HOME" x="0" y="0"/><waypoint name="A" x="10" y="0"/></waypoints>
<blocks><block name="b"><go wp="A" exceeding_time="a+b"/></block></blocks></flight_plan>"#;
    let p = vouch_fpl::front::parse_str("t.xml", xml).expect("parses");
    let fp = vouch_fpl::passes::lower::lower(&p).expect("lowers");
    let opts = Options { random_runs: 1, random_steps: 50, ..Options::default() };
    let header = |upstream_compat| {
        let eo =
            EmitOptions { flavor: Flavor::Instrumented, upstream_compat, ..EmitOptions::default() };
        compile_plan(&p, &eo).expect("compiles")
    };
    // The default output is what the semantics means.
    assert!(validate_header(&fp, &header(false), &opts).expect("runs").passed());
    // Upstream's -a+b is not -(a+b): the validation reports it instead of passing.
    let r = validate_header(&fp, &header(true), &opts).expect("runs");
    assert!(!r.passed(), "the compat header's approach test differs from the semantics");
    let cx = format!("{:?}", r.counterexample.expect("a counterexample"));
    assert!(cx.contains("-a+b"), "{cx}");
}

/// The build directory is private and fresh: a directory planted at the name the validator
/// once used (`$TMPDIR/vouch-fpl-validate-<pid>-<n>`, accepted when it existed) is ignored,
/// and nothing in it runs.
#[test]
fn a_planted_build_directory_is_never_used() {
    use std::os::unix::fs::PermissionsExt;
    let Some(_cc) = vouch_testkit::c_compiler() else { return };
    let planted = std::env::temp_dir().join(format!("vouch-fpl-validate-{}-0", std::process::id()));
    let marker = planted.join("ran");
    std::fs::create_dir_all(&planted).expect("plant");
    let evil = "#!/bin/sh\ntouch \"$(dirname \"$0\")/ran\"\n";
    for name in ["driver", "cc"] {
        std::fs::write(planted.join(name), evil).expect("plant");
        std::fs::set_permissions(planted.join(name), std::fs::Permissions::from_mode(0o755))
            .expect("chmod");
    }
    let r = validate(
        &plan("mutation.xml"),
        &Options { random_runs: 1, random_steps: 50, ..Options::default() },
    )
    .expect("validates");
    assert!(r.passed() && r.fixpoint);
    assert!(!marker.exists(), "a program of the planted directory ran");
    std::fs::remove_dir_all(&planted).expect("clean up");
}

/// The driver's directory is made private (mode 0700) under an unpredictable name, differs
/// from build to build, and is gone once the driver is.
#[test]
fn the_build_directory_is_private_unpredictable_and_removed() {
    use std::os::unix::fs::PermissionsExt;
    use vouch_fpl::evidence::cdriver::{Driver, Limits, Target};
    let Some(_cc) = vouch_testkit::c_compiler() else { return };
    let p = plan("mutation.xml");
    let h = vouch_fpl::emit::compile_plan(
        &p,
        &vouch_fpl::emit::EmitOptions {
            flavor: vouch_fpl::emit::Flavor::Instrumented,
            ..Default::default()
        },
    )
    .expect("compiles");
    let limits = Limits { leaf_budget: 100, question_limit: 100, values: (-128, 127) };
    let a = Driver::build(&h, limits, Target::Host, None).expect("builds");
    let b = Driver::build(&h, limits, Target::Host, None).expect("builds");
    let (da, db) = (a.build_dir().to_path_buf(), b.build_dir().to_path_buf());
    assert_ne!(da, db);
    for d in [&da, &db] {
        let mode = std::fs::metadata(d).expect("exists").permissions().mode() & 0o777;
        assert_eq!(mode, 0o700, "{}", d.display());
        let name = d.file_name().and_then(|n| n.to_str()).expect("name");
        let pid_form = format!("vouch-fpl-validate-{}-", std::process::id());
        assert!(name.starts_with("vouch-fpl-validate-") && !name.starts_with(&pid_form), "{name}");
    }
    drop(a);
    drop(b);
    assert!(!da.exists() && !db.exists());
}

/// Plan variables of every declaration form (arrays with brace initialisers, pointers, a
/// pointer to function, qualifiers) compile in the validation header and are found as C state.
#[test]
fn array_and_pointer_variables_validate_to_the_fixpoint() {
    let Some(_cc) = vouch_testkit::c_compiler() else { return };
    let r = validate(
        &plan("arrays.xml"),
        &Options { random_runs: 2, random_steps: 300, ..Options::default() },
    )
    .unwrap_or_else(|e| panic!("arrays.xml: {e}"));
    assert!(r.passed(), "{:?}", r.counterexample);
    assert!(r.fixpoint && r.cut.is_none());
    for v in ["buf", "grid", "names", "target", "on_done", "count", "laps"] {
        assert!(r.abstracted.c_variables.iter().any(|c| c == v), "{v} is C state");
    }
}

/// Plan variables whose types the validation build does not have (structures, unions, enums
/// and typedef names of module headers, with qualifiers, pointers and arrays of them; `const`
/// variables in read-only storage) compile with opaque stand-ins and are C state.
#[test]
fn variables_of_types_from_module_headers_validate_to_the_fixpoint() {
    let Some(_cc) = vouch_testkit::c_compiler() else { return };
    let r = validate(
        &plan("decls.xml"),
        &Options { random_runs: 2, random_steps: 300, ..Options::default() },
    )
    .unwrap_or_else(|e| panic!("decls.xml: {e}"));
    assert!(r.passed(), "{:?}", r.counterexample);
    assert!(r.fixpoint && r.cut.is_none());
    for v in ["target_pos", "corners", "origin", "path", "current", "survey", "gain", "table"] {
        assert!(r.abstracted.c_variables.iter().any(|c| c == v), "{v} is C state");
    }
    for v in ["mode", "raw", "count", "width", "rows"] {
        assert!(r.abstracted.c_variables.iter().any(|c| c == v), "{v} is C state");
    }
}

/// A call with 33,151 paths (two loops in a row bounded by plan variables, see the plan): the
/// 129 runs that leave the first loop at once join at the second loop's start, the 129 that
/// leave the second at the deroute after it, so the call takes 511 runs (255 to the end of the
/// call, 256 joined); a budget below that cuts it and the report says exactly which state was
/// cut.
#[test]
fn a_plan_that_hit_the_former_path_cap_reaches_the_fixpoint() {
    let Some(_cc) = vouch_testkit::c_compiler() else { return };
    let p = plan("wide.xml");
    let small = Options { max_paths_per_call: 300, random_runs: 0, ..Options::default() };
    let cut = validate(&p, &small).expect("runs");
    assert!(cut.passed() && cut.incomplete() && !cut.fixpoint);
    assert_eq!(cut.cut_states, ["block 0 'Grid' stage 0"]);
    assert!(cut.render("wide.xml").contains("NOT ESTABLISHED for the whole plan: 1 state(s) cut"));
    let r = validate(&p, &Options { random_runs: 1, random_steps: 100, ..Options::default() })
        .expect("runs");
    assert!(r.passed(), "{:?}", r.counterexample);
    assert!(r.fixpoint && !r.incomplete() && r.cut_states.is_empty());
    eprintln!("wide.xml: {} states, {} transitions, {:.2} s", r.states, r.transitions, r.seconds);
}

/// The walk of the interpreter alone, every path of every call run to its end (the model
/// checker's walk), with the validator's views and operator jumps: (states, transitions).
fn unjoined(p: &vouch_fpl::ast::FlightPlan) -> (usize, u128) {
    use vouch_fpl::semantics::space::{Alone, Space, SpaceOptions, explore};
    let fp = vouch_fpl::passes::lower::lower(p).expect("lowers");
    let opts = SpaceOptions { max_paths_per_call: 10_000_000, ..SpaceOptions::default() };
    let w = explore(&mut Space::new(&fp, opts), &mut Alone).expect("walks");
    assert!(w.fixpoint);
    (w.nodes.len(), w.transitions)
}

/// Joining runs loses nothing: the validator reaches exactly the states of the walk that runs
/// every path to its end, and counts the same transitions.
#[test]
fn joined_runs_cover_every_path() {
    let Some(_cc) = vouch_testkit::c_compiler() else { return };
    for name in ["wide.xml", "symbolic.xml", "deep.xml", "arrays.xml", "decls.xml", "wcet.xml"] {
        let p = plan(name);
        let r = validate(&p, &Options { random_runs: 0, ..Options::default() })
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(r.passed() && r.fixpoint, "{name}: {:?}", r.counterexample);
        assert_eq!((r.states, r.transitions), unjoined(&p), "{name}");
    }
}

/// Plans whose calls have exponentially many paths (chains of loops each left at once for
/// most values of its bound) reach the fixpoint: the number of paths of the first call,
/// derived by hand in each plan's comment, is what the validator reports it compared.
#[test]
fn exploding_plans_reach_the_fixpoint() {
    let Some(_cc) = vouch_testkit::c_compiler() else { return };
    // explode_loops.xml: 8 loops, 127 of the 256 values of a bound enter the loop (the call
    // ends there), 129 leave it at once; plus the 2 operator jumps of the initial state
    let loops: u128 = 127 * (0..8).map(|k| 129u128.pow(k)).sum::<u128>() + 129u128.pow(8) + 2;
    // explode_ranges.xml: 3 loops, of the 65,536 (first, last) pairs 32,640 have first > last
    let (s, e) = (32_640u128, 32_896u128);
    let ranges = e * (1 + s + s * s) + s.pow(3) + 2;
    for (name, first_call) in [("explode_loops.xml", loops), ("explode_ranges.xml", ranges)] {
        let p = plan(name);
        let one = Options { depth: Some(1), random_runs: 0, ..Options::default() };
        let r = validate(&p, &one).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(r.passed() && !r.incomplete(), "{name}: {:?}", r.counterexample);
        assert_eq!(r.transitions, first_call, "{name}");
    }
    let p = plan("explode_loops.xml");
    let r = validate(&p, &Options { random_runs: 1, random_steps: 200, ..Options::default() })
        .expect("runs");
    assert!(r.passed() && r.fixpoint, "{:?}", r.counterexample);
    assert!(r.runs < 100_000, "{} runs", r.runs);
    eprintln!(
        "explode_loops.xml: {} states, {} transitions, {} runs, {:.2} s",
        r.states, r.transitions, r.runs, r.seconds
    );
}
