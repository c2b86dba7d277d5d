//! Translation validation on an emulated Cortex-M core (`--target cortex-m4|cortex-m7`): the
//! instrumented header and the driver built by `arm-none-eabi-gcc` with the flags of a
//! Paparazzi STM32 build, run by QEMU. The walk is the host's: the same states and transitions
//! must come out; a generated header that only the ARM build gets wrong is caught there and not
//! on the host; a build that rounds the plan's comparison constants differently is reported.
//!
//! Needs the cross compiler and the emulator (`scripts/install-peers.sh`): skipped with a
//! message when absent, a failure under `VOUCH_REQUIRE_PEERS=1`.

use std::path::Path;

use vouch_fpl::emit::{EmitOptions, Flavor, compile_plan};
use vouch_fpl::evidence::validate::{Options, Target, validate, validate_header};

fn peers() -> Option<()> {
    vouch_testkit::program("arm-none-eabi-gcc", "--version")?;
    vouch_testkit::program("qemu-system-arm", "--version")?;
    vouch_testkit::c_compiler()?;
    Some(())
}

fn plan(name: &str) -> vouch_fpl::ast::FlightPlan {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/evidence_plans").join(name);
    vouch_fpl::front::parse_file(&p).expect("crafted plan parses")
}

fn on(target: Target) -> Options {
    Options { target, random_runs: 1, random_steps: 200, ..Options::default() }
}

fn header(p: &vouch_fpl::ast::FlightPlan) -> String {
    compile_plan(p, &EmitOptions { flavor: Flavor::Instrumented, ..EmitOptions::default() })
        .expect("compiles")
}

/// `mutation.xml` lowered, and its instrumented header with the code of its `set` stage
/// (`mode = 1`, run in call 1) replaced by `code`.
fn mutation_with(code: &str) -> (vouch_fpl::passes::fp::Fp, String) {
    let p = plan("mutation.xml");
    let fp = vouch_fpl::passes::lower::lower(&p).expect("lowers");
    let h = header(&p);
    let mutated = h.replacen("FP_X(\"mode = 1\");", code, 1);
    assert_ne!(mutated, h);
    (fp, mutated)
}

