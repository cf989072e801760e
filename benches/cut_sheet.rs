//! `cargo bench --bench cut_sheet`: the cost of a cut sheet.
//!
//! 1. In memory: time to plan and render a cut sheet (every layer, SVG + DXF, report) for 50 actuators
//!    of each thesis example design. Median of 7 runs per design.
//! 2. Large quantities through the binary: `cut-sheet examples/thesis-C.toml
//!    --quantity q` for q = 1000, 5000, 20000, as a lab runs it, into a fresh temporary folder. For each
//!    run: wall time, CPU time (user and system apart) and peak resident memory. The binary runs as a child and
//!    the figures are the kernel's own account of that child, read with `wait4` (its `rusage`): the peak
//!    RSS is the high-water mark of exactly that process, with no sampling gap, and needs no external
//!    tool (`/usr/bin/time` is not on every machine, and GNU and BSD print it differently). With
//!    `ACTUATOR_CAM_PEER=/path/to/other/actuator-cam` set, that binary runs the same quantity just before
//!    ours, so both are measured side by side at the same load. `CUT_SHEET_QUANTITIES=1000,5000` picks
//!    other quantities.

#[path = "../tests/common/fixtures.rs"]
mod fixtures;

use actuator_cam::cutsheet::{plan, write, CutSheetOptions, Formats, Template};
use actuator_cam::design::Design;
use actuator_model::ModelKind;
use fixtures::{example, example_path, THESIS_DESIGNS};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Instant;

fn main() {
    in_memory();
    large_quantities();
}

fn in_memory() {
    let opts = CutSheetOptions {
        formats: Formats {
            svg: true,
            dxf: true,
        },
        kerf_mm: None,
        quantity: Some(50),
        model: ModelKind::Original.into(),
        stroke_mm: 0.0254,
    };
    println!("cut-sheet, quantity 50, SVG + DXF + report, in memory (median of 7 runs)");
    for name in THESIS_DESIGNS {
        let design = Design::load(&example_path(&format!("{name}.toml"))).expect("example loads");
        let template = Template::resolve(&design.process, &design.source).expect("template");
        let mut times = Vec::new();
        let mut bytes = 0;
        let mut count = 0;
        for _ in 0..7 {
            let start = Instant::now();
            let sheet = plan(&design, &template, &opts).expect("plan");
            let files = write::render(&sheet, opts.formats, opts.stroke_mm).expect("render");
            times.push(start.elapsed().as_secs_f64());
            bytes = files.iter().map(|(_, b)| b.len()).sum::<usize>();
            count = files.len();
        }
        times.sort_by(f64::total_cmp);
        println!(
            "  {name:<10} {:>8.1} ms   {count:>4} files  {:>8.1} kB",
            times[3] * 1e3,
            bytes as f64 / 1e3
        );
    }
}

/// One child run: wall seconds, user and system CPU seconds, peak RSS in MB, files written.
struct Run {
    wall_s: f64,
    user_s: f64,
    sys_s: f64,
    peak_mb: f64,
    files: usize,
}

fn large_quantities() {
    let quantities: Vec<usize> = std::env::var("CUT_SHEET_QUANTITIES")
        .ok()
        .map(|s| {
            s.split(',')
                .map(|q| q.trim().parse().expect("a quantity"))
                .collect()
        })
        .unwrap_or_else(|| vec![1000, 5000, 20000]);
    let ours = env!("CARGO_BIN_EXE_actuator-cam").to_string();
    let peer = std::env::var("ACTUATOR_CAM_PEER").ok();
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "\ncut-sheet examples/thesis-C.toml --quantity q -o <new folder>, the binary as a child (load {})",
        load.split_whitespace().take(3).collect::<Vec<_>>().join(" ")
    );
    // System time is mostly the file system creating ~3 files per actuator; it varies with what else
    // the machine's file system is doing, so it is shown apart from the user time of rendering.
    println!("  binary   quantity     wall s     user s      sys s   peak RSS MB   files");
    for q in quantities {
        for (label, binary) in peer
            .iter()
            .map(|p| ("peer", p.as_str()))
            .chain([("ours", ours.as_str())])
        {
            let r = run_child(binary, q);
            println!(
                "  {label:<8} {q:>8} {:>10.2} {:>10.2} {:>10.2} {:>13.1} {:>7}",
                r.wall_s, r.user_s, r.sys_s, r.peak_mb, r.files
            );
        }
    }
}

/// Run `binary cut-sheet` for `q` actuators into a fresh folder and account for the child alone. The child
/// is reaped by `wait4` (which returns its rusage), not by `Child::wait`.
#[allow(clippy::zombie_processes)]
fn run_child(binary: &str, q: usize) -> Run {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("out");
    let start = Instant::now();
    let child = Command::new(binary)
        .args(["cut-sheet", &example("thesis-C.toml"), "--quantity"])
        .arg(q.to_string())
        .arg("-o")
        .arg(&out)
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
        "{binary} failed at q = {q}"
    );
    let seconds = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    Run {
        wall_s,
        user_s: seconds(usage.ru_utime),
        sys_s: seconds(usage.ru_stime),
        // Linux reports ru_maxrss in kilobytes.
        peak_mb: usage.ru_maxrss as f64 / 1024.0,
        files: count_files(&out),
    }
}

fn count_files(dir: &Path) -> usize {
    std::fs::read_dir(dir).map_or(0, |d| d.count())
}
