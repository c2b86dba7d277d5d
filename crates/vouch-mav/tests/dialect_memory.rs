//! The guard's peak RSS is meant to stay under 8 MB. Most of it used to be the XML DOM of the
//! embedded dialect built at start-up (common.xml alone is 676 KB of text). The default dialect
//! now comes from a build-time digest; this test measures the growth of this process's peak RSS
//! (VmHWM, Linux `/proc`) while loading it. Alone in its file so that no other test runs in the
//! process.
#![cfg(target_os = "linux")]

fn vm_hwm_kb() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

#[test]
fn loading_the_default_dialect_adds_little_to_peak_rss() {
    let before = vm_hwm_kb().expect("VmHWM in /proc/self/status");
    let d = match vouch_mav::dialect::Dialect::default_dialect() {
        Ok(d) => d,
        Err(e) => {
            let need = vouch_testkit::Need::Shared;
            return vouch_testkit::missing(need, &format!("no default dialect ({e})"))
                .unwrap_or(());
        }
    };
    let after = vm_hwm_kb().unwrap_or(before);
    let grown = after.saturating_sub(before);
    eprintln!("default dialect ({} messages): peak RSS +{grown} kB", d.messages().len());
    // Parsing the XML grew the peak by ~5 MB; the tables themselves need about 1 MB.
    assert!(grown <= 2048, "peak RSS grew by {grown} kB while loading the default dialect");
    // For comparison (printed only): the same dialect read from its XML, as before the digest.
    let xml = std::path::Path::new(vouch_mav::dialect::embedded_origin()).join("ardupilotmega.xml");
    if let Ok(x) = vouch_mav::dialect::load_dialect_file(&xml) {
        let grown_xml = vm_hwm_kb().unwrap_or(after).saturating_sub(after);
        eprintln!(
            "same dialect from XML ({} messages): peak RSS +{grown_xml} kB more",
            x.messages().len()
        );
    }
}
