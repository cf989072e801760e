//! `actuator-cam optimize spec.toml`: the lightest actuator (or the highest energy density) for a required
//! mechanical energy, with the winning design and the Pareto front written on request.

use super::flags::{ForceFlag, ModelFlag};
use actuator_cam::drive::analyse;
use actuator_cam::drive::spec::{DriveSpec, LinkageSpec};
use actuator_cam::input::short_number;
use actuator_cam::optimize::flap::{optimize_flap, wing_load};
use actuator_cam::optimize::flap_report;
use actuator_cam::optimize::model::SearchModel;
use actuator_cam::optimize::search::{Design, FieldLimit, Objective, Problem};
use actuator_cam::optimize::spec::Spec;
use actuator_cam::optimize::{
    optimize, pareto, report, OptimizeError, Progress, Silent, PARETO_LEVELS,
};
use actuator_cam::output::Output;
use actuator_cam::transmission::TransmissionSpec;
use actuator_model::primitives::Primitive;
use actuator_model::ModelChoice;
use anyhow::{bail, Context};
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Arc;

/// Grids above this many designs show a progress bar (on a terminal only).
const PROGRESS_ABOVE: u64 = 20_000_000;

/// Arguments of `optimize`.
#[derive(Debug, Clone, Args)]
pub struct OptimizeArgs {
    /// Spec file: requirement, drive, search ranges, laminate, constraints (see examples/optimize-*.toml).
    pub spec: PathBuf,
    /// `--model` to optimise with (the Euler-Bernoulli beam has no taper to optimise).
    #[command(flatten)]
    pub model: ModelFlag,
    /// What to optimise.
    #[arg(long, value_enum, default_value_t = ObjectiveArg::MinMass)]
    pub objective: ObjectiveArg,
    /// Write the winning design as a design.toml (cut-sheet reads it).
    #[arg(short = 'o', long = "output", value_name = "DESIGN_TOML")]
    pub output: Option<PathBuf>,
    /// Write the front of mass against delivered energy as CSV, and beside it an SVG plot.
    #[arg(long, value_name = "CSV")]
    pub pareto: Option<PathBuf>,
    /// `--force`.
    #[command(flatten)]
    pub force: ForceFlag,
}

/// `--objective`: what the search minimises.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ObjectiveArg {
    /// Lightest actuator with `U >= U_min`.
    MinMass,
    /// Highest `U / m` with `U >= U_min` (then the lightest such).
    MaxEnergyDensity,
}

impl From<ObjectiveArg> for Objective {
    fn from(o: ObjectiveArg) -> Objective {
        match o {
            ObjectiveArg::MinMass => Objective::MinMass,
            ObjectiveArg::MaxEnergyDensity => Objective::MaxEnergyDensity,
        }
    }
}

/// The search model for `--model`: a built-in name or a `calibrated-model.toml`.
fn search_model(choice: &ModelChoice) -> anyhow::Result<SearchModel> {
    match choice {
        ModelChoice::Calibrated(m) => {
            let model = m.effect_model()?;
            // The search scales the mass as l_tot w_0 per shape; a mass per actuator or per outline
            // length does not scale so.
            if let Some(d) = m.declared.iter().find(|d| {
                d.primitives.iter().any(|l| {
                    matches!(
                        l.primitive,
                        Primitive::AddedMass | Primitive::AddedMassPerLength
                    )
                })
            }) {
                bail!(
                    "--model: the declared effect {} adds a mass per actuator or per outline length, which the optimizer's search (mass proportional to l_tot w_0 per shape) does not take; use predict --model to evaluate designs with it",
                    d.name
                );
            }
            Ok(SearchModel::Calibrated(Arc::new(model)))
        }
        ModelChoice::Kind(kind) => SearchModel::from_kind(*kind).with_context(|| {
            format!(
                "--model {}: the Euler-Bernoulli beam covers rectangles only and has no taper or extension to optimise; use original, thesis-adjusted or a calibrated-model.toml",
                kind.name()
            )
        }),
    }
}

/// The exhaustive stage's progress as a bar on stderr.
struct Bar(ProgressBar);

impl Bar {
    fn new() -> Bar {
        Bar(
            ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr()).with_style(
                ProgressStyle::with_template("exhaustive grid {wide_bar} {percent}%")
                    .unwrap_or_else(|_| ProgressStyle::default_bar()),
            ),
        )
    }
}

impl Progress for Bar {
    fn start(&self, total: u64) {
        self.0.set_length(total);
    }
    fn advance(&self, steps: u64) {
        self.0.inc(steps);
    }
    fn finish(&self) {
        self.0.finish_and_clear();
    }
}

