//! Process control: the priority of the stream writer threads, and (with the `bench` feature)
//! the CPU pinning, CPU time, RSS, load average and SIGTERM of `vouch mav bench`.

#[cfg(feature = "bench")]
use std::process::Child;

#[cfg(feature = "bench")]
fn set_affinity(tid: libc::pid_t, cpus: impl Iterator<Item = usize>) {
    // SAFETY: cpu_set_t is plain data; sched_setaffinity reads it and changes only the CPU mask
    // of the given thread (0 = the caller); errors are ignored (pinning is best effort).
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        for c in cpus {
            libc::CPU_SET(c, &mut set);
        }
        libc::sched_setaffinity(tid, std::mem::size_of::<libc::cpu_set_t>(), &set);
    }
}

/// Lowers the calling thread's scheduling priority (nice `+n`), so that threads that route
/// frames run first when CPUs are busy. Best effort.
pub fn lower_current_thread_priority(n: i32) {
    // SAFETY: gettid has no preconditions; setpriority only changes the nice value of the
    // calling thread (PRIO_PROCESS with a thread id); errors are ignored.
    unsafe {
        let tid = libc::syscall(libc::SYS_gettid) as libc::id_t;
        libc::setpriority(libc::PRIO_PROCESS, tid, n);
    }
}

/// Pins the calling thread to one CPU.
#[cfg(feature = "bench")]
pub fn pin_current_thread(cpu: usize) {
    set_affinity(0, std::iter::once(cpu));
}

/// Lets the calling thread run on every CPU again.
#[cfg(feature = "bench")]
pub fn unpin_current_thread() {
    set_affinity(0, 0..libc::CPU_SETSIZE as usize);
}

/// Pins every thread of process `pid` to one CPU.
#[cfg(feature = "bench")]
pub fn pin_process(pid: u32, cpu: usize) {
    let Ok(tasks) = std::fs::read_dir(format!("/proc/{pid}/task")) else { return };
    for t in tasks.flatten() {
        if let Ok(tid) = t.file_name().to_string_lossy().parse::<libc::pid_t>() {
            set_affinity(tid, std::iter::once(cpu));
        }
    }
}

/// User + system CPU seconds used so far by process `pid` (all its threads).
#[cfg(feature = "bench")]
pub fn cpu_seconds(pid: u32) -> Option<f64> {
    let s = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    let rest = &s[s.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    // fields after the command name start at field 3 (state): utime is field 14, stime 15
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    // SAFETY: sysconf has no preconditions and only reads a system constant.
    let hz = unsafe { libc::sysconf(libc::_SC_CLK_TCK) } as f64;
    (hz > 0.0).then(|| ticks / hz)
}

#[cfg(feature = "bench")]
fn status_kb(pid: u32, key: &str) -> Option<u64> {
    let s = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = s.lines().find(|l| l.starts_with(key))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Peak resident set size of `pid` in kB (VmHWM).
#[cfg(feature = "bench")]
pub fn peak_rss_kb(pid: u32) -> Option<u64> {
    status_kb(pid, "VmHWM:")
}

/// Current resident set size of `pid` in kB (VmRSS).
#[cfg(feature = "bench")]
pub fn rss_kb(pid: u32) -> Option<u64> {
    status_kb(pid, "VmRSS:")
}

/// Resets the peak RSS counter of `pid` (Linux ≥ 4.0), so that a later [`peak_rss_kb`] covers
/// only what happened since.
#[cfg(feature = "bench")]
pub fn reset_peak_rss(pid: u32) {
    let _ = std::fs::write(format!("/proc/{pid}/clear_refs"), "5");
}

/// The 1, 5 and 15 minute load averages as printed by the kernel.
#[cfg(feature = "bench")]
pub fn load_average() -> Option<String> {
    let s = std::fs::read_to_string("/proc/loadavg").ok()?;
    Some(s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
}

/// Asks a child process to terminate (SIGTERM), so that a guard flushes its logs.
#[cfg(feature = "bench")]
pub fn terminate(child: &mut Child) {
    match libc::pid_t::try_from(child.id()) {
        // SAFETY: kill(2) on the pid of our own child, which has not been waited for yet.
        Ok(pid) => unsafe {
            libc::kill(pid, libc::SIGTERM);
        },
        Err(_) => {
            let _ = child.kill();
        }
    }
}
