//! `cargo bench --bench nest`: time to plan and render a batch (every layer, SVG + DXF, report) in
//! memory, for examples/batch.toml and the same designs scaled to 60 and 150 actuators. Prints the
//! median of 5 runs, the sheets used and the passive utilisation against the bounding-box baseline.

#[path = "../tests/common/fixtures.rs"]
mod fixtures;

use actuator_cam::{plan_nest, render_drawings, Batch, Formats, NestOptions, SvgOptions};
use fixtures::example_path;
use std::time::Instant;

fn main() {
    let example = Batch::load(&example_path("batch.toml")).expect("example batch loads");
    let opts = NestOptions::budget(example.seed, 1000);
    let formats = Formats {
        svg: true,
        dxf: true,
    };
    println!(
        "nest, {} iterations, 2 workers, SVG + DXF + report in memory (median of 5 runs)",
        opts.iterations
    );
    for scale in [1.0, 2.5, 6.25] {
        let mut batch = example.clone();
        for item in &mut batch.items {
            item.quantity = (item.quantity as f64 * scale).round() as usize;
        }
        let actuators: usize = batch.items.iter().map(|i| i.quantity).sum();
        let mut times = Vec::new();
        let mut summary = String::new();
        for _ in 0..5 {
            let start = Instant::now();
            let planned = plan_nest(&batch, &opts).expect("plan");
            let files = render_drawings(
                &planned.drawings,
                formats,
                &SvgOptions {
                    stroke_mm: 0.0254,
                    palette: batch.template.palette.clone(),
                },
            )
            .expect("render");
            times.push(start.elapsed().as_secs_f64());
            let r = &planned.report;
            let passive: Vec<String> = r.baseline.iter().map(|b| b.summary()).collect();
            summary = format!(
                "{} files, {} PZT sheets, {} panels; {}",
                files.len(),
                r.sheets_of("pzt"),
                r.clamp_panels.len(),
                passive.join("; ")
            );
        }
        times.sort_by(f64::total_cmp);
        println!(
            "  {actuators:>4} actuators {:>8.1} ms   {summary}",
            times[2] * 1e3
        );
    }
}
