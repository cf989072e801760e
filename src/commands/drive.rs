//! `actuator-cam drive drive.toml`: will the design flap the wing to the required stroke at the flapping
//! frequency, at what voltage and field, through which linkage and at what mass. A stroke out of reach
//! is a failed requirement: the report is printed (and written with `-o`, as the explanation), and the
//! command exits non-zero with one line naming the binding constraint.

use super::flags::{JsonFlag, ModelFlag, OutputDir};
use actuator_cam::{
    analyse_drive, design_for_process, short_number, Design, DriveError, DriveSpec, Output,
    Template,
};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `drive`.
#[derive(Debug, Args)]
#[command(mut_arg("output", |a| a.default_value(None::<&str>)))]
pub struct DriveArgs {
    /// Drive file: design, wing, transmission, flapping frequency and stroke (see examples/drive-*.toml).
    pub drive: PathBuf,
    /// `--model`: which model predicts the actuator.
    #[command(flatten)]
    pub model: ModelFlag,
    /// `--json` instead of a table.
    #[command(flatten)]
    pub json: JsonFlag,
    /// `-o`: report.md, report.json and frequency-response.svg, when given.
    #[command(flatten)]
    pub output: OutputDir,
}

/// Run `drive`.
pub fn run(args: &DriveArgs) -> anyhow::Result<()> {
    let spec = DriveSpec::load(&args.drive)?;
    // The design as its process builds it, as `predict` and `cut-sheet` see it.
    let design = Design::load(&spec.design)?;
    let template = Template::resolve(&design.process, &design.source)?;
    let design = design_for_process(&design, &template)?;
    args.output.check_ahead(
        "drive",
        [&args.drive, &spec.design],
        &["report.md", "report.json", "frequency-response.svg"],
    )?;
    let analysis = analyse_drive(&spec, &design, &args.model.model).map_err(|e| match e {
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
    if let Some(dir) = args.output.folder() {
        Output::new("drive")
            .force(args.output.force.force)
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
    if let Some(why) = &report.unbuildable_linkage {
        anyhow::bail!(
            "{}: transmission: the linkage cannot be built: {why}",
            args.drive.display()
        );
    }
    if let Some(why) = &report.past_small_deflection {
        anyhow::bail!(
            "{}: stroke_deg = {}: {why}",
            args.drive.display(),
            short_number(report.required_stroke_deg)
        );
    }
    if let Some(why) = &report.unsettled_field {
        anyhow::bail!("{}: --model {}: {why}", args.drive.display(), report.model);
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
