//! `actuator-cam optimize spec.toml`: the lightest actuator (or the highest energy density) for a required
//! mechanical energy, with the winning design and the Pareto front written on request.

use super::flags::{ModelFlag, OutputDir};
use actuator_cam::{
    analyse_drive, flap_drive_toml, flap_front_csv, flap_report, optimize, optimize_flap,
    optimize_report, optimized_design_toml, pareto_csv, pareto_front, pareto_svg, short_number,
    wing_load, DriveSpec, FieldLimit, LinkageSpec, Objective, OptimizeError, OptimizeSpec as Spec,
    Output, Problem, Progress, SearchModel, SearchPoint, Silent, TransmissionSpec, PARETO_LEVELS,
};
use actuator_model::primitives::Primitive;
use actuator_model::{Base, Effects, ModelChoice};
use anyhow::{bail, Context};
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The winning design's file in the `-o` folder.
const DESIGN_FILE: &str = "design.toml";

/// Grids above this many designs show a progress bar (on a terminal only).
const PROGRESS_ABOVE: u64 = 20_000_000;

/// Arguments of `optimize`.
#[derive(Debug, Clone, Args)]
#[command(mut_arg("output", |a| a.default_value(None::<&str>)))]
pub struct OptimizeArgs {
    /// Spec file: requirement, drive, search ranges, laminate, constraints (see examples/optimize-*.toml).
    pub spec: PathBuf,
    /// `--model` to optimise with (the Euler-Bernoulli beam has no taper to optimise).
    #[command(flatten)]
    pub model: ModelFlag,
    /// What to optimise.
    #[arg(long, value_enum, default_value_t = ObjectiveArg::MinMass)]
    pub objective: ObjectiveArg,
    /// `-o`: report.txt, the winning design as design.toml (cut-sheet reads it) and, for a wing,
    /// drive.toml (drive reads it), when given.
    #[command(flatten)]
    pub output: OutputDir,
    /// Also write the front of mass against delivered energy (or against frequency margin, for a wing)
    /// into the `-o` folder: pareto.csv, and for an energy requirement pareto.svg.
    #[arg(long, requires = "output")]
    pub pareto: bool,
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
        // The search's nonlinear rates are the bare laminate's; the nonlinear base's ply and bond
        // effects change the laminate, which the search does not carry.
        ModelChoice::Calibrated(m) if m.base == Base::Nonlinear => {
            if m.effects != Effects::default() {
                bail!(
                    "--model: a calibrated model on base = \"nonlinear\" with fitted effects is not searched by the optimizer (its nonlinear search takes the bare laminate); use predict --model to evaluate designs with it, or optimize --model nonlinear"
                );
            }
            Ok(SearchModel::Nonlinear)
        }
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
    check_output_ahead(args, &[&args.spec], false)?;
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
    let text = optimize_report(&spec, &file, &outcome, &perf);
    print!("{text}");
    let Some(dir) = args.output.folder() else {
        return Ok(());
    };
    let mut files = vec![
        ("report.txt".to_string(), text.into_bytes()),
        (
            DESIGN_FILE.to_string(),
            optimized_design_toml(&spec, &outcome.problem, &best).into_bytes(),
        ),
    ];
    let mut front_size = None;
    if args.pareto {
        let most: Vec<SearchPoint> = outcome.most_energy.iter().flatten().copied().collect();
        let front = pareto_front(&outcome.problem, &most, PARETO_LEVELS);
        files.push((
            "pareto.csv".to_string(),
            pareto_csv(&outcome.problem, &front)?.into_bytes(),
        ));
        files.push((
            "pareto.svg".to_string(),
            pareto_svg(&front, spec.energy, Some(&best)).into_bytes(),
        ));
        front_size = Some(front.len());
    }
    write_folder(args, dir, files, &[args.spec.as_path()])?;
    match front_size {
        Some(n) => println!("\nwrote {} ({n} designs on the front)", dir.display()),
        None => println!("\nwrote {}", dir.display()),
    }
    Ok(())
}

