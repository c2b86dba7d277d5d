//! Fuzz target: the expression lexer/parser never panics, and printing is stable: a printed
//! expression that parses again prints the same text (quoted identifiers excluded: upstream
//! prints them without their quotes, which is not meant to re-parse).
#![no_main]

use libfuzzer_sys::fuzz_target;
use vouch_fpl::expr::{parse, print_upstream};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if text.contains('\'') {
        let _ = parse(text).map(|e| print_upstream(&e));
        return;
    }
    if let Ok(e) = parse(text) {
        let once = print_upstream(&e);
        if let Ok(again) = parse(&once) {
            assert_eq!(print_upstream(&again), once);
        }
    }
});
