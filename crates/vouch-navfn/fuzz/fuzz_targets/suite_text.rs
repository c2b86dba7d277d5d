//! The suite reader never panics: any text, with the rest of the input as the map bytes.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let split = data.iter().position(|&b| b == 0).unwrap_or(data.len());
    let text = String::from_utf8_lossy(&data[..split]);
    let map = data.get(split + 1..).unwrap_or(&[]).to_vec();
    let path = std::path::Path::new("fuzz/test.txt");
    if let Ok(file) = vouch_navfn::maps::parse_suite_text(path, &text, |_| Ok(map)) {
        assert_eq!(file.map.len(), file.width * file.height);
        for case in &file.cases {
            let _ = case.cells(file.width, file.height);
        }
    }
});
