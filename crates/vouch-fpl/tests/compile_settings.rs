//! The settings made from a plan's variables (`settings.xml` and `settings.h`) are
//! byte-identical with the ones upstream's `gen_aircraft` wrote for the 28 corpus plans that have
//! settings (`../shared/fpl/upstream/settings/`), and the other plans have none.

mod common;

use vouch_fpl::emit::settings::settings;
use vouch_fpl::front::parse_file;

#[test]
fn settings_of_every_corpus_plan_match_upstream() {
    let Some(corpus) = common::corpus_dir() else { return };
    let Some(upstream) = vouch_testkit::shared("fpl/upstream", "INDEX.tsv") else { return };
    let mut with_settings = 0;
    let mut failures = Vec::new();
    for p in common::corpus_plans(&corpus) {
        let rel = p.strip_prefix(&corpus).expect("in corpus").to_string_lossy().to_string();
        let stem = rel.trim_end_matches(".xml");
        let plan = parse_file(&p).expect("parses");
        let s = settings(&plan, "v7.0_unstable").expect("settings");
        let xml = std::fs::read_to_string(upstream.join(format!("settings/{stem}.xml")));
        let h = std::fs::read_to_string(upstream.join(format!("settings/{stem}.h")));
        match (xml, h) {
            (Ok(xml), Ok(h)) => {
                with_settings += 1;
                if s.xml != xml {
                    failures.push(format!("{rel}: settings.xml differs"));
                }
                if s.header != h {
                    failures.push(format!("{rel}: settings.h differs"));
                }
            }
            _ if s.count > 0 => {
                failures.push(format!("{rel}: {} settings, upstream none", s.count))
            }
            _ => {}
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert_eq!(with_settings, 28);
}
