//! sqlite3 storage files of any content: opened read-only, they give messages or a storage
//! error, never a panic.
#![no_main]
use std::collections::BTreeSet;
use std::io::Write;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(mut file) = tempfile::Builder::new().suffix(".db3").tempfile() else { return };
    if file.write_all(data).is_err() {
        return;
    }
    let topics: BTreeSet<String> = ["/plan".to_string(), "/map".to_string()].into_iter().collect();
    let _ = vouch_navfn::rosbag::read_bag(file.path(), &topics);
});
