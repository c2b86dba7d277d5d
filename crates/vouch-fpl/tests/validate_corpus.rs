//! Translation validation on the corpus: for every plan upstream compiles, the compiled
//! `auto_nav` (instrumented header + stub runtime, built with the system `cc`) and the
//! reference interpreter agree on every call path and operator jump from every reachable state
//! pair (the walk reaches its fixpoint), and on seeded random runs.

mod common;

use std::collections::HashMap;
use std::time::Instant;
use vouch_fpl::evidence::validate::Options;

#[test]
fn every_corpus_plan_validates_to_the_fixpoint() {
    let Some(_cc) = common::c_compiler() else { return };
    let t0 = Instant::now();
    let opts = Options { random_runs: 3, random_steps: 300, ..Options::default() };
    let Some(results) = common::validate_corpus(&opts) else { return };
    let walks = unjoined_walks();
    let mut failures = Vec::new();
    let (mut states, mut transitions, mut second, mut random) = (0, 0, 0, 0);
    let (mut runs, mut joined) = (0, 0);
    let mut slowest: Vec<(f64, &str, usize, u128)> = Vec::new();
    for (name, r) in &results {
        match r {
            Ok(rep) => {
                states += rep.states;
                transitions += rep.transitions;
                second += rep.second_runs;
                runs += rep.runs;
                joined += rep.joined;
                random += rep.random_calls;
                slowest.push((rep.seconds, name, rep.states, rep.transitions));
                // joining the runs of a call at stage starts loses nothing: the states and
                // the transitions are those of the walk that runs every path to its end
                if walks.get(name) != Some(&(rep.states, rep.transitions)) {
                    failures.push(format!(
                        "{name}: {} states, {} transitions; every path run: {:?}",
                        rep.states,
                        rep.transitions,
                        walks.get(name)
                    ));
                }
                if !rep.fixpoint {
                    failures.push(format!("{name}: no fixpoint ({:?})", rep.cut));
                }
                if let Some(cx) = &rep.counterexample {
                    failures.push(format!("{name}: {}", cx.render()));
                }
                assert!(rep.second_runs >= rep.runs - rep.joined, "{name}: every run repeated");
                assert!(rep.max_events_seen <= rep.bound.max_events, "{name}: bound");
                assert!(rep.abstracted.watched_bytes.is_some(), "{name}: data segment watched");
            }
            Err(e) => failures.push(format!("{name}: {e}")),
        }
    }
    slowest.sort_by(|a, b| b.0.total_cmp(&a.0));
    eprintln!(
        "validate: {} plans to the fixpoint, {states} states, {transitions} transitions compared in {runs} runs ({joined} joined), {second} changed-state runs, {random} random calls, {:.1} s",
        results.len(),
        t0.elapsed().as_secs_f64()
    );
    for (s, name, st, tr) in slowest.iter().take(5) {
        eprintln!("  {name}: {st} states, {tr} transitions, {s:.2} s");
    }
    assert!(failures.is_empty(), "{} failures:\n{}", failures.len(), failures.join("\n"));
}

/// The interpreter's walk of every corpus plan with the validator's views and operator jumps,
/// every path of every call run to its end (the model checker's walk, which joins nothing):
/// corpus-relative name → (states, transitions).
fn unjoined_walks() -> HashMap<String, (usize, u128)> {
    use rayon::prelude::*;
    use vouch_fpl::semantics::space::{Alone, Space, SpaceOptions, explore};
    let Some(dir) = common::corpus_dir() else { return HashMap::new() };
    common::corpus_plans(&dir)
        .par_iter()
        .filter_map(|p| {
            let plan = vouch_fpl::front::parse_file(p).ok()?;
            let fp = vouch_fpl::passes::lower::lower(&plan).ok()?;
            let w = explore(&mut Space::new(&fp, SpaceOptions::default()), &mut Alone).ok()?;
            let name = p.strip_prefix(&dir).unwrap_or(p).display().to_string();
            Some((name, (w.nodes.len(), w.transitions)))
        })
        .collect()
}