/// Run `optimize`.
pub fn run(args: &OptimizeArgs) -> anyhow::Result<()> {
    let model = search_model(&args.model.model)?;
    let spec = Spec::from_file(&args.spec)?;
    let file = args.spec.display().to_string();
    if let Some(flap) = &spec.flap {
        return run_flap(args, &spec, model, flap);
    }
    let problem = Problem::from_spec(&spec, model, args.objective.into())
        .with_context(|| format!("{file}: the laminate cannot be solved"))?;
    let bar =
        (problem.grid_size() > PROGRESS_ABOVE && std::io::stderr().is_terminal()).then(Bar::new);
    let progress: &dyn Progress = match &bar {
        Some(b) => b,
        None => &Silent,
    };
    let outcome = optimize(problem, progress).map_err(|e| match e {
        // Blame what holds the energy down: a voltage or strain cap the user wrote, or else the
        // requirement itself.
        OptimizeError::Infeasible { limit, .. } => match (limit, spec.max_voltage) {
            (FieldLimit::Voltage, Some(v)) => {
                anyhow::anyhow!("{file}: drive.max_voltage_V = {}: {e}", short_number(v))
            }
            (FieldLimit::Strain, _) => anyhow::anyhow!(
                "{file}: constraints.max_peak_pzt_strain = {}: {e}",
                spec.max_peak_pzt_strain.map_or("-".into(), short_number)
            ),
            _ => anyhow::anyhow!(
                "{file}: requirement.energy_mJ = {}: {e}",
                short_number(spec.energy * 1e3)
            ),
        },
    })?;
    let best = outcome.best;
    let perf = outcome
        .problem
        .performance(&best)
        .with_context(|| format!("{file}: the optimum cannot be predicted"))?;
    if perf.energy < spec.energy * (1.0 - 1e-9) {
        bail!(
            "internal: the optimum delivers {} mJ < {} mJ",
            perf.energy * 1e3,
            spec.energy * 1e3
        );
    }
    print!("{}", report::text(&spec, &file, &outcome, &perf));
    let mut output = Output::new("optimize")
        .force(args.force.force)
        .inputs([&args.spec]);
    let mut wrote = Vec::new();
    if let Some(path) = &args.output {
        output = output.file(
            "-o",
            path,
            report::design_toml(&spec, &outcome.problem, &best),
        );
        wrote.push(format!("\nwrote {}", path.display()));
    }
    if let Some(path) = &args.pareto {
        let most: Vec<Design> = outcome.most_energy.iter().flatten().copied().collect();
        let front = pareto::front(&outcome.problem, &most, PARETO_LEVELS);
        let svg = path.with_extension("svg");
        output = output
            .file("--pareto", path, pareto::to_csv(&outcome.problem, &front)?)
            .file(
                "--pareto",
                &svg,
                pareto::to_svg(&front, spec.energy, Some(&best)),
            );
        wrote.push(format!(
            "wrote {} and {} ({} designs on the front)",
            path.display(),
            svg.display(),
            front.len()
        ));
    }
    output.write()?;
    for line in wrote {
        println!("{line}");
    }
    Ok(())
}

/// `optimize` with `requirement.flap`: the lightest design that flaps the drive file's wing, its drive
/// file beside the design file, and the front of mass against frequency margin.
fn run_flap(
    args: &OptimizeArgs,
    spec: &Spec,
    model: SearchModel,
    flap: &std::path::Path,
) -> anyhow::Result<()> {
    let file = args.spec.display().to_string();
    if args.objective != ObjectiveArg::MinMass {
        bail!(
            "{file}: requirement.flap: --objective {}: a wing is flapped by the lightest design (min-mass) only",
            args.objective
                .to_possible_value()
                .map_or(String::new(), |v| v.get_name().to_string())
        );
    }
    let drive = DriveSpec::load(flap)?;
    let load = wing_load(&drive, &args.model.model)?;
    let problem = Problem::from_spec(spec, model, Objective::MinMass)
        .with_context(|| format!("{file}: the laminate cannot be solved"))?;
    let outcome = optimize_flap(spec, &problem, &load, &args.model.model)
        .map_err(|e| anyhow::anyhow!("{file}: requirement.flap = {}: {e}", flap.display()))?;
    let chosen = &outcome.chosen;
    let cand = &problem.candidates[chosen.design.candidate];
    let survival = flap_report::survival_at(cand.section.drive.field, cand.section.drive.mode);
    // The chosen design driven as `drive` will drive it from the files written here.
    let design_path = args
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from("optimized.toml"));
    let design_name = design_path
        .file_name()
        .map_or("optimized.toml".to_string(), |n| {
            n.to_string_lossy().into_owned()
        });
    let check = DriveSpec {
        design: design_path.clone(),
        survival,
        transmission: TransmissionSpec {
            linkage: match drive.transmission.linkage {
                LinkageSpec::Solve {
                    angle_minus,
                    angle_plus,
                    coupler_ratio,
                    ..
                } => LinkageSpec::Solve {
                    angle_minus,
                    angle_plus,
                    coupler_ratio,
                    travel: Some(chosen.travel),
                },
                given => given,
            },
            ..drive.transmission.clone()
        },
        ..drive.clone()
    };
    let analysis = analyse(&check, &chosen.built, &args.model.model)
        .map_err(|e| anyhow::anyhow!("{file}: the optimized design's drive: {e}"))?;
    if !analysis.report.reached {
        bail!(
            "internal: the optimized design does not reach the stroke when driven: {}",
            analysis
                .report
                .unreachable
                .as_ref()
                .map_or(String::new(), |u| u.binding.clone())
        );
    }
    print!(
        "{}",
        flap_report::text(spec, &file, &problem, &outcome, &analysis.report)
    );
    let mut output = Output::new("optimize")
        .force(args.force.force)
        .inputs([&args.spec, &flap.to_path_buf()]);
    let mut wrote = Vec::new();
    if let Some(path) = &args.output {
        let drive_path = path.with_file_name(format!("drive-{design_name}"));
        let drive_text =
            flap_report::drive_toml(flap, &file, &design_name, survival, chosen.travel)?;
        output =
            output
                .file("-o", path, chosen.design_toml.clone())
                .file("-o", &drive_path, drive_text);
        wrote.push(format!(
            "\nwrote {} and {}",
            path.display(),
            drive_path.display()
        ));
    }
    if let Some(path) = &args.pareto {
        output = output.file(
            "--pareto",
            path,
            flap_report::front_csv(&problem, &outcome.front),
        );
        wrote.push(format!(
            "wrote {} ({} levels on the front)",
            path.display(),
            outcome.front.len()
        ));
    }
    output.write()?;
    for line in wrote {
        println!("{line}");
    }
    Ok(())
}
