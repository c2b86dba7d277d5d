//! Fuzz target: Paparazzi's `conf/conf.xml` as `vouch fpl aircraft` reads it — any text is an
//! aircraft or a typed error, never a panic; and a plan's dump and settings never panic either.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(ac) =
        vouch_fpl::aircraft::find_in(&text, Path::new("conf.xml"), Path::new("conf"), "A")
    {
        assert_eq!(ac.name, "A");
        assert!(!ac.flight_plan_rel.is_empty());
    }
    if let Ok(plan) = vouch_fpl::front::parse_str("fuzz.xml", &text) {
        let _ = vouch_fpl::emit::dump::dump(&plan);
        let _ = vouch_fpl::emit::settings::settings(&plan, "v");
    }
});
