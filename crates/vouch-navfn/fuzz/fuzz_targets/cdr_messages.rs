//! CDR payloads of any content, decoded as every message type check-bag reads: a value or a
//! decode error, never a panic or a huge allocation; grids that decode are consistent.
#![no_main]
use libfuzzer_sys::fuzz_target;
use vouch_navfn::rosbag::msgs::{decode, NavMessage, KNOWN_TYPES};
use vouch_navfn::rosbag::BagMessage;

fuzz_target!(|data: &[u8]| {
    for type_name in KNOWN_TYPES {
        let m = BagMessage {
            topic: "/fuzz".into(),
            type_name: type_name.into(),
            log_time: 0,
            data: data.to_vec(),
        };
        if let Ok(NavMessage::Grid(g)) = decode(&m) {
            let len = match &g.cells {
                vouch_navfn::rosbag::msgs::GridCells::Occupancy(v) => v.len(),
                vouch_navfn::rosbag::msgs::GridCells::Costs(v) => v.len(),
            };
            assert_eq!(len, g.width * g.height);
        }
    }
});
