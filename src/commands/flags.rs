//! Flags that several subcommands share, each defined once and pulled in with `#[command(flatten)]`, with
//! the one parser of each value.

use actuator_cam::calibrate::model_file;
use actuator_cam::cutsheet::Formats;
use actuator_cam::input::InputError;
use actuator_model::model::{ModelChoice, ModelKind};
use clap::Args;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// `-o DIR`: the folder a command writes its files into. The default is `out`; a command with another
/// default sets it with `#[command(mut_arg("output", |a| a.default_value(...)))]`.
#[derive(Debug, Clone, Args)]
pub struct OutputDir {
    /// Output folder: new, empty, or one actuator-cam wrote before (it replaces only its own files there).
    #[arg(
        short = 'o',
        long = "output",
        value_name = "DIR",
        default_value = "out"
    )]
    pub output: PathBuf,
    /// `--force` goes with every output folder.
    #[command(flatten)]
    pub force: ForceFlag,
}

/// `--force`: the user's word that a run may write into a folder that holds other files.
#[derive(Debug, Clone, Args)]
pub struct ForceFlag {
    /// Write into a folder that holds files actuator-cam did not write, replacing files of the same name
    /// (never an input of the run; nothing else in the folder is removed).
    #[arg(long)]
    pub force: bool,
}

/// `--format svg,dxf`: which layer-file formats to write.
#[derive(Debug, Clone, Args)]
pub struct FormatFlag {
    /// File formats, comma separated.
    #[arg(long = "format", value_delimiter = ',', default_value = "svg,dxf", value_parser = parse_format)]
    format: Vec<Formats>,
}

impl FormatFlag {
    /// Every format named.
    pub fn formats(&self) -> Formats {
        self.format.iter().fold(
            Formats {
                svg: false,
                dxf: false,
            },
            |a, b| Formats {
                svg: a.svg || b.svg,
                dxf: a.dxf || b.dxf,
            },
        )
    }
}

/// One entry of `--format`.
fn parse_format(text: &str) -> Result<Formats, String> {
    match text {
        "svg" => Ok(Formats {
            svg: true,
            dxf: false,
        }),
        "dxf" => Ok(Formats {
            svg: false,
            dxf: true,
        }),
        _ => Err("expected svg, dxf or svg,dxf".into()),
    }
}

/// `--stroke-mm`: hairline width of the SVG files.
#[derive(Debug, Clone, Args)]
pub struct StrokeFlag {
    /// Hairline stroke width in the SVG files, mm.
    #[arg(long, default_value_t = 0.0254, value_parser = parse_stroke_mm)]
    pub stroke_mm: f64,
}

/// `--stroke-mm`: (0, 1] mm, the range a laser's hairline setting reads.
fn parse_stroke_mm(text: &str) -> Result<f64, String> {
    let mm: f64 = text.parse().map_err(|_| "not a number".to_string())?;
    if mm.is_finite() && mm > 0.0 && mm <= 1.0 {
        Ok(mm)
    } else {
        Err("outside the allowed range (0, 1] mm".into())
    }
}

/// `--model`: which model predicts.
#[derive(Debug, Clone, Args)]
pub struct ModelFlag {
    /// Model: original, thesis-adjusted, euler-bernoulli, or a calibrated-model.toml written by `calibrate`.
    #[arg(long, default_value = "original", value_parser = parse_model)]
    pub model: ModelChoice,
}

/// `--json`: the report as JSON on standard output.
#[derive(Debug, Clone, Args)]
pub struct JsonFlag {
    /// Print the report as one JSON object on standard output instead of the text summary.
    #[arg(long)]
    pub json: bool,
}

/// The built-in names, for help and errors.
pub const BUILT_IN: &str = "original, thesis-adjusted, euler-bernoulli";

/// The one parser of a model on the command line (`--model`, `sweep --compare`): a built-in name, or the
/// path of a `calibrated-model.toml`, which is read here.
pub fn parse_model(text: &str) -> Result<ModelChoice, String> {
    let kind = match text {
        "original" => Some(ModelKind::Original),
        "thesis-adjusted" => Some(ModelKind::ThesisAdjusted),
        "euler-bernoulli" => Some(ModelKind::EulerBernoulli),
        _ => None,
    };
    if let Some(k) = kind {
        return Ok(ModelChoice::Kind(k));
    }
    let path = Path::new(text);
    if !path.exists() {
        return Err(format!(
            "unknown model; expected one of {BUILT_IN}, or a calibrated-model.toml file"
        ));
    }
    let model = model_file::load(path).map_err(|e| without_the_file(&e, text))?;
    Ok(ModelChoice::Calibrated(Arc::new(model)))
}

/// A refusal of the file the flag names, without the file: a refused value is printed after the
/// flag and the value (`--model "F": reason`, src/main.rs), which names the file once already.
fn without_the_file(e: &InputError, text: &str) -> String {
    let message = e.to_string();
    if e.file != text {
        return message;
    }
    message
        .strip_prefix(&format!("{}: ", e.file))
        .map_or(message.clone(), str::to_string)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn built_in_model_names_round_trip_and_others_are_refused() {
        for name in ["original", "thesis-adjusted", "euler-bernoulli"] {
            assert_eq!(parse_model(name).unwrap().name(), name);
        }
        let e = parse_model("no-such-model").unwrap_err();
        assert!(e.contains("unknown model") && e.contains(BUILT_IN), "{e}");
    }

    #[test]
    fn a_refused_model_file_is_named_by_the_flag_alone() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("calibrated-model.toml");
        std::fs::write(
            &file,
            "model = \"calibrated\"\nverdict = \"x\"\nselected_effects = []\n[effects]\nd31_scale = 9\n",
        )
        .unwrap();
        let text = file.to_str().unwrap();
        // The field, its value and what is allowed; the file is left to the flag's `--model "F":`.
        assert_eq!(
            parse_model(text).unwrap_err(),
            "effects.d31_scale = 9: outside the allowed range [0.05, 3]"
        );
    }

    #[test]
    fn formats_and_stroke_are_checked_by_their_parsers() {
        assert!(parse_format("svg").unwrap().svg);
        assert!(parse_format("png").is_err());
        assert_eq!(parse_stroke_mm("0.1"), Ok(0.1));
        for bad in ["0", "-1", "2", "NaN", "x"] {
            assert!(parse_stroke_mm(bad).is_err(), "{bad}");
        }
    }
}
