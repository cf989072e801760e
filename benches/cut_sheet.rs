//! `cargo bench --bench cut_sheet`: the cost of a cut sheet.
//!
//! 1. In memory: time to plan and render a cut sheet (every layer, SVG + DXF, report) for 50 actuators
//!    of each thesis example design. Median of 7 runs per design.
//! 2. Large quantities through the binary: `cut-sheet examples/thesis-C.toml
//!    --quantity q` for q = 1000, 5000, 20000, as a lab runs it, into a fresh temporary folder. For each
//!    run: wall time, CPU time (user and system apart) and peak resident memory, the kernel's own
//!    account of the child (`common/child.rs`). With `ACTUATOR_CAM_PEER=/path/to/other/actuator-cam`
//!    set, that binary runs the same quantity just before ours, so both are measured side by side at the
//!    same load. `CUT_SHEET_QUANTITIES=1000,5000` picks other quantities, `CUT_SHEET_DESIGNS=thesis-7`
//!    other example designs.

#[path = "common/child.rs"]
mod child;
#[path = "../tests/common/fixtures.rs"]
mod fixtures;

use actuator_cam::{
    plan_cut_sheet as plan, render_layer_files, CutSheetOptions, Design, Formats, Template,
};
use actuator_model::ModelKind;
use fixtures::{example, example_path, THESIS_DESIGNS};
use std::path::Path;
use std::process::Command;
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
            let files = render_layer_files(&sheet, opts.formats, opts.stroke_mm).expect("render");
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
    let designs: Vec<String> = std::env::var("CUT_SHEET_DESIGNS")
        .ok()
        .map(|s| s.split(',').map(|d| d.trim().to_string()).collect())
        .unwrap_or_else(|| vec!["thesis-C".into()]);
    let ours = env!("CARGO_BIN_EXE_actuator-cam").to_string();
    let peer = std::env::var("ACTUATOR_CAM_PEER").ok();
    println!(
        "\ncut-sheet examples/DESIGN.toml --quantity q -o <new folder>, the binary as a child (load {})",
        child::load()
    );
    // System time is mostly the file system creating ~3 files per actuator; it varies with what else
    // the machine's file system is doing, so it is shown apart from the user time of rendering.
    println!(
        "  design     binary   quantity     wall s     user s      sys s   peak RSS MB   files"
    );
    for design in &designs {
        for &q in &quantities {
            for (label, binary) in peer
                .iter()
                .map(|p| ("peer", p.as_str()))
                .chain([("ours", ours.as_str())])
            {
                let r = run_child(binary, design, q);
                println!(
                    "  {design:<10} {label:<8} {q:>8} {:>10.2} {:>10.2} {:>10.2} {:>13.1} {:>7}",
                    r.wall_s, r.user_s, r.sys_s, r.peak_mb, r.files
                );
            }
        }
    }
    println!("  (load after: {})", child::load());
}

/// Run `binary cut-sheet` of `design` for `q` actuators into a fresh folder and account for the child
/// alone.
fn run_child(binary: &str, design: &str, q: usize) -> Run {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("out");
    let mut command = Command::new(binary);
    command
        .args([
            "cut-sheet",
            &example(&format!("{design}.toml")),
            "--quantity",
        ])
        .arg(q.to_string())
        .arg("-o")
        .arg(&out);
    let u = child::measure(command);
    Run {
        wall_s: u.wall_s,
        user_s: u.user_s,
        sys_s: u.sys_s,
        peak_mb: u.peak_mb,
        files: count_files(&out),
    }
}

fn count_files(dir: &Path) -> usize {
    std::fs::read_dir(dir).map_or(0, |d| d.count())
}
