//! Arbitrary bytes as a stream, as a tlog, and through the monitor: never panics, and every
//! frame returned is a byte range of the input that parses again to the same frame.
#![no_main]

use std::sync::{Arc, OnceLock};

use libfuzzer_sys::fuzz_target;
use vouch_mav::codec::{FrameSplitter, MessageView, TlogReader};
use vouch_mav::dialect::Dialect;
use vouch_mav::monitor::Monitor;
use vouch_mav::protocol::{load_protocols, stdlib, ProtocolSet};

fn dialect() -> &'static Arc<Dialect> {
    static D: OnceLock<Arc<Dialect>> = OnceLock::new();
    D.get_or_init(|| Arc::new(Dialect::default_dialect().expect("default dialect")))
}

/// The standard library compiled once (compiling it per input would dominate the run time).
fn protocols() -> &'static ProtocolSet {
    static P: OnceLock<ProtocolSet> = OnceLock::new();
    P.get_or_init(|| load_protocols(dialect(), &stdlib::sources(), &[]).expect("stdlib"))
}

fuzz_target!(|data: &[u8]| {
    let d = dialect();
    let mut monitor = Monitor::new(d.clone(), protocols().clone());
    let mut sp = FrameSplitter::new();
    let mut pos = 0;
    let mut t = 0u64;
    while let Some((range, f)) = sp.next(data, &mut pos, d, true) {
        assert_eq!(&data[range], f.bytes);
        if let Some(v) = MessageView::of_frame(&f, d) {
            let _ = v.render_fields();
        }
        t += 1000;
        let _ = monitor.on_frame(&f, None, t);
    }
    assert_eq!(pos, data.len());
    let mut r = TlogReader::new(data, d);
    for rec in r.by_ref() {
        let _ = monitor.on_frame(&rec.frame, None, rec.time_us);
    }
    let _ = r.stats();
    monitor.finish();
});
