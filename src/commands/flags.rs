//! Every flag's value: the one parser of each, with its range, in ripgrep's manner (one definition holds
//! the name, the help, the parse and the range). A flag several subcommands share is a struct here,
//! pulled in with `#[command(flatten)]`; a flag of one subcommand names its parser from here in its
//! `#[arg]`. Every refusal is clap's value error, which `src/main.rs` prints in the tool's one format,
//! `--flag "value": reason`, exit status 1. The ranges themselves are the library's (`input::limits`,
//! with their reasons in docs/limits.md), so a flag and the file field it overrides allow the same.

use actuator_cam::{
    limits, load_calibrated_model, parse_layup, Formats, InputError, Output, Range,
};
use actuator_model::model::{ModelChoice, ModelKind};
use actuator_model::Material;
use clap::Args;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// `-o DIR`: the folder a command writes its files into, in every command. A command whose work is its
/// files (cut-sheet, nest: `out`; calibrate: `calibration`) has a default; one whose work is the
/// printed report (drive, optimize) writes files only when `-o` is given, which it states with
/// `#[command(mut_arg("output", |a| a.default_value(None::<&str>)))]`.
#[derive(Debug, Clone, Args)]
pub struct OutputDir {
    /// Output folder: new, empty, or one actuator-cam wrote before (it replaces only its own files there).
    #[arg(
        short = 'o',
        long = "output",
        value_name = "DIR",
        default_value = "out"
    )]
    output: Option<PathBuf>,
    /// `--force` goes with every output folder.
    #[command(flatten)]
    pub force: ForceFlag,
}

impl OutputDir {
    /// The folder, when one is given or defaulted.
    pub fn folder(&self) -> Option<&Path> {
        self.output.as_deref()
    }

    /// The folder of a command that always has one (its `-o` has a default).
    pub fn required(&self) -> &Path {
        self.output.as_deref().unwrap_or(Path::new("out"))
    }

    /// The folder, when there is one, checked against the output policy before `command`'s work
    /// ([`Output::check_folder_ahead`]), with the `names` the run writes there whatever it finds.
    pub fn check_ahead<P: AsRef<Path>>(
        &self,
        command: &str,
        inputs: impl IntoIterator<Item = P>,
        names: &[&str],
    ) -> anyhow::Result<()> {
        if let Some(dir) = self.folder() {
            Output::new(command)
                .force(self.force.force)
                .inputs(inputs)
                .check_folder_ahead("-o", dir, names)?;
        }
        Ok(())
    }
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
    /// Layer-file formats, comma separated.
    #[arg(long = "format", value_name = "svg,dxf", value_delimiter = ',', default_value = "svg,dxf", value_parser = parse_format)]
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
    /// Hairline stroke width of the SVG files, mm.
    #[arg(long, value_name = "MM", default_value_t = 0.0254, value_parser = stroke_mm)]
    pub stroke_mm: f64,
}

/// `--model`: which model predicts.
#[derive(Debug, Clone, Args)]
pub struct ModelFlag {
    /// Model: original, thesis-adjusted, nonlinear (the field-dependent, bimodular ceramic of Jafferis et
    /// al. 2015), euler-bernoulli, or a calibrated-model.toml written by `calibrate`.
    #[arg(long, value_name = "MODEL", default_value = "original", value_parser = parse_model)]
    pub model: ModelChoice,
}

/// `--model` of a sweep: a built-in model only, since a sweep solves each laminate once and predicts
/// every design from it, which a calibrated model (it changes the stack) cannot share.
#[derive(Debug, Clone, Args)]
pub struct BuiltInModelFlag {
    /// Model: original, thesis-adjusted, nonlinear or euler-bernoulli (a built-in model: a sweep shares
    /// one laminate solution across designs, which a calibrated model's stack changes).
    #[arg(long, value_name = "MODEL", default_value = "original", value_parser = parse_built_in_model)]
    pub model: ModelKind,
}

/// `--json`: the report as JSON on standard output.
#[derive(Debug, Clone, Args)]
pub struct JsonFlag {
    /// Print the report as one JSON object on standard output instead of the text summary.
    #[arg(long)]
    pub json: bool,
}

