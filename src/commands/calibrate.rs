//! `actuator-cam calibrate measured.csv -o calibration/`: trace measured-vs-model errors to a physical
//! effect and write `calibrated-model.toml`, the reports and the plots.

use super::flags::{self, JsonFlag, OutputDir};
use actuator_cam::{
    calibrate, calibration_summary, read_effects, read_measured, render_calibration, Declared,
    Output, Settings,
};
use anyhow::Context;
use clap::Args;
use std::path::PathBuf;

/// Arguments of `calibrate`.
#[derive(Debug, Clone, Args)]
#[command(mut_arg("output", |a| a.default_value("calibration")))]
pub struct CalibrateArgs {
    /// Measured data, CSV with columns
    /// id,l_tot_mm,l_r,w0_mm,w_r,t_p_mm,layup,voltage_V,mass_mg,free_deflection_mm,blocked_force_N
    /// (optional drive, pzt, ply, base_tab_mm).
    pub measured: PathBuf,
    /// `-o`: calibrated-model.toml, report.json, report.md and the SVG plots.
    #[command(flatten)]
    pub output: OutputDir,
    /// `--json`: report.json on standard output.
    #[command(flatten)]
    pub json: JsonFlag,
    /// Seed of the cross-validation folds.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub seed: u64,
    /// Largest number of effects (besides the d31 scale) combined in one model, 0 to 2.
    #[arg(long, value_name = "N", default_value_t = 2, value_parser = flags::max_effects)]
    pub max_effects: usize,
    /// Effects this lab declares (effects.toml: compositions of the model's primitives with a
    /// parameter, bounds and a null value), fitted as candidates beside the library's.
    #[arg(long, value_name = "FILE")]
    pub effects: Option<PathBuf>,
}

/// Run `calibrate`: read, analyse, then write every output at once (nothing is written on an error).
pub fn run(args: &CalibrateArgs) -> anyhow::Result<()> {
    // The input layer's error names the file already.
    let data = read_measured(&args.measured)?;
    if let Some(warning) = data.unknown_columns_warning(&args.measured) {
        eprintln!("warning: {warning}");
    }
    let declared = match &args.effects {
        Some(path) => read_effects(path)?
            .into_iter()
            .flat_map(Declared::all)
            .collect(),
        None => Vec::new(),
    };
    args.output.check_ahead(
        "calibrate",
        std::iter::once(&args.measured).chain(&args.effects),
        &[],
    )?;
    let settings = Settings {
        seed: args.seed,
        max_effects: args.max_effects,
        declared,
        ..Settings::default()
    };
    // The library's fit and row errors name the line, not the file.
    let calibration =
        calibrate(&data, &settings).with_context(|| args.measured.display().to_string())?;
    let source = args
        .measured
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let files = render_calibration(&calibration, &data, &source)?;
    let json = files
        .iter()
        .find(|(name, _)| name == "report.json")
        .map(|(_, text)| text.clone())
        .unwrap_or_else(|| "{}".into());
    let dir = args.output.required();
    Output::new("calibrate")
        .force(args.output.force.force)
        .inputs(std::iter::once(&args.measured).chain(&args.effects))
        .folder(
            "-o",
            dir,
            files
                .into_iter()
                .map(|(name, text)| (name, text.into_bytes()))
                .collect(),
        )
        .write()?;
    if args.json.json {
        println!("{json}");
    } else {
        print!("{}", calibration_summary(&calibration));
        println!("wrote {}", dir.display());
    }
    Ok(())
}
