//! Arbitrary text as a mavlink-router configuration file (and as the second file of a conf
//! directory): never panics; every error and warning points inside the file it names.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vouch_mav::guard::conf::{assign_sides, parse_sources, Source};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data).into_owned();
    let mut mid = text.len() / 2;
    while !text.is_char_boundary(mid) {
        mid += 1;
    }
    let (a, b) = text.split_at(mid);
    for sources in [
        vec![Source { name: "main.conf".into(), text: text.clone() }],
        vec![
            Source { name: "main.conf".into(), text: a.to_string() },
            Source { name: "config.d/10.conf".into(), text: b.to_string() },
        ],
    ] {
        match parse_sources(sources) {
            Ok(mut f) => {
                for w in &f.warnings {
                    assert!(w.span.0 + w.span.1 <= w.src.inner().len());
                }
                let _ = assign_sides(&mut f.endpoints);
            }
            Err(e) => assert!(e.span.0 + e.span.1 <= e.src.inner().len()),
        }
    }
});
