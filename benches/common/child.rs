//! One run of the release binary as a child, accounted for by the kernel: wall time, CPU time (user and
//! system apart) and peak resident memory, read with `wait4` (the child's own `rusage`). The peak RSS is
//! the high-water mark of exactly that process, with no sampling gap, and needs no external tool
//! (`/usr/bin/time` is not on every machine, and GNU and BSD print it differently).

use std::process::{Command, Stdio};
use std::time::Instant;

/// What one child run cost.
pub struct Usage {
    pub wall_s: f64,
    pub user_s: f64,
    pub sys_s: f64,
    pub peak_mb: f64,
}

/// Run `command` (stdout discarded) to its end and account for it; panics if it fails. The child is
/// reaped by `wait4` (which returns its rusage), not by `Child::wait`.
#[allow(clippy::zombie_processes)]
pub fn measure(mut command: Command) -> Usage {
    let start = Instant::now();
    let child = command
        .stdout(Stdio::null())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("the binary starts");
    let pid = child.id() as libc::pid_t;
    let mut status = 0;
    // SAFETY: `rusage` is plain data the kernel fills; `pid` is our own child, waited for exactly once
    // (the `Child` handle is not waited on again).
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let waited = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    let wall_s = start.elapsed().as_secs_f64();
    assert_eq!(waited, pid, "wait4 on the child");
    assert!(
        libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0,
        "{command:?} failed"
    );
    let seconds = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    Usage {
        wall_s,
        user_s: seconds(usage.ru_utime),
        sys_s: seconds(usage.ru_stime),
        // Linux reports ru_maxrss in kilobytes.
        peak_mb: usage.ru_maxrss as f64 / 1024.0,
    }
}

/// The machine's load averages (1, 5, 15 minutes), as `/proc/loadavg` gives them.
pub fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .unwrap_or_default()
        .split_whitespace()
        .take(3)
        .collect::<Vec<_>>()
        .join(" ")
}
