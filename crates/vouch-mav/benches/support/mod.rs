//! Timing for the benches: wall time, and the time the bench thread was on a CPU (the
//! thread's CPU clock), which other jobs on a shared machine do not inflate.

use std::time::Instant;

use cpu_time::ThreadTime;

/// Wall and on-CPU nanoseconds of `f`.
pub fn timed(f: impl FnOnce()) -> (f64, Option<f64>) {
    let (t, c) = (Instant::now(), ThreadTime::try_now().ok());
    f();
    let cpu = c.and_then(|c| c.try_elapsed().ok()).map(|d| d.as_nanos() as f64);
    (t.elapsed().as_nanos() as f64, cpu)
}

/// Per-message figures of repeated runs: wall and on-CPU nanoseconds per message.
#[derive(Default)]
pub struct Figures {
    wall: Vec<f64>,
    cpu: Vec<f64>,
}

impl Figures {
    /// Adds one run of `n` messages.
    pub fn add(&mut self, (wall, cpu): (f64, Option<f64>), n: u64) {
        self.wall.push(wall / n as f64);
        self.cpu.extend(cpu.map(|c| c / n as f64));
    }

    /// `wall min A, median B ns/msg; on CPU min C, median D`.
    pub fn line(&mut self) -> String {
        let stats = |v: &mut Vec<f64>| {
            v.sort_by(|a, b| a.total_cmp(b));
            v.first().map(|min| (*min, v[v.len() / 2]))
        };
        let wall = stats(&mut self.wall)
            .map_or_else(String::new, |(a, b)| format!("wall min {a:.0}, median {b:.0} ns/msg"));
        let cpu = stats(&mut self.cpu)
            .map_or_else(String::new, |(a, b)| format!("; on CPU min {a:.0}, median {b:.0}"));
        format!("{wall}{cpu}")
    }
}
