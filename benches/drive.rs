//! `cargo bench --bench drive`: time of one `drive` analysis (prediction, lumped model, linkage, the
//! stroke's harmonic balance and the 61-point frequency sweep, the report built in memory) for each
//! example drive file. Prints the median and the slowest of 21 runs, and the machine's load.

#[path = "../tests/common/fixtures.rs"]
mod fixtures;

use actuator_cam::{analyse_drive as analyse, design_for_process, Design, DriveSpec, Template};
use actuator_model::model::{ModelChoice, ModelKind};
use fixtures::example_path;
use std::time::Instant;

fn main() {
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "drive, one analysis with its frequency sweep (21 runs); /proc/loadavg {}",
        load.trim()
    );
    let model = ModelChoice::Kind(ModelKind::Original);
    for name in [
        "drive-hawkmoth.toml",
        "drive-robobee-jafferis2016-linkage.toml",
    ] {
        let mut times = Vec::new();
        for _ in 0..21 {
            let start = Instant::now();
            let spec = DriveSpec::load(&example_path(name)).expect("example drive file loads");
            let design = Design::load(&spec.design).expect("its design loads");
            let template = Template::resolve(&design.process, &design.source).expect("template");
            let design = design_for_process(&design, &template).expect("process");
            let a = analyse(&spec, &design, &model).expect("analysis");
            let _ = std::hint::black_box(a.report.table());
            times.push(start.elapsed().as_secs_f64() * 1e3);
        }
        times.sort_by(f64::total_cmp);
        println!(
            "{name}: median {:.2} ms, slowest {:.2} ms",
            times[times.len() / 2],
            times[times.len() - 1]
        );
    }
}
