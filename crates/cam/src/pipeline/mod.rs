//! The one layout pipeline of `cut-sheet` and `nest`: from designs with quantities to verified,
//! drawn layer sheets. `cut-sheet` is a build of one design, `nest` a build of a batch.
//!
//! [`build`] runs the stages in file order:
//! 1. the layer builders make each layer's parts from the designs and the process template (PZT
//!    plates, passive parts or plies, Pyralux bond layers, clamp-panel layers), kerf included;
//! 2. one placement-and-verification step lays them out on sheets: PZT plates as a snappable layout
//!    of score lines, cut-through parts by the build's [`Packing`] (the shelf packer or the irregular
//!    nester), and checks every layout with the independent verifier of [`crate::layout::verify`]
//!    before anything is drawn;
//! 3. the drawings are made, numbered per layer across the build, with a record of every part on
//!    every sheet and the placement map.
//!
//! The commands turn the [`Build`] into their reports; nothing here writes files.

mod build;
mod clamp;
mod coupon;
mod cut;
mod cut_order;
mod jobs;
mod label;
mod mold;
mod panel;
mod parts;
mod place;
mod score_lines;
mod sheet_label;
pub mod snap_guide;

pub use build::{build, build_into, Build};
pub use clamp::{ClampBuild, PanelRun};
pub use jobs::{unlabelled_note, DrawingSink, Names, SheetRecord, SinkError, StockCount};
pub use label::Label;
pub use mold::{MoldBand, MoldChoice};
pub use panel::{border_label, grid, grid_slots, panel_outline, pin_centres};
pub use parts::PartGeometry;
pub use place::{
    sheets_instead_of_roll, BaselineRow, NestObserver, NestOptions, Packing, SearchRow, TimeBudget,
    Unobserved, WORKERS,
};

use crate::drawing::model::Drawing;
use thiserror::Error;

/// A build problem the user can fix.
#[derive(Debug, Error)]
pub enum BuildError {
    /// A feature vanishes or is thinner than the kerf, or the parts do not fit the sheets.
    #[error("{file}: {what}")]
    Geometry {
        /// Design or batch file.
        file: String,
        /// What is wrong, with the numbers.
        what: String,
    },
    /// The model refused the design.
    #[error("{file}: {0}", file = .1)]
    Model(actuator_model::ModelError, String),
    /// A design or process value a build cannot use, named as the user wrote it.
    #[error(transparent)]
    Input(#[from] crate::input::InputError),
    /// A streamed build's drawing sink failed (a drawing could not be rendered or written).
    #[error(transparent)]
    Sink(SinkError),
}

/// One named drawing (a layer on one sheet or panel).
#[derive(Debug, Clone)]
pub struct SheetDrawing {
    /// File stem: the sheet's name and its stock, `pzt-1_pzt-sheet-piezo-systems-0.267mm`,
    /// `mold-2-1_ptfe-non-porous-0.127mm`, … ([`crate::drawing::model::file_stem`]).
    pub stem: String,
    /// Layer name the report groups it under.
    pub layer: String,
    /// The geometry.
    pub drawing: Drawing,
}