/// Every crafted plan, the declaration forms and a call with 10^17 paths included, reaches the
/// fixpoint on both cores, over exactly the host's states and transitions.
#[test]
fn crafted_plans_validate_on_the_cortex_m_cores() {
    let Some(()) = peers() else { return };
    for name in [
        "arrays.xml",
        "decls.xml",
        "deep.xml",
        "symbolic.xml",
        "pingpong.xml",
        "mutation.xml",
        "wide.xml",
        "explode_loops.xml",
    ] {
        let p = plan(name);
        let host = validate(&p, &on(Target::Host)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(host.passed() && host.fixpoint, "{name} on the host: {:?}", host.counterexample);
        for target in [Target::CortexM4, Target::CortexM7] {
            let r = validate(&p, &on(target)).unwrap_or_else(|e| panic!("{name} {target}: {e}"));
            assert!(r.passed(), "{name} on {target}: {:?}", r.counterexample);
            assert!(r.fixpoint && r.cut.is_none(), "{name} on {target}");
            assert_eq!((r.states, r.transitions), (host.states, host.transitions), "{name}");
            assert_eq!(r.second_runs, host.second_runs, "{name}: same changed-state runs");
            assert!(r.built.contains("arm-none-eabi-gcc") && r.built.contains("mps2-an"));
            assert!(r.abstracted.watched_bytes.is_some(), "{name}: static storage watched");
            assert!(r.constant_differences().is_empty(), "{name}: {:?}", r.constants);
        }
    }
}

/// A generator that declared the loop counters as plain `char`: on x86-64 `char` is signed,
/// like `int8_t`, so the host build behaves as the semantics says; with the ARM EABI `char`
/// is unsigned, a negative bound (the plan variable `laps`, every `int8_t` value tried) wraps
/// to 255 and the loop runs where it must not. Only the target build catches it.
#[test]
fn a_counter_type_bug_only_the_arm_build_has_is_caught_there_and_not_on_the_host() {
    let Some(()) = peers() else { return };
    let p = plan("symbolic.xml");
    let fp = vouch_fpl::passes::lower::lower(&p).expect("lowers");
    let h = header(&p);
    assert!(h.contains("static int8_t _var_n;") && h.contains("static int8_t _var_n_to;"));
    let mutated = h.replace("static int8_t _var_n", "static char _var_n");
    let host = validate_header(&fp, &mutated, &on(Target::Host)).expect("host build");
    assert!(host.passed() && host.fixpoint, "the host cannot see it: {:?}", host.counterexample);
    for target in [Target::CortexM4, Target::CortexM7] {
        let r = validate_header(&fp, &mutated, &on(target)).expect("target build");
        let cx = r.counterexample.unwrap_or_else(|| panic!("{target} must catch it"));
        assert_eq!(cx.target, target.name());
        assert!(cx.render().contains(&format!("found on: {target}")));
        // call 1 enters the loop with a bound the oracle chose: the first negative one
        // answered (-1, answer number -2) already runs the body on the target
        assert_eq!(cx.calls, 1, "{}", cx.render());
        assert!(cx.answers.iter().any(|a| *a < 0), "a negative bound: {:?}", cx.answers);
    }
}

/// Paparazzi's flags keep C's double constants; `-fsingle-precision-constant` (ChibiOS's own
/// default, which Paparazzi's rules comment out) makes `10.3` a float. The walk still agrees
/// (conditions are free), and the report says where host and target differ.
#[test]
fn a_build_that_rounds_constants_to_float_is_reported() {
    let Some(()) = peers() else { return };
    let xml = r#"<flight_plan name="c" lat0="43.46" lon0="1.27" alt="200" ground_alt="150" security_height="25" max_dist_from_home="1000">
<waypoints><waypoint name="HOME" x="0" y="0"/><waypoint name="A" x="10" y="0"/></waypoints>
<exceptions><exception cond="GetPosAlt() > ground_alt + 10.3" deroute="HOME"/></exceptions>
<blocks><block name="b"><go wp="A" until="stage_time > 2.5"/></block></blocks></flight_plan>"#;
    let p = vouch_fpl::front::parse_str("c.xml", xml).expect("parses");
    let m4 = validate(&p, &on(Target::CortexM4)).expect("runs");
    assert!(m4.passed() && m4.fixpoint);
    let texts: Vec<&str> = m4.constants.iter().map(|c| c.text.as_str()).collect();
    // as the generated C writes them (upstream's printer: `%f`)
    assert_eq!(texts, ["10.300000", "2.500000"]);
    assert!(m4.constant_differences().is_empty(), "Paparazzi's flags: {:?}", m4.constants);
    let mut flags = Target::CortexM4.default_cflags();
    flags.push("-fsingle-precision-constant".into());
    let single = Options { cflags: Some(flags), ..on(Target::CortexM4) };
    let r = validate(&p, &single).expect("runs");
    assert!(r.passed() && r.fixpoint, "conditions are free: the walk agrees");
    let d = r.constant_differences();
    assert_eq!(d.len(), 1, "2.5 is exact in float: {:?}", r.constants);
    assert_eq!((d[0].text.as_str(), d[0].host), ("10.300000", 10.3));
    assert_eq!(d[0].compiled, f64::from(10.3f32));
    assert!(r.render("c.xml").contains("HOST AND CORTEX-M4 DIFFER on 1 of 2"));
}

/// A fault of the ARM core (a store to an unmapped address) is a crash on its path, like a
/// signal on the host, and the emulator is restarted.
#[test]
fn a_fault_on_the_target_is_reported_on_its_path() {
    let Some(()) = peers() else { return };
    let (fp, mutated) = mutation_with("*(volatile int *)0xF0000000u = 0;");
    let r = validate_header(&fp, &mutated, &on(Target::CortexM4)).expect("builds");
    let cx = r.counterexample.expect("caught");
    assert!(cx.what.contains("died (status 139)"), "{}", cx.what);
    assert_eq!((cx.calls, cx.target.as_str()), (1, "cortex-m4"));
    assert!(r.abstracted.restarts >= 1);
}

/// A call that never returns and asks nothing (a loop the question limit cannot stop) is ended
/// by the core's SysTick time limit, like `alarm` on the host: a crash with status 142 on its
/// path. The limit is shortened to 2 s through `--cflags` (`-DVOUCH_ALARM_SECONDS=2`).
#[test]
fn a_hang_on_the_target_is_ended_by_the_time_limit() {
    let Some(()) = peers() else { return };
    let (fp, mutated) = mutation_with("for (;;) { __asm volatile (\"\"); }");
    let mut flags = Target::CortexM4.default_cflags();
    flags.push("-DVOUCH_ALARM_SECONDS=2".into());
    let o = Options { cflags: Some(flags), random_runs: 0, ..on(Target::CortexM4) };
    let r = validate_header(&fp, &mutated, &o).expect("builds");
    let cx = r.counterexample.expect("caught");
    assert!(cx.what.contains("died (status 142)"), "{}", cx.what);
    assert_eq!(cx.calls, 1);
}
