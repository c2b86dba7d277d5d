//! The text form of a [`BenchReport`]: one table per scenario with a row per figure and a
//! column per path, every figure with its unit, and the notes that say how it was measured.

use std::fmt::Write as _;

use super::{BenchReport, Latency, PathKind, PathResult, RouterResult};

/// Width of the figure names.
const LABEL: usize = 38;
/// Width of one path's column.
const COLUMN: usize = 12;

/// The report as tables (proxy scenario, then router scenario), ending with a newline.
pub fn table(r: &BenchReport) -> String {
    let mut w = String::new();
    if !r.proxy.is_empty() {
        proxy_table(&mut w, &r.proxy);
    }
    if !r.router.is_empty() {
        if !w.is_empty() {
            w.push('\n');
        }
        router_table(&mut w, &r.router);
    }
    if !w.is_empty() {
        let load = r.load_average.as_deref().unwrap_or("unknown");
        let _ = writeln!(w, "\nLoad average of the machine at the end (1, 5, 15 min): {load}.");
    }
    w
}

/// The two header lines of a path's column ("guard relay-only" → "guard", "relay-only").
fn column_head(p: PathKind) -> (&'static str, &'static str) {
    match p {
        PathKind::Direct => ("", "direct"),
        PathKind::Socat => ("", "socat"),
        PathKind::GuardRelayOnly => ("guard", "relay-only"),
        PathKind::GuardMonitor => ("guard", "monitor"),
        PathKind::GuardEnforce => ("guard", "enforce"),
        PathKind::GuardRouterRelayOnly => ("router", "relay-only"),
        PathKind::GuardRouter => ("router", "checking"),
    }
}

fn head(w: &mut String, paths: &[PathKind]) {
    let (top, bottom): (Vec<_>, Vec<_>) = paths.iter().map(|&p| column_head(p)).unzip();
    let line = |cells: Vec<&str>| {
        let cells: String = cells.iter().map(|c| format!("{c:>COLUMN$}")).collect();
        format!("{:LABEL$}{cells}", "").trim_end().to_string()
    };
    let _ = writeln!(w, "{}", line(top));
    let _ = writeln!(w, "{}", line(bottom));
}

fn row(w: &mut String, label: &str, cells: impl Iterator<Item = String>) {
    let cells: String = cells.map(|c| format!("{c:>COLUMN$}")).collect();
    let _ = writeln!(w, "{label:LABEL$}{cells}");
}

fn micros(v: f64) -> String {
    if v.is_nan() { "-".into() } else { format!("{v:.1}") }
}

fn middle_half(l: &Latency) -> String {
    if l.samples == 0 { "-".into() } else { format!("{:.1}-{:.1}", l.p25_us, l.p75_us) }
}