/// The `-o` folder checked before the search, with the files every run of `args` writes there (a
/// wing's adds its drive file).
fn check_output_ahead(args: &OptimizeArgs, inputs: &[&Path], wing: bool) -> anyhow::Result<()> {
    let mut names = vec!["report.txt", DESIGN_FILE];
    match (wing, args.pareto) {
        (true, pareto) => names.extend(
            ["drive.toml"]
                .into_iter()
                .chain(pareto.then_some("pareto.csv")),
        ),
        (false, true) => names.extend(["pareto.csv", "pareto.svg"]),
        (false, false) => {}
    }
    args.output.check_ahead("optimize", inputs, &names)
}

/// The files of a run into the `-o` folder, through the one writer: nothing written unless all are.
fn write_folder(
    args: &OptimizeArgs,
    dir: &Path,
    files: Vec<(String, Vec<u8>)>,
    inputs: &[&Path],
) -> anyhow::Result<()> {
    Output::new("optimize")
        .force(args.output.force.force)
        .inputs(inputs.iter().map(|p| p.to_path_buf()))
        .folder("-o", dir, files)
        .write()?;
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
    // What `drive` will hold the design to, the search holds its field to.
    let spec = &Spec {
        poling_survival: Some(drive.survival),
        ..spec.clone()
    };
    let problem = Problem::from_spec(spec, model, Objective::MinMass)
        .with_context(|| format!("{file}: the laminate cannot be solved"))?;
    check_output_ahead(args, &[&args.spec, flap], true)?;
    let outcome = optimize_flap(spec, &problem, &load, &args.model.model)
        .map_err(|e| anyhow::anyhow!("{file}: requirement.flap = {}: {e}", flap.display()))?;
    let chosen = &outcome.chosen;
    // The chosen design driven as `drive` will drive it from the files written here.
    let design_path = args
        .output
        .folder()
        .map_or_else(|| PathBuf::from(DESIGN_FILE), |d| d.join(DESIGN_FILE));
    let check = DriveSpec {
        design: design_path.clone(),
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
    let analysis = analyse_drive(&check, &chosen.built, &args.model.model)
        .map_err(|e| anyhow::anyhow!("{file}: the optimized design's drive: {e}"))?;
    // Every check `drive` makes, and the spec's strain limit on the strain along the plate in flight.
    let r = &analysis.report;
    let strained = r.operating.as_ref().and_then(|o| {
        let max = spec.max_peak_pzt_strain?;
        (o.peak_pzt_strain > max).then(|| {
            format!(
                "its plate strains {:.0} µstrain at x/l_p {:.2} in flight, past constraints.max_peak_pzt_strain = {}",
                o.peak_pzt_strain * 1e6,
                o.peak_pzt_strain_x_over_l_p,
                short_number(max)
            )
        })
    });
    let failed = r
        .unbuildable_linkage
        .clone()
        .or_else(|| r.past_small_deflection.clone())
        .or_else(|| r.unsettled_field.clone())
        .or_else(|| r.unreachable.as_ref().map(|u| u.binding.clone()))
        .or(strained);
    if let Some(why) = failed {
        bail!(
            "{file}: requirement.flap = {}: the lightest design that meets the wing's energy fails `drive`: {why}",
            flap.display()
        );
    }
    let text = flap_report(spec, &file, &problem, &outcome, &analysis.report);
    print!("{text}");
    let Some(dir) = args.output.folder() else {
        return Ok(());
    };
    let mut files = vec![
        ("report.txt".to_string(), text.into_bytes()),
        (
            DESIGN_FILE.to_string(),
            chosen.design_toml.clone().into_bytes(),
        ),
        (
            "drive.toml".to_string(),
            flap_drive_toml(flap, &file, DESIGN_FILE, chosen.travel)?.into_bytes(),
        ),
    ];
    if args.pareto {
        files.push((
            "pareto.csv".to_string(),
            flap_front_csv(&problem, &outcome.front).into_bytes(),
        ));
    }
    write_folder(args, dir, files, &[args.spec.as_path(), flap])?;
    if args.pareto {
        println!(
            "\nwrote {} ({} levels on the front)",
            dir.display(),
            outcome.front.len()
        );
    } else {
        println!("\nwrote {}", dir.display());
    }
    Ok(())
}
