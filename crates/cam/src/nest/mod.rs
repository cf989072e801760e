//! `nest`: a batch of designs and quantities laid out on as few sheets and clamp panels as possible,
//! with the same layer files as `cut-sheet` and a report of where every part went.

pub mod file;
pub mod linkage;
pub mod plan;
pub mod remnant;
pub mod report;

pub use crate::pipeline::{NestOptions, TimeBudget};
pub use file::Batch;
pub use plan::{plan, plan_observed, Planned};
