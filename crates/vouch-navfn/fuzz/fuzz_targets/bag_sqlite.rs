//! sqlite3 storage files of any content: opened read-only, they give messages or a storage
//! error, never a panic.
#![no_main]
use std::collections::BTreeSet;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let path = std::env::temp_dir().join(format!("vouch-fuzz-{}.db3", std::process::id()));
    if std::fs::write(&path, data).is_err() {
        return;
    }
    let topics: BTreeSet<String> = ["/plan".to_string(), "/map".to_string()].into_iter().collect();
    let _ = vouch_navfn::rosbag::read_bag(&path, &topics);
    let _ = std::fs::remove_file(&path);
});
