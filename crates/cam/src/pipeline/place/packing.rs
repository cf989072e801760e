//! How a build packs its cut-through layers ([`Packing`]), the irregular nester's settings
//! ([`NestOptions`], [`TimeBudget`]), what it reports while it works ([`NestObserver`]) and what
//! it reports when done ([`BaselineRow`], [`SearchRow`]).

use cam_nest::{NestProgress, Reached, SearchEnd, SearchLimit};
use serde::Serialize;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

/// Settings of the irregular nester.
#[derive(Debug, Clone, Copy)]
pub struct NestOptions {
    /// Seed of the irregular nester.
    pub seed: u64,
    /// Optimiser budget (improvement moves over all workers); above the default 1000, anytime
    /// rounds after the base search ([`cam_nest::nest_until`]).
    pub iterations: usize,
    /// Wall-clock budget of the whole nest, if any: each layer searches until its share of it
    /// (`TimeBudget::share`) or until `iterations`, whichever comes first.
    pub time: Option<TimeBudget>,
    /// Set by the command line's first Ctrl-C: every layer ends its search with its best layout
    /// so far, and the build goes on with those.
    pub interrupt: Option<&'static AtomicBool>,
}

impl NestOptions {
    /// A seed and an iteration budget, with neither a time budget nor an interrupt.
    pub fn budget(seed: u64, iterations: usize) -> NestOptions {
        NestOptions {
            seed,
            iterations,
            time: None,
            interrupt: None,
        }
    }

    /// The nester's limit for a layer whose search ends at `deadline`.
    pub(super) fn limit(&self, deadline: Option<Instant>) -> SearchLimit<'static> {
        SearchLimit {
            deadline,
            interrupt: self.interrupt,
        }
    }
}

/// A time budget of a nest: the seconds asked for, and the instant they run out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeBudget {
    pub seconds: f64,
    pub deadline: Instant,
}

impl TimeBudget {
    /// `seconds` from now.
    pub fn from_now(seconds: f64) -> TimeBudget {
        TimeBudget {
            seconds,
            deadline: Instant::now() + Duration::from_secs_f64(seconds),
        }
    }

    /// The deadline of a layer that starts now with `left` layers (itself included) still to
    /// nest, `at_once` of them at a time: an equal share of the time left per turn, so the
    /// layers after it keep theirs.
    pub(super) fn share(&self, left: usize, at_once: usize) -> Instant {
        let now = Instant::now();
        let turns = left.div_ceil(at_once.max(1)).max(1);
        now + self.deadline.saturating_duration_since(now) / turns as u32
    }
}

/// How a layer's search ended, in the report when a time budget or an interrupt ended it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SearchRow {
    /// Iterations the layout is the result of.
    pub iterations: usize,
    /// True if `--iterations` with `iterations` gives the same layout on any machine.
    pub replayable: bool,
    /// What ended the search: `budget` (iterations or the search's stop rules), `time`, or
    /// `interrupt`.
    pub ended: String,
    /// The search's wall time, s, when its first layout was finished past the time budget: every part
    /// must be placed once, however long that takes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub over_budget_s: Option<f64>,
}

impl SearchRow {
    /// The row of a search that ended as `reached` says.
    pub(super) fn of(reached: &Reached) -> SearchRow {
        SearchRow {
            iterations: reached.iterations,
            replayable: reached.replayable,
            ended: match reached.ended {
                SearchEnd::Budget => "budget",
                SearchEnd::Time => "time",
                SearchEnd::Interrupt => "interrupt",
            }
            .into(),
            over_budget_s: reached.over_budget.map(|d| d.as_secs_f64()),
        }
    }
}

/// Parallel workers of the irregular nester: fixed, so the layout does not depend on the machine.
pub const WORKERS: usize = 2;

/// What a build reports while the irregular nester works (a progress bar in the command layer).
/// Calls come from the thread that runs the build, layer after layer in order (even when layers
/// are nested at once, `place_cut_layers`); an observer never changes the layout.
pub trait NestObserver {
    /// Cut layer `index` (0-based) of the build's `count` starts nesting `parts` part copies.
    fn layer(&self, index: usize, count: usize, layer: &str, parts: usize);
    /// A snapshot of the layer being nested (sheets, best density, iterations).
    fn progress(&self, progress: &NestProgress);
}

/// An observer that ignores every report.
#[derive(Debug, Clone, Copy, Default)]
pub struct Unobserved;

impl NestObserver for Unobserved {
    fn layer(&self, _: usize, _: usize, _: &str, _: usize) {}
    fn progress(&self, _: &NestProgress) {}
}

/// How a build packs its cut-through layers (passive plies, Pyralux).
#[derive(Clone, Copy)]
pub enum Packing<'a> {
    /// The shelf packer: fast and deterministic, cut paths (outline + kerf/2) the template's spacing
    /// apart, no stock limit. What `cut-sheet` uses for one design.
    Shelf,
    /// The irregular nester: nominal outlines kerf + spacing apart within the stock (or along a
    /// roll, `SheetSpec::roll`), compared with the bounding-box baseline on the same parts,
    /// reporting to the observer as it goes. What `nest` uses for a batch.
    Irregular(NestOptions, &'a dyn NestObserver),
}

impl std::fmt::Debug for Packing<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Packing::Shelf => write!(f, "Shelf"),
            Packing::Irregular(opts, _) => write!(f, "Irregular({opts:?})"),
        }
    }
}

/// Irregular nest against the bounding-box baseline on the same parts and sheet.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BaselineRow {
    pub layer: String,
    pub material: String,
    pub parts: usize,
    pub sheets: usize,
    /// Part area / area of the sheets used.
    pub utilization: f64,
    /// Part area / (sheet width x used length): the emptiest sheet counts up to its highest part,
    /// the rest being a remnant (`NestSolution::used_length_utilization`).
    pub used_length_utilization: f64,
    pub baseline_sheets: usize,
    pub baseline_utilization: f64,
    pub baseline_used_length_utilization: f64,
    /// On roll stock: the used length of the strip, mm (as drawn, rounded up to 0.1 mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub strip_length_mm: Option<f64>,
    /// On roll stock: the length the bounding-box baseline uses, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub baseline_strip_length_mm: Option<f64>,
    /// How the search ended, when a time budget or an interrupt could end it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub search: Option<SearchRow>,
}

impl BaselineRow {
    /// One line: parts, sheets and utilisation of the nest and of the baseline.
    pub fn summary(&self) -> String {
        if let (Some(length), Some(boxes)) = (self.strip_length_mm, self.baseline_strip_length_mm) {
            return format!(
                "{} {} parts: {length:.1} mm of roll, density {:.1}%; bounding boxes {boxes:.1} mm, {:.1}%",
                self.layer,
                self.parts,
                self.used_length_utilization * 100.0,
                self.baseline_used_length_utilization * 100.0
            );
        }
        format!(
            "{} {} parts: {} sheet(s) {:.1}% (used length {:.1}%), bounding boxes {} sheet(s) {:.1}% (used length {:.1}%)",
            self.layer,
            self.parts,
            self.sheets,
            self.utilization * 100.0,
            self.used_length_utilization * 100.0,
            self.baseline_sheets,
            self.baseline_utilization * 100.0,
            self.baseline_used_length_utilization * 100.0
        )
    }
}