/// The built-in names, for help and errors.
pub const BUILT_IN: &str = "original, thesis-adjusted, nonlinear, euler-bernoulli";

/// A built-in model's name.
fn built_in(text: &str) -> Option<ModelKind> {
    match text {
        "original" => Some(ModelKind::Original),
        "thesis-adjusted" => Some(ModelKind::ThesisAdjusted),
        "nonlinear" => Some(ModelKind::Nonlinear),
        "euler-bernoulli" => Some(ModelKind::EulerBernoulli),
        _ => None,
    }
}

/// The one parser of a model on the command line (`--model`): a built-in name, or the path of a
/// `calibrated-model.toml`, which is read here.
pub fn parse_model(text: &str) -> Result<ModelChoice, String> {
    if let Some(k) = built_in(text) {
        return Ok(ModelChoice::Kind(k));
    }
    let path = Path::new(text);
    if !path.exists() {
        return Err(format!(
            "unknown model; expected one of {BUILT_IN}, or a calibrated-model.toml file"
        ));
    }
    let model = load_calibrated_model(path).map_err(|e| without_the_file(&e, text))?;
    Ok(ModelChoice::Calibrated(Arc::new(model)))
}

/// A built-in model only (`sweep --model`, `sweep --compare`).
pub fn parse_built_in_model(text: &str) -> Result<ModelKind, String> {
    built_in(text).ok_or_else(|| {
        format!(
            "unknown model for a sweep; expected a built-in model, one of {BUILT_IN} (a calibrated model is not swept)"
        )
    })
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

/// A number within `range`, or why not: the reason clap's value error carries.
fn number_in(text: &str, range: Range) -> Result<f64, String> {
    let x: f64 = text
        .trim()
        .parse()
        .map_err(|_| "not a number".to_string())?;
    if range.contains(x) {
        Ok(x)
    } else {
        Err(format!("outside the {range}"))
    }
}

/// A whole number within `[lo, hi]`, or why not.
fn count_in(text: &str, lo: i64, hi: i64) -> Result<i64, String> {
    let n: i64 = text
        .trim()
        .parse()
        .map_err(|_| "not a whole number".to_string())?;
    if (lo..=hi).contains(&n) {
        Ok(n)
    } else {
        Err(format!("outside the allowed range [{lo}, {hi}]"))
    }
}

/// `--stroke-mm`: (0, 1] mm, the range a laser's hairline setting reads.
pub fn stroke_mm(text: &str) -> Result<f64, String> {
    number_in(text, limits::STROKE_MM)
}

/// `--kerf-mm`: the template's kerf range.
pub fn kerf_mm(text: &str) -> Result<f64, String> {
    number_in(text, limits::KERF_MM)
}

/// `--quantity`: actuators of one design, as a design's `quantity`.
pub fn quantity(text: &str) -> Result<usize, String> {
    count_in(text, 1, limits::MAX_QUANTITY).map(|n| n as usize)
}

/// `--iterations`: the nester's budget, as a batch's `iterations`.
pub fn iterations(text: &str) -> Result<usize, String> {
    count_in(text, 0, limits::MAX_ITERATIONS).map(|n| n as usize)
}

/// `--max-effects`: effects besides the d31 scale combined in one calibrated model.
pub fn max_effects(text: &str) -> Result<usize, String> {
    count_in(text, 0, 2).map(|n| n as usize)
}

/// `--pzt-thickness-mm`: a plate thickness, as a design's `pzt_thickness_mm`.
pub fn pzt_thickness_mm(text: &str) -> Result<f64, String> {
    number_in(text, limits::PZT_THICKNESS_MM)
}

/// One rate of `--survival`: strictly between 0 and 1.
pub fn survival(text: &str) -> Result<f64, String> {
    number_in(text, Range::open(0.0, 1.0, ""))
}

/// `--time`: seconds, or a number with `s`, `m` or `h`, within `NEST_TIME_S`.
pub fn time_s(text: &str) -> Result<f64, String> {
    let t = text.trim();
    let (number, unit) = match t.char_indices().last() {
        Some((i, 's')) => (&t[..i], 1.0),
        Some((i, 'm')) => (&t[..i], 60.0),
        Some((i, 'h')) => (&t[..i], 3600.0),
        _ => (t, 1.0),
    };
    let range = limits::NEST_TIME_S;
    number
        .trim()
        .parse::<f64>()
        .ok()
        .map(|n| n * unit)
        .filter(|s| range.contains(*s))
        .ok_or_else(|| format!("a time such as 30s, 2m or 90 (seconds), within {range}"))
}

/// `--layup 0/90/0`: ply angles bottom to top, as a design's `layup`, and the text as written.
#[derive(Debug, Clone)]
pub struct Layup {
    /// Angles, degrees, bottom to top.
    pub angles: Vec<f64>,
    /// As the user wrote it, for the report's heading.
    pub text: String,
}

/// `--layup`.
pub fn layup(text: &str) -> Result<Layup, String> {
    parse_layup(text)
        .map(|angles| Layup {
            angles,
            text: text.to_string(),
        })
        .map_err(|e| e.to_string())
}

/// `--ply`, `--pzt`: a material of the built-in library, by name.
pub fn material(text: &str) -> Result<Material, String> {
    Material::builtin(text).ok_or_else(|| {
        format!(
            "unknown material; the built-in library has {}",
            actuator_model::material::builtin_names().join(", ")
        )
    })
}

/// `--ply`: a passive material of the built-in library with a standard ply thickness (the layup is
/// counted in plies).
pub fn ply_material(text: &str) -> Result<Material, String> {
    let m = material(text)?;
    if m.ply_thickness.is_none() {
        return Err(format!("{} has no standard ply thickness", m.name));
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn built_in_model_names_round_trip_and_others_are_refused() {
        for name in [
            "original",
            "thesis-adjusted",
            "nonlinear",
            "euler-bernoulli",
        ] {
            assert_eq!(parse_model(name).unwrap().name(), name);
            assert_eq!(parse_built_in_model(name).unwrap().name(), name);
        }
        let e = parse_model("no-such-model").unwrap_err();
        assert!(e.contains("unknown model") && e.contains(BUILT_IN), "{e}");
        let e = parse_built_in_model("calibration/calibrated-model.toml").unwrap_err();
        assert!(e.contains("built-in") && e.contains(BUILT_IN), "{e}");
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
    fn every_number_is_checked_against_its_range_by_its_parser() {
        assert!(parse_format("svg").unwrap().svg);
        assert!(parse_format("png").is_err());
        assert_eq!(stroke_mm("0.1"), Ok(0.1));
        for bad in ["0", "-1", "2", "NaN", "x", "inf"] {
            assert!(stroke_mm(bad).is_err(), "{bad}");
        }
        assert_eq!(kerf_mm("0.05"), Ok(0.05));
        assert_eq!(
            kerf_mm("9").unwrap_err(),
            "outside the allowed range [0, 2] mm"
        );
        assert_eq!(quantity("3"), Ok(3));
        assert_eq!(
            quantity("0").unwrap_err(),
            "outside the allowed range [1, 100000]"
        );
        assert_eq!(quantity("1.5").unwrap_err(), "not a whole number");
        assert_eq!(iterations("0"), Ok(0));
        assert!(iterations("10000001").is_err());
        assert!(max_effects("3").is_err());
        assert!(pzt_thickness_mm("0.01").is_err());
        assert!(survival("1").is_err() && survival("0").is_err());
        assert_eq!(survival("0.9"), Ok(0.9));
        assert_eq!(time_s("2m"), Ok(120.0));
        assert!(time_s("0s").is_err() && time_s("2d").is_err());
        assert_eq!(layup("0/90/0").unwrap().angles, vec![0.0, 90.0, 0.0]);
        assert!(layup("0/x").is_err());
        assert!(material("PZT-5H").is_ok());
        assert!(ply_material("CF-thesis").is_ok());
        assert!(ply_material("PZT-5H")
            .unwrap_err()
            .contains("no standard ply thickness"));
        assert!(material("unobtainium")
            .unwrap_err()
            .contains("built-in library"));
    }
}
