//! `cargo bench --bench cut_sheet`: time to plan and render a cut sheet (every layer, SVG + DXF, report)
//! for 50 actuators of each thesis example design, in memory. Prints the median of 7 runs per design.

#[path = "../tests/common/fixtures.rs"]
mod fixtures;

use actuator_cam::cutsheet::{plan, write, CutSheetOptions, Formats, Template};
use actuator_cam::design::Design;
use actuator_model::ModelKind;
use fixtures::{example_path, THESIS_DESIGNS};
use std::time::Instant;

fn main() {
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
