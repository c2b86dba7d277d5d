//! MCAP bytes of any shape: the reader returns messages or a storage error, never panics, and
//! whatever it returns goes through the CDR decoders and the plan checks without panicking.
#![no_main]
use std::collections::BTreeSet;

use libfuzzer_sys::fuzz_target;
use vouch_navfn::bagcheck::{check_bag, BagCheckOptions, Topics};
use vouch_navfn::rosbag::{read_mcap_bytes, Bag};

fuzz_target!(|data: &[u8]| {
    let t = Topics::default();
    let topics: BTreeSet<String> =
        [&t.map, &t.costmap, &t.costmap_raw, &t.costmap_updates, &t.plan, &t.goal, &t.robot_pose, &t.tf]
            .into_iter()
            .cloned()
            .collect();
    if let Ok(messages) = read_mcap_bytes(data, &topics) {
        let bag = Bag { files: Vec::new(), messages };
        let _ = check_bag(&bag, &BagCheckOptions::default());
    }
});
