//! One side of a side-by-side measurement: vouch itself or an external implementation under the
//! oracle contract. Both sides are started the same way, as `sh -c '<CMD> "$@"' oracle ARGS…
//! TARGET` (the contract's invocation), so that each is charged the same shell and process
//! start.
//!
//! Two measurements:
//! * planning only: the side is asked for `--time-planning R` and prints one `TIME` line per test
//!   file with the best of `R` repetitions of its planning calls (thread CPU time) and its peak
//!   resident set (the contract's timing extension, docs/navfn-core.md);
//! * whole process: the side runs the contract (all output lines, sent to `/dev/null`) and is
//!   charged the user + system CPU time of its process tree (`getrusage(RUSAGE_CHILDREN)`
//!   before and after the wait).

use std::path::Path;
use std::process::{Command, Output, Stdio};

/// How to start one side.
pub struct Side {
    /// `vouch` or `oracle`.
    pub name: &'static str,
    /// Command prefix answering `--time-planning`.
    planning: String,
    /// Command prefix printing the contract's CASE/PATH lines.
    process: String,
}

/// One `TIME` line: `TIME cases=N reps=R best_ns=T sum_ns=S found=F [explored=E] maxrss_kb=K`.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct TimeLine {
    pub cases: u64,
    pub best_ns: f64,
    pub found: u64,
    /// Cells given a finite potential, summed over the cases (vouch's side prints it).
    pub explored: Option<u64>,
    pub maxrss_kb: u64,
    /// Peak resident set before the input was read (the process's own start-up share).
    pub start_rss_kb: Option<u64>,
}

/// `s` quoted for `sh`.
fn shell_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

impl Side {
    /// vouch itself: this executable's `navfn bench` (timing) and `navfn suite run` (process).
    pub fn vouch() -> std::io::Result<Side> {
        let exe = std::env::current_exe()?;
        let q = shell_quote(&exe.to_string_lossy());
        Ok(Side {
            name: "vouch",
            planning: format!("{q} -q navfn bench"),
            process: format!("{q} -q navfn suite run"),
        })
    }

    /// An external implementation of the oracle contract.
    pub fn oracle(cmd: &str) -> Side {
        Side { name: "oracle", planning: cmd.to_string(), process: cmd.to_string() }
    }

    /// Runs `cmd` (the contract's invocation) on `target` and waits; `keep_stdout` false sends
    /// the output to `/dev/null`. A failed run is an error naming the side and its stderr.
    fn run(
        &self,
        cmd: &str,
        args: &[String],
        target: &Path,
        keep_stdout: bool,
    ) -> Result<Output, String> {
        let out = Command::new("sh")
            .arg("-c")
            .arg(format!("{cmd} \"$@\""))
            .arg("oracle")
            .args(args)
            .arg(target)
            .stdin(Stdio::null())
            .stdout(if keep_stdout { Stdio::piped() } else { Stdio::null() })
            .stderr(Stdio::piped())
            .output()
            .map_err(|e| format!("{}: cannot start `{cmd}`: {e}", self.name))?;
        if !out.status.success() {
            return Err(self.failed(&out.status.to_string(), &out.stderr, target));
        }
        Ok(out)
    }

    /// Planning times of every test file below `target` (one `TIME` line each).
    pub fn time_planning(
        &self,
        args: &[String],
        reps: usize,
        target: &Path,
    ) -> Result<Vec<TimeLine>, String> {
        let mut a = args.to_vec();
        a.extend(["--time-planning".to_string(), reps.to_string()]);
        let out = self.run(&self.planning, &a, target, true)?;
        let text = String::from_utf8_lossy(&out.stdout);
        let lines: Vec<TimeLine> = text.lines().filter_map(parse_time_line).collect();
        if lines.is_empty() {
            return Err(format!(
                "{} printed no `TIME` line for `--time-planning` on {}",
                self.name,
                target.display()
            ));
        }
        Ok(lines)
    }

