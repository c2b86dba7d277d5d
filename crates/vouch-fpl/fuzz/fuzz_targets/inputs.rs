//! Fuzz target: the small languages given on the command line — the model checker's property
//! language (`vouch fpl check --property`), answer files (`vouch fpl sim --conditions`) and
//! jumps files (`vouch fpl sim --jumps`) — must reject any text with a located error, never
//! panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let blocks = vec!["Take off".to_string(), "Land".to_string(), "HOME".to_string()];
    if let Err(e) = vouch_fpl::model_check::property::parse(&text, &blocks) {
        assert!(e.at.offset() <= text.len());
    }
    if let Err(e) = vouch_fpl::semantics::oracle::Scripted::parse(&text) {
        assert!(e.at.offset() + e.at.len() <= text.len());
    }
    match vouch_fpl::semantics::sim::parse_jumps(&text, blocks.len()) {
        Ok(jumps) => assert!(jumps.iter().all(|&(_, b)| b < blocks.len())),
        Err(e) => assert!(e.at.offset() + e.at.len() <= text.len()),
    }
});
