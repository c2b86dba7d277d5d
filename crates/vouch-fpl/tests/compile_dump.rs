//! `vouch fpl compile --dump`: the dump (Paparazzi's `flight_plan.xml`) is byte-identical with
//! the one upstream's `dump_flight_plan` wrote for every corpus plan
//! (`../shared/fpl/upstream/dumps/REL.xml`): same elements, attributes in the same order, same
//! text, same layout.

mod common;

use std::path::Path;

use rayon::prelude::*;
use vouch_fpl::emit::dump::dump;
use vouch_fpl::front::parse_file;

fn first_difference(ours: &str, theirs: &str) -> String {
    let (a, b): (Vec<&str>, Vec<&str>) = (ours.lines().collect(), theirs.lines().collect());
    for i in 0..a.len().max(b.len()) {
        if a.get(i) != b.get(i) {
            return format!(
                "line {}:\n    vouch:    {:?}\n    upstream: {:?}",
                i + 1,
                a.get(i),
                b.get(i)
            );
        }
    }
    "the final newline differs".into()
}

#[test]
fn every_corpus_dump_is_byte_identical_with_upstream() {
    let Some(corpus) = common::corpus_dir() else { return };
    let Some(upstream) = vouch_testkit::shared("fpl/upstream", "INDEX.tsv") else { return };
    let plans = common::corpus_plans(&corpus);
    assert_eq!(plans.len(), 104);
    let failures: Vec<String> = plans
        .par_iter()
        .filter_map(|p| {
            let rel = p.strip_prefix(&corpus).ok()?.to_string_lossy().to_string();
            let want = std::fs::read_to_string(upstream.join("dumps").join(&rel)).ok()?;
            let got = parse_file(p)
                .map_err(|d| d.listing())
                .and_then(|plan| dump(&plan).map_err(|e| e.to_string()));
            match got {
                Ok(g) if g == want => None,
                Ok(g) => Some(format!("{rel}: {}", first_difference(&g, &want))),
                Err(e) => Some(format!("{rel}: {e}")),
            }
        })
        .collect();
    assert!(
        failures.is_empty(),
        "{} of 104 dumps differ:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn demo_dump_numbers_blocks_and_stages_and_indexes_them() {
    let demo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/fpl/demo.xml");
    let text = dump(&parse_file(&demo).expect("demo parses")).expect("dumps");
    assert!(text.starts_with("<dump>\n  <flight_plan "), "{text}");
    // "Wait GPS": set (0), while (test 1, loop-back 2): the while carries its test stage.
    assert!(text.contains("<while cond=\"!GpsFixValid()\" no=\"1\"/>"), "{text}");
    assert!(text.contains("<stage block=\"0\" block_name=\"Wait GPS\" stage=\"1\">"), "{text}");
    assert!(text.contains("<block name=\"HOME\" no="), "{text}");
    assert!(text.ends_with("  </stages>\n</dump>\n"), "{text}");
}
