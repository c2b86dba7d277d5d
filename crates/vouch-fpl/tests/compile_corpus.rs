//! The compiler on the whole corpus: every plan upstream compiles, vouch compiles; the
//! instrumented flavour maps back to the drop-in text; known upstream values.

mod common;

use common::{corpus_dir, corpus_plans};
use vouch_fpl::emit::{EmitOptions, Flavor, unwrap_instrumented};
use vouch_fpl::pipeline::compile_file;

#[test]
fn every_upstream_compilable_plan_compiles_and_instrumentation_is_faithful() {
    let Some(dir) = corpus_dir() else { return };
    let plans = corpus_plans(&dir);
    assert_eq!(plans.len(), 104, "INDEX.tsv lists 104 plans upstream compiles");
    let mut failures = Vec::new();
    for p in &plans {
        let opts = EmitOptions { source_path: "plan.xml".into(), ..EmitOptions::default() };
        let dropin = match compile_file(p, &opts) {
            Ok(h) => h,
            Err(e) => {
                failures.push(format!("{}: {}", p.display(), e.listing()));
                continue;
            }
        };
        let inst = compile_file(p, &EmitOptions { flavor: Flavor::Instrumented, ..opts.clone() })
            .expect("same plan");
        let plan = vouch_fpl::front::parse_file(p).expect("parsed above");
        let back = unwrap_instrumented(&inst, plan.header.as_ref().map(|h| h.text.as_str()));
        assert!(
            back == dropin,
            "{}: instrumented header does not unwrap to the drop-in header",
            p.display()
        );
    }
    assert!(failures.is_empty(), "{} plans failed:\n{}", failures.len(), failures.join("\n"));
}

#[test]
fn demo_compiles() {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/fpl/demo.xml");
    let h =
        compile_file(&p, &EmitOptions::default()).map_err(|e| e.listing()).expect("demo compiles");
    assert!(h.contains("static inline void auto_nav(void) {"), "the demo header defines auto_nav");
}
