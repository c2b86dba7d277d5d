//! One side of a side-by-side measurement: vouch itself or an external implementation under the
//! oracle contract. Both sides are started the same way: their program directly, with the
//! contract's arguments and the target appended — no shell, so each side is charged its own
//! process only. The oracle's command line is split into words as a POSIX shell would
//! (`shlex`: quotes and backslashes; no variables, pipes or redirections).
//!
//! Two measurements:
//! * planning only: the side is asked for `--time-planning R` and prints one `TIME` line per test
//!   file with the best of `R` repetitions of its planning calls (thread CPU time) and its peak
//!   resident set (the contract's timing extension, docs/navfn-core.md);
//! * whole process: the side runs the contract (all output lines, sent to `/dev/null`) and is
//!   charged the user + system CPU time of its process (`getrusage(RUSAGE_CHILDREN)` before
//!   and after the wait).

use std::path::Path;
use std::process::{Command, Output, Stdio};

use super::BenchError;

/// Which implementation a side runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SideName {
    /// This vouch executable.
    Vouch,
    /// The external implementation given with `--oracle`.
    Oracle,
}

impl SideName {
    /// The name used in messages.
    pub fn as_str(self) -> &'static str {
        match self {
            SideName::Vouch => "vouch",
            SideName::Oracle => "oracle",
        }
    }
}

/// How to start one side: the argument vectors (program first) answering the timing
/// extension and printing the contract's CASE/PATH lines.
#[derive(Clone, Debug)]
pub struct Side {
    /// Which side this is.
    pub name: SideName,
    planning: Vec<String>,
    process: Vec<String>,
}

/// One `TIME` line: `TIME cases=N reps=R best_ns=T sum_ns=S found=F [explored=E] maxrss_kb=K
/// [start_rss_kb=K0]`.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct TimeLine {
    /// Cases timed.
    pub cases: u64,
    /// Repetitions.
    pub reps: u64,
    /// Best repetition, thread CPU nanoseconds.
    pub best_ns: f64,
    /// Sum of the repetitions, thread CPU nanoseconds.
    pub sum_ns: f64,
    /// Cases with a path.
    pub found: u64,
    /// Cells given a finite potential, summed over the cases.
    pub explored: Option<u64>,
    /// Peak resident set of the process, KiB.
    pub maxrss_kb: u64,
    /// Peak resident set before the input was read (the process's own start-up share).
    pub start_rss_kb: Option<u64>,
}

impl TimeLine {
    /// Parses a `TIME` line (other lines: `None`).
    pub fn parse(line: &str) -> Option<TimeLine> {
        let rest = line.strip_prefix("TIME ")?;
        let mut t = TimeLine::default();
        for tok in rest.split_whitespace() {
            let (k, v) = tok.split_once('=')?;
            match k {
                "cases" => t.cases = v.parse().ok()?,
                "reps" => t.reps = v.parse().ok()?,
                "best_ns" => t.best_ns = v.parse().ok()?,
                "sum_ns" => t.sum_ns = v.parse().ok()?,
                "found" => t.found = v.parse().ok()?,
                "explored" => t.explored = v.parse().ok(),
                "maxrss_kb" => t.maxrss_kb = v.parse().ok()?,
                "start_rss_kb" => t.start_rss_kb = v.parse().ok(),
                _ => {}
            }
        }
        Some(t)
    }

    /// The line as the contract prints it.
    pub fn render(&self) -> String {
        let explored = self.explored.map(|e| format!(" explored={e}")).unwrap_or_default();
        let start = self.start_rss_kb.map(|k| format!(" start_rss_kb={k}")).unwrap_or_default();
        format!(
            "TIME cases={} reps={} best_ns={:.0} sum_ns={:.0} found={}{explored} maxrss_kb={}{start}",
            self.cases, self.reps, self.best_ns, self.sum_ns, self.found, self.maxrss_kb
        )
    }
}

impl Side {
    /// vouch itself: `EXE -q navfn bench` (timing) and `EXE -q navfn suite run` (process).
    pub fn vouch(exe: &Path) -> Side {
        let exe = exe.to_string_lossy().into_owned();
        let words = |rest: &[&str]| {
            std::iter::once(exe.clone()).chain(rest.iter().map(|s| s.to_string())).collect()
        };
        Side {
            name: SideName::Vouch,
            planning: words(&["-q", "navfn", "bench"]),
            process: words(&["-q", "navfn", "suite", "run"]),
        }
    }

    /// An external implementation of the oracle contract, `cmd` split into words.
    pub fn oracle(cmd: &str) -> Result<Side, BenchError> {
        let words = shlex::split(cmd).filter(|w| !w.is_empty());
        let words = words.ok_or_else(|| BenchError::OracleCommand(cmd.to_string()))?;
        Ok(Side { name: SideName::Oracle, planning: words.clone(), process: words })
    }

