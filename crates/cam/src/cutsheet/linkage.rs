//! `cut-sheet design.toml --drive drive.toml`, or a design with a `[transmission]`: the linkage laminate
//! cut with the actuator (docs/cam.md §7). Its layers are drawn for as many linkages as actuators,
//! checked across layers before anything is written, and listed in the report with their build steps.

use super::{process_template, CutSheetOptions, SheetDrawing, Template};
use crate::design::transmission::TransmissionSpec;
use crate::design::Design;
use crate::drive::spec::DriveSpec;
use crate::drive::{linkage_laminate_in, DriveError};
use crate::input::InputError;
use crate::linkage::checks::{check_linkage_drawings, Expected};
use crate::linkage::drawings::linkage_drawings;
use crate::linkage::pattern::STACK;
use crate::linkage::LinkageLaminate;
use std::path::PathBuf;

/// The linkage of a cut sheet: the laminate, its drawings (file order) and, when the drive file gives
/// the transmission's stiffness and mass instead of flexures, how the drawn ones compare.
#[derive(Debug, Clone)]
pub struct LinkageCut {
    /// The file that gives the transmission: the drive file, or the design file's `[transmission]`.
    pub source: PathBuf,
    /// The laminate.
    pub laminate: LinkageLaminate,
    /// Its layer drawings.
    pub drawings: Vec<SheetDrawing>,
    /// Panels.
    pub panels: usize,
    /// The drive file's given transmission against the drawn one, if it gives one.
    pub note: Option<String>,
}

impl LinkageCut {
    /// Count the sheets the linkage's layers are cut from into the stock list `rows`: every layer
    /// file is a sheet of its stock; the release cut runs through the laminated stack, no stock of its
    /// own.
    pub fn count_stock(&self, rows: &mut Vec<crate::pipeline::StockCount>) {
        for d in self
            .drawings
            .iter()
            .filter(|d| d.layer != "linkage-release")
        {
            crate::pipeline::StockCount::count(rows, &d.drawing, 1);
        }
    }
}

/// Why the linkage cannot be cut.
#[derive(Debug, thiserror::Error)]
pub enum LinkageCutError {
    /// The drive file, its design or the linkage.
    #[error(transparent)]
    Drive(#[from] DriveError),
    /// The drawings fail a cross-layer check (nothing is written).
    #[error("{file}: the linkage drawings fail their checks: {problems}")]
    Checks {
        /// The drive file.
        file: String,
        /// The problems, joined.
        problems: String,
    },
}

impl From<InputError> for LinkageCutError {
    fn from(e: InputError) -> Self {
        LinkageCutError::Drive(DriveError::Input(e))
    }
}

/// The drive file `drive_file`, refused unless it drives `design`.
pub fn drive_of(drive_file: &std::path::Path, design: &Design) -> Result<DriveSpec, InputError> {
    let drive = DriveSpec::load(drive_file)?;
    let same = match (drive.design.canonicalize(), design.source.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if !same {
        return Err(InputError::invalid(
            drive_file,
            "design",
            drive.design.display().to_string(),
            format!(
                "the design being cut, {} (a drive file drives one design)",
                design.source.display()
            ),
        ));
    }
    Ok(drive)
}

/// The transmission a cut sheet cuts, and the file that gives it: a `--drive` file (which must drive
/// `design`), the design's own `[transmission]`, or both when they are the same (a design's
/// `[transmission]` and its drive file's may not disagree: refused naming both); `None` without either.
pub fn transmission_of(
    drive_file: Option<&std::path::Path>,
    design: &Design,
) -> Result<Option<(PathBuf, TransmissionSpec)>, InputError> {
    let from_drive = drive_file
        .map(|f| drive_of(f, design).map(|d| (f.to_path_buf(), d.transmission)))
        .transpose()?;
    match (from_drive, &design.transmission) {
        (Some((file, t)), Some(own)) if t != *own => Err(InputError::invalid(
            &design.source,
            "transmission",
            "(given)",
            format!(
                "the [transmission] (and stroke_deg) of the drive file {}, or left out: a design's transmission and its drive file's may not disagree",
                file.display()
            ),
        )),
        (Some(given), _) => Ok(Some(given)),
        (None, Some(own)) => Ok(Some((design.source.clone(), own.clone()))),
        (None, None) => Ok(None),
    }
}

/// Plan the linkage of the transmission `spec` given in `source` (a drive file or the design file) for
/// `design` (the design as given).
pub fn plan_linkage(
    source: &std::path::Path,
    spec: &TransmissionSpec,
    design: &Design,
    template: &Template,
    opts: &CutSheetOptions,
) -> Result<LinkageCut, LinkageCutError> {
    let drive_file = source;
    let template = process_template(template, opts);
    let built = super::design_for_process(design, &template).map_err(|e| {
        InputError::invalid(
            drive_file,
            "design",
            design.source.display().to_string(),
            e.to_string(),
        )
    })?;
    let own = Template::resolve(&design.process, &design.source)?;
    let laminate = linkage_laminate_in(spec, source, &built, &opts.model, &own)?;
    let count = opts.quantity.unwrap_or(design.quantity);
    let drawings = linkage_drawings(&laminate, &template, count, &design.name)?;
    let report = laminate.report();
    let expected = Expected::of(&report);
    let per_panel = STACK.len() + 1;
    let problems: Vec<String> = drawings
        .chunks(per_panel)
        .flat_map(|panel| check_linkage_drawings(panel, &expected))
        .collect();
    if !problems.is_empty() {
        return Err(LinkageCutError::Checks {
            file: drive_file.display().to_string(),
            problems: problems.join("; "),
        });
    }
    let note = spec.flexures.is_none().then(|| {
        format!(
            "{} gives the transmission as {} µN·m/rad, {} mg·mm² and {} mg; the drawn linkage has {} µN·m/rad, {} mg·mm² and {} mg: give its flexures (flexure_length_um, flexure_width_mm, film_thickness_um) for `drive` to use the drawn linkage",
            drive_file.display(),
            crate::input::fixed(spec.flexure_stiffness * 1e6, 3),
            crate::input::fixed(spec.link_inertia * 1e12, 3),
            crate::input::fixed(spec.transmission_mass * 1e6, 3),
            crate::input::fixed(report.flexure_stiffness_uNm_per_rad, 3),
            crate::input::fixed(report.link_inertia_mg_mm2, 3),
            crate::input::fixed(report.mass_mg, 3),
        )
    });
    Ok(LinkageCut {
        source: source.to_path_buf(),
        laminate,
        panels: drawings.len() / per_panel,
        drawings,
        note,
    })
}
