//! The router's log directory (mavlink-router's `Log`, `LogTelemetry`, `MaxLogFiles`): one
//! violations log per run (`vouch-YYYYMMDD-HHMMSS.jsonl`) and, with telemetry, one tlog of all
//! traffic (`vouch-YYYYMMDD-HHMMSS.tlog`); the oldest of vouch's files go when there would be
//! more than the limit.

use std::io;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

/// `YYYYMMDD-HHMMSS` (UTC) of a UNIX time.
pub fn stamp(unix_secs: u64) -> String {
    let days = (unix_secs / 86_400) as i64;
    let secs = unix_secs % 86_400;
    // civil date from days since 1970-01-01 (proleptic Gregorian)
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{y:04}{m:02}{d:02}-{:02}{:02}{:02}", secs / 3600, secs / 60 % 60, secs % 60)
}

/// Creates `dir` if needed, removes the oldest `vouch-*.jsonl` / `vouch-*.tlog` files so that
/// at most `max_files` remain with the new ones (0 = no limit), and returns the new paths.
pub fn log_files(
    dir: &Path,
    telemetry: bool,
    max_files: u64,
) -> io::Result<(PathBuf, Option<PathBuf>)> {
    std::fs::create_dir_all(dir)?;
    let now = SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs());
    let base = format!("vouch-{}", stamp(now));
    let new = 1 + u64::from(telemetry);
    if max_files > 0 {
        let mut old: Vec<PathBuf> = std::fs::read_dir(dir)?
            .flatten()
            .map(|e| e.path())
            .filter(|p| {
                let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
                name.starts_with("vouch-") && (name.ends_with(".jsonl") || name.ends_with(".tlog"))
            })
            .collect();
        old.sort();
        let keep = max_files.saturating_sub(new) as usize;
        let remove = old.len().saturating_sub(keep);
        for p in &old[..remove] {
            std::fs::remove_file(p)?;
        }
    }
    let tlog = telemetry.then(|| dir.join(format!("{base}.tlog")));
    Ok((dir.join(format!("{base}.jsonl")), tlog))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utc_stamps() {
        assert_eq!(stamp(0), "19700101-000000");
        // 2000-02-29 12:34:56 UTC (a leap day)
        assert_eq!(stamp(951_827_696), "20000229-123456");
        assert_eq!(stamp(1_735_689_599), "20241231-235959");
    }

    #[test]
    fn the_oldest_files_go_beyond_the_limit() {
        let dir = std::env::temp_dir().join(format!("vouch-logdir-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        for n in [
            "vouch-20240101-000000.jsonl",
            "vouch-20240102-000000.tlog",
            "vouch-20240103-000000.jsonl",
            "other.txt",
        ] {
            std::fs::write(dir.join(n), b"x").unwrap();
        }
        let (log, tlog) = log_files(&dir, true, 3).unwrap();
        assert!(log.to_string_lossy().ends_with(".jsonl") && tlog.is_some());
        let mut left: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(
            left,
            vec!["other.txt", "vouch-20240103-000000.jsonl"],
            "room for the 2 new ones"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
