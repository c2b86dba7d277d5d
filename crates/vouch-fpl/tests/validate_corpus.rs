//! Translation validation on the corpus: for every plan upstream compiles, the compiled
//! `auto_nav` (instrumented header + stub runtime, built with the system `cc`) and the
//! reference interpreter agree on every path of the first 8 calls (exhaustive over condition
//! answers, states merged) and on seeded random runs.

mod common;

use rayon::prelude::*;
use std::time::Instant;
use vouch_fpl::evidence::validate::{validate, Options};

#[test]
fn every_corpus_plan_validates_at_depth_8() {
    let Some(_cc) = common::c_compiler() else { return };
    let Some(dir) = common::corpus_dir() else { return };
    let plans = common::corpus_plans(&dir);
    assert_eq!(plans.len(), 104);
    let t0 = Instant::now();
    let opts = Options { depth: 8, random_runs: 3, random_steps: 300, ..Options::default() };
    let results: Vec<(String, Result<vouch_fpl::evidence::validate::Report, String>)> = plans
        .par_iter()
        .map(|p| {
            let name = p.strip_prefix(&dir).unwrap_or(p).display().to_string();
            let r = vouch_fpl::front::parse_file(p)
                .map_err(|d| d.listing())
                .and_then(|plan| validate(&plan, &opts).map_err(|e| e.to_string()));
            (name, r)
        })
        .collect();
    let mut failures = Vec::new();
    let (mut states, mut paths, mut random, mut cut, mut covered) = (0, 0, 0, 0, 0.0);
    for (name, r) in &results {
        match r {
            Ok(rep) => {
                states += rep.states;
                paths += rep.call_paths;
                random += rep.random_calls;
                covered += rep.runs_covered;
                assert!(rep.runs_covered >= 1.0, "{name}: covers at least one run");
                if rep.cut.is_some() {
                    cut += 1;
                    failures.push(format!("{name}: exploration cut: {:?}", rep.cut));
                }
                if let Some(cx) = &rep.counterexample {
                    failures.push(format!("{name}: {cx:?}"));
                }
                assert!(rep.max_events_seen <= rep.bound.max_events, "{name}: bound");
            }
            Err(e) => failures.push(format!("{name}: {e}")),
        }
    }
    eprintln!(
        "validate: {} plans, depth 8, {states} states, {paths} call paths compared (covering {covered:.3e} complete 8-call runs), {random} random calls, {cut} cut, {:.1} s",
        results.len(),
        t0.elapsed().as_secs_f64()
    );
    assert!(failures.is_empty(), "{} failures:\n{}", failures.len(), failures.join("\n"));
}
