//! `actuator-cam drive drive.toml`: will the design flap the wing to the required stroke at the flapping
//! frequency, at what voltage and field, through which linkage and at what mass. A stroke out of reach
//! is a failed requirement: the report is printed (and written with `-o`, as the explanation), and the
//! command exits non-zero with one line naming the binding constraint.

use super::flags::{ForceFlag, JsonFlag, ModelFlag};
use actuator_cam::cutsheet::design_for_process;
use actuator_cam::design::Design;
use actuator_cam::drive::spec::DriveSpec;
use actuator_cam::drive::{analyse, DriveError};
use actuator_cam::input::short_number;
use actuator_cam::output::Output;
use actuator_cam::process::template::Template;
use clap::Args;
use std::path::PathBuf;

/// Arguments of `drive`.
#[derive(Debug, Args)]
pub struct DriveArgs {
    /// Drive file: design, wing, transmission, flapping frequency and stroke (see examples/drive-*.toml).
    pub drive: PathBuf,
    /// `--model`: which model predicts the actuator.
    #[command(flatten)]
    pub model: ModelFlag,
    /// `--json` instead of a table.
    #[command(flatten)]
    pub json: JsonFlag,
    /// Write report.md, report.json and frequency-response.svg into this folder.
    #[arg(short = 'o', long = "output", value_name = "DIR")]
    pub output: Option<PathBuf>,
    /// `--force`.
    #[command(flatten)]
    pub force: ForceFlag,
}

/// Run `drive`.
pub fn run(args: &DriveArgs) -> anyhow::Result<()> {
    let spec = DriveSpec::load(&args.drive)?;
    // The design as its process builds it, as `predict` and `cut-sheet` see it.
    let design = Design::load(&spec.design)?;
    let template = Template::resolve(&design.process, &design.source)?;
    let design = design_for_process(&design, &template)?;
    let analysis = analyse(&spec, &design, &args.model.model).map_err(|e| match e {
        // An input error names its own file.
        DriveError::Input(e) => anyhow::anyhow!("{e}"),
        e => anyhow::anyhow!("{}: {e}", args.drive.display()),
    })?;
    let report = &analysis.report;
    let json = serde_json::to_string_pretty(report)? + "\n";
    if args.json.json {
        print!("{json}");
    } else {
        print!("{}", report.table());
    }
    if let Some(dir) = &args.output {
        Output::new("drive")
            .force(args.force.force)
            .inputs([&args.drive, &spec.design])
            .folder(
                "-o",
                dir,
                vec![
                    ("report.md".into(), report.markdown().into_bytes()),
                    ("report.json".into(), json.into_bytes()),
                    ("frequency-response.svg".into(), report.svg().into_bytes()),
                ],
            )
            .write()?;
        if !args.json.json {
            println!("\nwrote {}", dir.display());
        }
    }
    if let Some(u) = &report.unreachable {
        anyhow::bail!(
            "{}: stroke_deg = {}: not reached at {} Hz: the best stroke is ±{:.1}°; binding: {}",
            args.drive.display(),
            short_number(report.required_stroke_deg),
            short_number(report.frequency_Hz),
            u.best_stroke_deg,
            u.binding
        );
    }
    Ok(())
}