    /// CPU seconds (user + system, the whole process tree) of one contract run on `target`,
    /// its output discarded.
    pub fn process_cpu(&self, args: &[String], target: &Path) -> Result<f64, String> {
        let before = children_cpu_seconds();
        self.run(&self.process, args, target, false)?;
        Ok(children_cpu_seconds() - before)
    }

    /// The CASE and PATH lines of one contract run (to check that both sides did the same work).
    pub fn answer_lines(&self, args: &[String], target: &Path) -> Result<String, String> {
        let out = self.run(&self.process, args, target, true)?;
        let text = String::from_utf8_lossy(&out.stdout);
        let mut keep = String::new();
        for l in text.lines().filter(|l| l.starts_with("CASE ") || l.starts_with("PATH")) {
            keep.push_str(l);
            keep.push('\n');
        }
        Ok(keep)
    }

    fn failed(&self, status: &str, stderr: &[u8], target: &Path) -> String {
        let err = String::from_utf8_lossy(stderr);
        let err: Vec<&str> = err.lines().take(3).collect();
        format!("{} failed on {} ({status}): {}", self.name, target.display(), err.join(" | "))
    }
}

fn parse_time_line(line: &str) -> Option<TimeLine> {
    let rest = line.strip_prefix("TIME ")?;
    let mut t = TimeLine::default();
    for tok in rest.split_whitespace() {
        let (k, v) = tok.split_once('=')?;
        match k {
            "cases" => t.cases = v.parse().ok()?,
            "best_ns" => t.best_ns = v.parse().ok()?,
            "found" => t.found = v.parse().ok()?,
            "explored" => t.explored = v.parse().ok(),
            "maxrss_kb" => t.maxrss_kb = v.parse().ok()?,
            "start_rss_kb" => t.start_rss_kb = v.parse().ok(),
            _ => {}
        }
    }
    Some(t)
}

/// The `TIME` line of vouch's side.
pub fn format_time_line(t: &TimeLine, reps: usize, sum_ns: f64) -> String {
    let explored = t.explored.map(|e| format!(" explored={e}")).unwrap_or_default();
    let start = t.start_rss_kb.map(|k| format!(" start_rss_kb={k}")).unwrap_or_default();
    format!(
        "TIME cases={} reps={reps} best_ns={:.0} sum_ns={sum_ns:.0} found={}{explored} maxrss_kb={}{start}",
        t.cases, t.best_ns, t.found, t.maxrss_kb
    )
}

/// User + system CPU seconds of the waited-for children of this process, and of theirs.
#[cfg(unix)]
fn children_cpu_seconds() -> f64 {
    use nix::sys::resource::{UsageWho, getrusage};
    getrusage(UsageWho::RUSAGE_CHILDREN).map_or(0.0, |u| {
        let s = |t: nix::sys::time::TimeVal| t.tv_sec() as f64 + t.tv_usec() as f64 * 1e-6;
        s(u.user_time()) + s(u.system_time())
    })
}

#[cfg(not(unix))]
fn children_cpu_seconds() -> f64 {
    0.0
}

/// Peak resident set of this process in KiB (0 where unknown).
pub fn peak_rss_kb() -> u64 {
    #[cfg(unix)]
    {
        use nix::sys::resource::{UsageWho, getrusage};
        getrusage(UsageWho::RUSAGE_SELF).map_or(0, |u| u.max_rss().max(0) as u64)
    }
    #[cfg(not(unix))]
    {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_lines_parse() {
        let t = parse_time_line(
            "TIME cases=12 reps=3 best_ns=1500 sum_ns=4600 found=9 explored=77 maxrss_kb=3400",
        )
        .expect("parses");
        assert_eq!(
            (t.cases, t.best_ns, t.found, t.explored, t.maxrss_kb),
            (12, 1500.0, 9, Some(77), 3400)
        );
        assert!(parse_time_line("CASE 0 1 2 3 4").is_none());
        assert!(parse_time_line("TIME cases=x").is_none());
        assert_eq!(shell_quote("a'b"), r"'a'\''b'");
    }
}