/// A whole number with thousands separators ("1,234,567").
fn count(v: f64) -> String {
    if !v.is_finite() {
        return "-".into();
    }
    let digits = format!("{:.0}", v.max(0.0));
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

fn kilobytes(v: Option<u64>) -> String {
    v.map_or_else(|| "-".into(), |k| count(k as f64))
}

fn latency_rows(w: &mut String, what: &str, of: &[&Latency]) {
    row(w, &format!("{what}: median (µs)"), of.iter().map(|l| micros(l.median_us)));
    row(w, "  middle half, 25th-75th pct (µs)", of.iter().map(|l| middle_half(l)));
    row(w, "  99th percentile (µs)", of.iter().map(|l| micros(l.p99_us)));
}

fn proxy_table(w: &mut String, ps: &[PathResult]) {
    let _ = writeln!(w, "Proxy scenario: one ground station and one vehicle over UDP on 127.0.0.1");
    head(w, &ps.iter().map(|p| p.path).collect::<Vec<_>>());
    latency_rows(w, "upload latency", &ps.iter().map(|p| &p.upload).collect::<Vec<_>>());
    latency_rows(w, "telemetry latency", &ps.iter().map(|p| &p.telemetry).collect::<Vec<_>>());
    let rate = ps.first().map_or(0, |p| p.stream_rate);
    let stream = format!("paced {} msg/s: delivered (%)", count(f64::from(rate)));
    row(w, &stream, ps.iter().map(|p| format!("{:.1}", p.stream_delivered_pct)));
    row(w, "  99th percentile latency (µs)", ps.iter().map(|p| micros(p.stream.p99_us)));
    row(w, "flood: delivered (frames/s)", ps.iter().map(|p| count(p.flood_delivered_per_s)));
    let per_cpu = |p: &PathResult| p.frames_per_cpu_second.map_or_else(|| "-".into(), count);
    row(w, "  relay capacity (frames/CPU-second)", ps.iter().map(per_cpu));
    row(
        w,
        "relay memory, peak at start-up (kB)",
        ps.iter().map(|p| kilobytes(p.startup_peak_rss_kb)),
    );
    row(w, "  peak during the traffic (kB)", ps.iter().map(|p| kilobytes(p.peak_rss_kb)));
    row(w, "  at the end (kB)", ps.iter().map(|p| kilobytes(p.end_rss_kb)));
    let _ = writeln!(
        w,
        "\nLatency is one way with one message in flight: 100-waypoint uploads (ground station and\n\
         vehicle taking turns) and single ATTITUDE frames. Compare paths by their middle halves:\n\
         where two overlap, the paths differ by less than the noise of this run. The flood sends\n\
         as fast as it can with the relay pinned to CPU 0; its frames per CPU-second are the\n\
         relay's capacity on one core, which other load on the machine hardly changes."
    );
}

fn router_table(w: &mut String, ps: &[RouterResult]) {
    let _ = writeln!(
        w,
        "Router scenario: the vehicle (UDP server endpoint), two ground stations (UDP clients)\n\
         and a companion (TCP), the guard with all standard protocols"
    );
    head(w, &ps.iter().map(|p| p.path).collect::<Vec<_>>());
    row(w, "endpoints of the relay", ps.iter().map(|p| p.endpoints.to_string()));
    latency_rows(w, "telemetry latency", &ps.iter().map(|p| &p.telemetry).collect::<Vec<_>>());
    row(w, "flood: offered (frames/s)", ps.iter().map(|p| count(p.offered_per_s)));
    row(w, "  delivered to ground 1 (frames/s)", ps.iter().map(|p| count(p.delivered_per_s)));
    row(w, "  delivered to all peers (frames/s)", ps.iter().map(|p| count(p.delivered_all_per_s)));
    let per_cpu = |p: &RouterResult| p.frames_per_cpu_second.map_or_else(|| "-".into(), count);
    row(w, "  relay capacity (frames/CPU-second)", ps.iter().map(per_cpu));
    row(
        w,
        "relay memory, peak at start-up (kB)",
        ps.iter().map(|p| kilobytes(p.startup_peak_rss_kb)),
    );
    row(w, "  peak during the traffic (kB)", ps.iter().map(|p| kilobytes(p.peak_rss_kb)));
    let _ = writeln!(
        w,
        "\nLatency is one way from the vehicle to the first ground station, one frame in flight.\n\
         In the flood the vehicle sends 600,000 frames as fast as it can, the relay pinned to\n\
         CPU 0; socat and the direct path feed the first ground station only."
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::{REPORT_VERSION, Skipped};

    fn path(kind: PathKind, median: f64) -> PathResult {
        let mut p = PathResult::new(kind, 100_000);
        p.upload = Latency::of((-2..=2).map(|d| median + f64::from(d)).collect());
        p.telemetry = Latency::of(vec![median]);
        p.stream_delivered_pct = 99.5;
        p.flood_delivered_per_s = 1_234_567.0;
        p.frames_per_cpu_second = (kind != PathKind::Direct).then_some(250_000.0);
        p
    }

    fn report() -> BenchReport {
        BenchReport {
            version: REPORT_VERSION,
            proxy: vec![
                path(PathKind::Direct, 1.1),
                path(PathKind::Socat, 6.0),
                path(PathKind::GuardRelayOnly, 5.4),
                path(PathKind::GuardMonitor, 6.0),
                path(PathKind::GuardEnforce, 5.9),
            ],
            router: vec![],
            skipped: vec![Skipped {
                scenario: "router",
                path: PathKind::Socat,
                reason: "socat not found".into(),
            }],
            load_average: Some("1.00 0.50 0.25".into()),
        }
    }

    #[test]
    fn a_table_a_person_reads_in_a_terminal() {
        let t = table(&report());
        let widest = t.lines().map(|l| l.chars().count()).max().unwrap();
        assert!(widest <= 100, "widest line {widest}:\n{t}");
        assert!(t.contains("upload latency: median (µs)"), "{t}");
        assert!(t.contains("5.0-7.0"), "middle half of the socat upload:\n{t}");
        assert!(t.contains("1,234,567"), "{t}");
        assert!(t.contains("relay-only") && t.contains("enforce"), "{t}");
        assert!(t.contains("1.00 0.50 0.25"), "{t}");
    }

    #[test]
    fn json_names_are_snake_case_and_versioned() {
        let v = serde_json::to_value(report()).unwrap();
        assert_eq!(v["version"], REPORT_VERSION);
        assert_eq!(v["proxy"][2]["path"], "guard_relay_only");
        assert_eq!(v["proxy"][0]["upload"]["median_us"], 1.1);
        assert_eq!(v["skipped"][0]["path"], "socat");
        assert_eq!(v["skipped"][0]["scenario"], "router");
    }
}
