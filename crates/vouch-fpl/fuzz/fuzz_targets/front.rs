//! Fuzz target: the whole front end (tolerant pre-pass, roxmltree, includes, building,
//! resolution, diagnostics rendering) on arbitrary text must never panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data).into_owned();
    // A path in a directory that does not exist keeps includes from reaching real files.
    let path = std::path::Path::new("/nonexistent-vouch-fuzz/plan.xml");
    match vouch_fpl::front::parse_str_at(path, text, &vouch_fpl::front::Options::default()) {
        Ok(plan) => {
            let _ = vouch_fpl::ast::outline::outline(&plan);
        }
        Err(d) => {
            let _ = d.listing();
            let mut s = String::new();
            let _ = miette::GraphicalReportHandler::new().render_report(&mut s, &d);
        }
    }
});
