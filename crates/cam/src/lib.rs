//! actuator-cam: design files, predictions, laser-cut layer geometry and reports for piezoelectric bimorph
//! bending actuators, on top of the `actuator-model` physics crate.
//!
//! The modules are private; this page is the API, one section per job the command line does, each item
//! re-exported under the name a caller needs (a module's generic `report::text` is `optimize_report`
//! here). Everything a caller reads is validated once on the way in ([`InputError`] names the file, the
//! field as written, the value and what is allowed) and trusted after that; every file a caller writes
//! goes through the one [`Output`] writer and its policy.
//!
//! | job | entry points |
//! |---|---|
//! | read a design and its process | [`Design::load`], [`Template::resolve`], [`design_for_process`] |
//! | predict | [`Prediction::with_dynamics`] |
//! | cut one design | [`plan_and_put`], [`plan_linkage`], [`render_drawings`], [`render_report`] |
//! | nest a batch | [`Batch::load`], [`plan_nest_observed`] |
//! | flap a wing | [`DriveSpec::load`], [`analyse_drive`] |
//! | optimize | [`OptimizeSpec::from_file`], [`optimize`], [`optimize_flap`] |
//! | sweep | [`SweepSpec::from_file`], [`for_each_design`] |
//! | calibrate | [`read_measured`], [`read_effects`], [`calibrate()`], [`render_calibration`] |
//! | write files | [`Output`] |

mod book;
mod calibrate;
mod cutsheet;
mod design;
mod drawing;
mod drive;
mod field_limits;
mod input;
mod layout;
mod linkage;
mod markdown;
mod nest;
mod optimize;
mod output;
mod parts;
mod pipeline;
mod plot;
mod prediction;
mod process;
mod sweep;

// Input: one error type, the ranges of every field, numbers printed short.
pub use input::failures::read_column as read_failure_column;
pub use input::limits;
pub use input::{parse_toml, short_number, InputError, Range};

// A design and the process that builds it.
pub use cutsheet::design_for_process;
pub use design::layup::parse_layup;
pub use design::Design;
pub use prediction::Prediction;
pub use process::Template;

// The drawing model and its writers.
pub use drawing::dxf::to_dxf;
pub use drawing::label::label_strokes;
pub use drawing::model::{Drawing, Operation, Shape};
pub use drawing::svg::{fmt_mm, to_svg, SvgOptions};

// cut-sheet: one design's layer files, report and build book.
pub use cutsheet::linkage::{plan_linkage, transmission_of};
pub use cutsheet::report::LinkageSection;
pub use cutsheet::stream::{plan_and_put, IN_FLIGHT};
pub use cutsheet::write::{
    render as render_layer_files, render_drawings, render_report, svg_options,
};
pub use cutsheet::{plan as plan_cut_sheet, CutSheetOptions, Formats};

// nest: a batch on shared sheets and clamp panels.
pub use nest::{
    plan as plan_nest, plan_observed as plan_nest_observed, Batch, NestOptions, Planned, TimeBudget,
};
pub use pipeline::{build as build_layers, Names, NestObserver, Packing, Unobserved};

// Extra parts from drawings.
pub use parts::flatten::TOLERANCE_MM as FLATTEN_TOLERANCE_MM;
pub use parts::import as import_parts;

// drive: an actuator flapping a wing through its linkage.
pub use design::transmission::TransmissionSpec;
pub use drive::spec::{DriveSpec, LinkageSpec, WingSpec};
pub use drive::{analyse as analyse_drive, Analysis, DriveError};

// optimize: the lightest design for an energy or a wing.
pub use optimize::flap::{optimize_flap, wing_load};
pub use optimize::flap_report::{
    drive_toml as flap_drive_toml, front_csv as flap_front_csv, text as flap_report,
};
pub use optimize::model::SearchModel;
pub use optimize::pareto::{front as pareto_front, to_csv as pareto_csv, to_svg as pareto_svg};
pub use optimize::report::{design_toml as optimized_design_toml, text as optimize_report};
pub use optimize::search::{exhaustive, Design as SearchPoint, FieldLimit, Objective, Problem};
pub use optimize::spec::Spec as OptimizeSpec;
pub use optimize::{optimize, OptimizeError, Progress, Silent, PARETO_LEVELS};

// sweep: factorial studies.
pub use sweep::analysis::{report as sweep_report, ComparisonSums, CsvRows, EffectSums};
pub use sweep::spec::{Factor, SweepSpec};
pub use sweep::{check_models, for_each_design};

// calibrate: measured actuators against the model.
pub use calibrate::csv::{
    parse as parse_measured, parse_file as parse_measured_file, read_path as read_measured,
};
pub use calibrate::discover::catalogue::{
    bounds as primitive_bounds, name as primitive_name, parameter as primitive_parameter,
};
pub use calibrate::effects_file::{parse as parse_effects, read_path as read_effects};
pub use calibrate::library::{Declared, DeclaredParameter, DeclaredSpec, EffectId};
pub use calibrate::model_file::{
    from_toml as parse_calibrated_model, load as load_calibrated_model,
    to_toml as calibrated_model_toml,
};
pub use calibrate::report::tree::selected_effects;
pub use calibrate::report::{render as render_calibration, summary as calibration_summary};
pub use calibrate::select::{adequacy_of, select as select_effects, Candidate};
pub use calibrate::{calibrate, predict_row, Calibration, Dataset, Measurement, Settings};

// The one output writer.
pub use output::{
    in_words, pause_after_interrupted_search, remove_after_interrupt, Output, STAGING_PREFIX,
};