    /// Runs `argv` with the contract's `args` and `target` appended and waits; `keep_stdout`
    /// false sends the output to `/dev/null`. A failed run is an error naming the side and
    /// the first lines of its stderr.
    fn run(
        &self,
        argv: &[String],
        args: &[String],
        target: &Path,
        keep_stdout: bool,
    ) -> Result<Output, BenchError> {
        let (program, fixed) =
            argv.split_first().ok_or(BenchError::OracleCommand(String::new()))?;
        let out = Command::new(program)
            .args(fixed)
            .args(args)
            .arg(target)
            .stdin(Stdio::null())
            .stdout(if keep_stdout { Stdio::piped() } else { Stdio::null() })
            .stderr(Stdio::piped())
            .output()
            .map_err(|e| self.failed(target, format!("cannot start `{program}`: {e}")))?;
        if !out.status.success() {
            let err = String::from_utf8_lossy(&out.stderr);
            let err: Vec<&str> = err.lines().take(3).collect();
            return Err(self.failed(target, format!("{}: {}", out.status, err.join(" | "))));
        }
        Ok(out)
    }

    fn failed(&self, target: &Path, message: String) -> BenchError {
        BenchError::Side { side: self.name, target: target.to_path_buf(), message }
    }

    /// Planning times of every test file below `target` (one `TIME` line each).
    pub fn time_planning(
        &self,
        args: &[String],
        reps: usize,
        target: &Path,
    ) -> Result<Vec<TimeLine>, BenchError> {
        let mut a = args.to_vec();
        a.extend(["--time-planning".to_string(), reps.to_string()]);
        let out = self.run(&self.planning, &a, target, true)?;
        let text = String::from_utf8_lossy(&out.stdout);
        let lines: Vec<TimeLine> = text.lines().filter_map(TimeLine::parse).collect();
        if lines.is_empty() {
            return Err(self.failed(target, "no `TIME` line for `--time-planning`".into()));
        }
        Ok(lines)
    }

    /// CPU seconds (user + system) of one contract run on `target`, its output discarded.
    pub fn process_cpu(&self, args: &[String], target: &Path) -> Result<f64, BenchError> {
        let before = children_cpu_seconds();
        self.run(&self.process, args, target, false)?;
        Ok(children_cpu_seconds() - before)
    }

    /// The CASE and PATH lines of one contract run (to check that both sides did the same work).
    pub fn answer_lines(&self, args: &[String], target: &Path) -> Result<String, BenchError> {
        let out = self.run(&self.process, args, target, true)?;
        let text = String::from_utf8_lossy(&out.stdout);
        let mut keep = String::new();
        for l in text.lines().filter(|l| l.starts_with("CASE ") || l.starts_with("PATH")) {
            keep.push_str(l);
            keep.push('\n');
        }
        Ok(keep)
    }
}

/// User + system CPU seconds of the waited-for children of this process.
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

/// Peak resident set of this process in KiB (0 where unknown). On Linux the high-water mark
/// of its own memory (`VmHWM` in `/proc/self/status`): `getrusage`'s `ru_maxrss` survives
/// `execve`, so a process started by a large one would report at least its parent's size.
pub fn peak_rss_kb() -> u64 {
    if let Ok(status) = std::fs::read_to_string("/proc/self/status")
        && let Some(kb) = status.lines().find_map(|l| l.strip_prefix("VmHWM:"))
        && let Some(kb) = kb.trim().trim_end_matches("kB").trim().parse().ok()
    {
        return kb;
    }
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
    fn time_lines_parse_and_render() {
        let line =
            "TIME cases=12 reps=3 best_ns=1500 sum_ns=4600 found=9 explored=77 maxrss_kb=3400";
        let t = TimeLine::parse(line).expect("parses");
        assert_eq!(
            (t.cases, t.reps, t.best_ns, t.found, t.explored, t.maxrss_kb),
            (12, 3, 1500.0, 9, Some(77), 3400)
        );
        assert_eq!(t.render(), line);
        assert!(TimeLine::parse("CASE 0 1 2 3 4").is_none());
        assert!(TimeLine::parse("TIME cases=x").is_none());
    }

    #[test]
    fn oracle_commands_split_like_a_shell() {
        let s = Side::oracle("'/opt/my oracle' --flag \"a b\"").expect("splits");
        assert_eq!(s.process, ["/opt/my oracle", "--flag", "a b"]);
        assert!(Side::oracle("unbalanced 'quote").is_err());
        assert!(Side::oracle("   ").is_err());
    }
}
