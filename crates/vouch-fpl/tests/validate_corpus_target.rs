//! Translation validation of every corpus plan on the emulated Cortex-M4 (`arm-none-eabi-gcc`
//! with a Paparazzi STM32F4 build's flags, QEMU `mps2-an386`): the fixpoint on every plan, no
//! disagreement, and the comparison constants read as on the host. The figures are printed for
//! information only; time is measured by the benchmark (`benches/validate_target.rs`).

mod common;

use vouch_fpl::evidence::validate::{Options, Target};

#[test]
fn every_corpus_plan_validates_to_the_fixpoint_on_cortex_m4() {
    if vouch_testkit::program("arm-none-eabi-gcc", "--version").is_none()
        || vouch_testkit::program("qemu-system-arm", "--version").is_none()
    {
        return;
    }
    let opts = Options {
        target: Target::CortexM4,
        random_runs: 1,
        random_steps: 100,
        ..Options::default()
    };
    let Some(results) = common::validate_corpus(&opts) else { return };
    let mut failures = Vec::new();
    let (mut states, mut transitions, mut constants) = (0, 0, 0);
    for (name, r) in &results {
        match r {
            Ok(rep) => {
                states += rep.states;
                transitions += rep.transitions;
                constants += rep.constants.len();
                if !rep.fixpoint {
                    failures.push(format!("{name}: no fixpoint ({:?})", rep.cut));
                }
                if let Some(cx) = &rep.counterexample {
                    failures.push(format!("{name}: {}", cx.render()));
                }
                if !rep.constant_differences().is_empty() {
                    failures.push(format!("{name}: constants differ: {:?}", rep.constants));
                }
            }
            Err(e) => failures.push(format!("{name}: {e}")),
        }
    }
    eprintln!(
        "cortex-m4: {} plans to the fixpoint, {states} states, {transitions} transitions, {constants} comparison constants read as on the host",
        results.len() - failures.len()
    );
    assert!(failures.is_empty(), "{} failures:\n{}", failures.len(), failures.join("\n"));
}
