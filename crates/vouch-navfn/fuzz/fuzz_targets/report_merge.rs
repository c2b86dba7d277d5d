//! Reading and merging campaign reports never panics and never loops for long: any bytes as a
//! report; a report that reads is merged alone, with itself (a duplicate) and with a copy that
//! claims the next shard, and its summary table is drawn.
#![no_main]
use libfuzzer_sys::fuzz_target;
use vouch_navfn::campaign::merge::Completeness;
use vouch_navfn::campaign::report::Report;
use vouch_navfn::campaign::summary::summary_table;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let Ok(r) = Report::from_json(std::path::Path::new("fuzz.json"), &text) else { return };
    let _ = summary_table(&r);
    if let Ok(m) = Report::merge(std::slice::from_ref(&r), Completeness::AllowPartial) {
        let _ = summary_table(&m);
    }
    assert!(Report::merge(&[r.clone(), r.clone()], Completeness::AllowPartial).is_err());
    let mut next = r.clone();
    next.shards.indices = r.shards.indices.iter().map(|i| i.wrapping_add(1) % r.shards.count.max(1)).collect();
    let _ = Report::merge(&[r, next], Completeness::Required);
});
