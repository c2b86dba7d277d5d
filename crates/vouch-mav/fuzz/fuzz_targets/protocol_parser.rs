//! Arbitrary text as a protocol file: either a located error or a protocol set, never a panic.
#![no_main]

use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use vouch_mav::dialect::Dialect;
use vouch_mav::protocol::{lint, parser};

fn dialect() -> &'static Dialect {
    static D: OnceLock<Dialect> = OnceLock::new();
    D.get_or_init(|| Dialect::default_dialect().expect("default dialect"))
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let _ = parser::parse(text);
    if let Err(e) = lint(dialect(), &[("fuzz.vproto".to_string(), text.to_string())]) {
        assert!(e.line >= 1 && e.col >= 1);
    }
});
