//! The allowed range of every numeric user field, stated once with its unit. Every file kind checks
//! against these: a length is a length whether it comes from a design file, an optimize search range, a
//! sweep level or a measured-data CSV row.
//!
//! The ranges are what a laser can cut and a lab can handle, not what the arithmetic survives: each bound
//! is justified in `docs/limits.md` (same order as here). Checks that combine fields (plate length, tip
//! width, features against the kerf) are in `crate::design::geometry`.

use super::Range;

// Geometry (design `[geometry]`, optimize `[search]`, sweep `[factors]`, measured CSV).

/// Total length l_tot = l_p + l_ext.
pub const LENGTH_MM: Range = Range::closed(1.0, 1000.0, "mm");
/// Extension ratio l_r = l_ext / l_p.
pub const EXTENSION_RATIO: Range = Range::closed(0.0, 20.0, "");
/// Base width w_0.
pub const BASE_WIDTH_MM: Range = Range::closed(0.5, 1000.0, "mm");
/// Width ratio w_r = w_0 / w_nom; the tip width `(2 - w_r) w_nom` must stay positive (and at least
/// [`MIN_FEATURE_MM`], checked on the design), and the tip at most 7 times the base.
pub const WIDTH_RATIO: Range = Range::half_open(0.25, 2.0, "");
/// Passive-only tab behind the PZT.
pub const BASE_TAB_MM: Range = Range::closed(0.0, 1000.0, "mm");
/// Smallest tip width asked of the optimizer (0: unconstrained).
pub const MIN_TIP_WIDTH_MM: Range = Range::at_least(0.0, "mm");

/// Shortest PZT plate l_p = l_tot / (1 + l_r) (checked on the design).
pub const MIN_PLATE_LENGTH_MM: f64 = 1.0;
/// Narrowest tip `(2 - w_r) w_0 / w_r` (checked on the design); cut-sheet also asks for two kerfs.
pub const MIN_FEATURE_MM: f64 = 0.1;

// Laminate.

/// One PZT plate.
pub const PZT_THICKNESS_MM: Range = Range::closed(0.05, 2.0, "mm");
/// One passive ply, one bond layer, a material's standard ply.
pub const PLY_THICKNESS_MM: Range = Range::closed(0.005, 5.0, "mm");
/// A ply angle from the actuator axis.
pub const PLY_ANGLE_DEG: Range = Range::closed(-180.0, 180.0, "deg");
/// Most plies in a layup.
pub const MAX_PLIES: usize = 64;

// Materials (`[materials.NAME]`, sweep property levels).

/// Young's and shear moduli: from a soft silicone (about 1 MPa) to diamond.
pub const MODULUS_GPA: Range = Range::closed(0.001, 2000.0, "GPa");
/// In-plane Poisson ratio ν12.
pub const POISSON: Range = Range::closed(0.0, 0.5, "");
/// Density of a material or a clamp layer.
pub const DENSITY_KG_PER_M3: Range = Range::positive_up_to(30_000.0, "kg/m^3");
/// Piezoelectric coefficient d31, signed.
pub const D31_PM_PER_V: Range = Range::closed(-2000.0, 2000.0, "pm/V");
/// |d31| of a sweep level (the library material's sign is kept).
pub const D31_MAGNITUDE_PM_PER_V: Range = Range::positive_up_to(2000.0, "pm/V");
/// A PZT's depolarization field against its poling: soft ceramics begin to depole at tens of V/mm and
/// the hardest reach their coercive field near 2000 V/mm (thesis §2.2.3, Table 2.1).
pub const DEPOLARIZATION_V_PER_MM: Range = Range::positive_up_to(3000.0, "V/mm");
/// Relative permittivity ε33/ε0.
pub const PERMITTIVITY: Range = Range::closed(0.0, 100_000.0, "");

// Drive.

/// Peak field in a plate.
pub const FIELD_V_PER_MM: Range = Range::positive_up_to(3000.0, "V/mm");
/// Supply voltage of a design, or the optimizer's highest supply voltage.
pub const VOLTAGE_V: Range = Range::positive_up_to(100_000.0, "V");
/// Applied voltage of a measurement: a reading at rest (0 V) is allowed.
pub const MEASURED_VOLTAGE_V: Range = Range::closed(0.0, 100_000.0, "V");
/// Share of plates that survive the field (Weibull fit, thesis eq. 3.2).
pub const SURVIVAL: Range = Range::open(0.0, 1.0, "");

// Requirements and measurements.

/// Required mechanical energy U = ½ F_b δ: from a picojoule to a kilojoule.
pub const ENERGY_MJ: Range = Range::closed(1e-9, 1e6, "mJ");
/// Largest peak |strain| on a PZT surface.
pub const PZT_STRAIN: Range = Range::positive("");
/// Measured mass of an actuator: from the smallest part a lab handles to the largest the geometry allows.
pub const MASS_MG: Range = Range::closed(0.01, 1e7, "mg");
/// Measured one-sided free deflection: a tenth of a micrometre up to the longest actuator.
pub const FREE_DEFLECTION_MM: Range = Range::closed(1e-4, 1000.0, "mm");
/// Measured blocked force: a micronewton up to a kilonewton.
pub const BLOCKED_FORCE_N: Range = Range::closed(1e-6, 1000.0, "N");
/// Measured first resonance of the bare clamped actuator: the bending modes the geometry ranges allow.
pub const RESONANCE_HZ: Range = Range::closed(0.1, 1e6, "Hz");
/// Measured quality factor of that resonance: a resonance (above 1) up to a hard PZT's `Q_m`.
pub const QUALITY_FACTOR: Range = Range::closed(1.0, 10_000.0, "");
/// Standard deviation of a measured resonance's reading: positive, at most the resonance range's top
/// (each is also held below half its own `f1`).
pub const RESONANCE_SD_HZ: Range = Range::closed(1e-6, 1e6, "Hz");
/// A failure value of the Weibull fit (field, strain or stress, any unit): within 12 decades of 1.
pub const FAILURE_VALUE: Range = Range::closed(1e-12, 1e12, "");
/// Largest ratio of the highest to the lowest failure value of one fit.
pub const FAILURE_SPREAD: f64 = 1000.0;

// Counts.

/// Actuators of one design.
pub const MAX_QUANTITY: i64 = 100_000;
/// Points per continuous variable in the optimizer's exhaustive stage: 500⁴ points per laminate is
/// already hours of work, and fewer than 2 spans nothing.
pub const GRID: (i64, i64) = (2, 500);
/// Most levels of one sweep factor, or choices of one optimize search variable (PZT thicknesses,
/// layups).
pub const MAX_LEVELS: usize = 1000;
/// Largest sweep: designs are evaluated a batch at a time and streamed to the CSV, so the bound is the
/// run's time and the CSV's size on disk (about 140 bytes a design), not memory.
pub const MAX_DESIGNS: usize = 10_000_000;
/// Largest optimiser budget of the irregular nester.
pub const MAX_ITERATIONS: i64 = 10_000_000;
/// Time budget of a nest (`nest --time`, a batch's `time_s`): up to a day.
pub const NEST_TIME_S: Range = Range::positive_up_to(86_400.0, "s");

// Process templates and batch sheet overrides.

/// Side of a stock sheet or a clamp panel.
pub const SHEET_SIDE_MM: Range = Range::closed(1.0, 2000.0, "mm");
/// Hairline stroke width of the SVG files: the range a laser's hairline setting reads.
pub const STROKE_MM: Range = Range::positive_up_to(1.0, "mm");
/// Laser kerf.
pub const KERF_MM: Range = Range::closed(0.0, 2.0, "mm");
/// Gaps, margins and clearances of sheets and clamp panels.
pub const GAP_MM: Range = Range::closed(0.0, 50.0, "mm");
/// Gap between parts on top of the kerf.
pub const SPACING_MM: Range = GAP_MM;
/// Thickness of a clamp layer, a mold film or a bond film: no film a laser cuts and a hand lays is
/// thinner than 1 µm.
pub const LAYER_THICKNESS_MM: Range = Range::closed(0.001, 20.0, "mm");
/// Largest sheet stock.
pub const MAX_STOCK: i64 = 100_000;
/// Rotations an extra part of a batch may be cut at: any angle, written within one turn either way.
pub const PART_ROTATION_DEG: Range = Range::closed(-360.0, 360.0, "deg");
/// Price of one sheet.
pub const PRICE: Range = Range::closed(0.0, 1e9, "per sheet");
/// Price of one metre of roll stock (its length, at the roll's width).
pub const PRICE_PER_M: Range = Range::closed(0.0, 1e9, "per m");
/// Engraved label text height.
pub const LABEL_HEIGHT_MM: Range = Range::closed(0.0, 20.0, "mm");
/// Registration pin hole radius.
pub const PIN_RADIUS_MM: Range = Range::positive_up_to(20.0, "mm");
/// Narrowest snappable PZT strip, in sheet thicknesses: below one thickness a scored strip breaks
/// off in chips rather than along its score line (docs/cam.md §4, "Snappable strips").
pub const SNAP_STRIP_THICKNESSES: Range = Range::closed(1.0, 50.0, "thicknesses");
/// How far a PZT score line runs past the sheet edge: enough for the laser to be at speed where it
/// enters the ceramic; more than 5 mm only widens the page (docs/limits.md §1).
pub const SCORE_OVERRUN_MM: Range = Range::closed(0.0, 5.0, "mm");
/// PZT-to-CF edge margin.
pub const PASSIVE_EDGE_MARGIN_MM: Range = Range::closed(0.0, 2.0, "mm");
/// Pyralux bond part inset from the PZT plate edge (method 1 squeeze-out).
pub const BOND_INSET_MM: Range = Range::closed(0.0, 2.0, "mm");
/// The ground tab a process adds behind the PZT of a design that has no base tab.
pub const GROUND_TAB_MM: Range = Range::closed(0.0, 20.0, "mm");
/// Via for silver epoxy, diameter.
pub const VIA_DIAMETER_MM: Range = Range::positive_up_to(10.0, "mm");
/// A position as a fraction of a length, ends excluded.
pub const FRACTION: Range = Range::open(0.0, 1.0, "");
/// Laser power of a `[laser]` setting, % of the laser's full power.
pub const LASER_POWER_PERCENT: Range = Range::positive_up_to(100.0, "%");
/// Head speed of a `[laser]` setting: no laboratory laser moves its head faster than 10 m/s.
pub const LASER_SPEED_MM_PER_S: Range = Range::positive_up_to(10_000.0, "mm/s");
/// Most passes of a `[laser]` setting over one line.
pub const PASSES: i64 = 100;
/// Focal plane below the top surface of a `[laser]` setting: within a lens's usual focus travel.
pub const FOCUS_MM: Range = Range::closed(-20.0, 20.0, "mm");
/// Dowel (registration pin) diameter of a clamp, at most the largest pin hole.
pub const DOWEL_DIAMETER_MM: Range = Range::positive_up_to(40.0, "mm");
/// Clamp pressure on the stack, kPa: up to 10 MPa, well past any prepreg or Pyralux press schedule.
pub const PRESSURE_KPA: Range = Range::positive_up_to(10_000.0, "kPa");
/// AutoCAD colour index.
pub const ACI: Range = Range::closed(1.0, 255.0, "");

// Drive files (`actuator-cam drive`): the wing, the transmission and the flapping requirement.

/// Flapping frequency.
pub const FLAPPING_FREQUENCY_HZ: Range = Range::positive_up_to(5000.0, "Hz");
/// Required stroke amplitude (half the peak-to-peak stroke angle).
pub const STROKE_DEG: Range = Range::open(0.0, 90.0, "deg");
/// An end angle of the stroke the linkage is solved for.
pub const END_ANGLE_DEG: Range = Range::open(-90.0, 90.0, "deg");
/// Mass budget of actuator + transmission for one wing.
pub const MASS_BUDGET_MG: Range = Range::positive_up_to(1e6, "mg");
/// Structural loss factor η of the actuator.
pub const LOSS_FACTOR: Range = Range::positive_up_to(1.0, "");
/// Wing span from its root to its tip.
pub const WING_SPAN_MM: Range = Range::closed(1.0, 1000.0, "mm");
/// Distance from the stroke axis to the wing root.
pub const WING_ROOT_OFFSET_MM: Range = Range::closed(0.0, 1000.0, "mm");
/// Chord of a rectangle or the largest chord of a half-ellipse; chords of a table may be 0.
pub const CHORD_MM: Range = Range::positive_up_to(1000.0, "mm");
/// A chord of a chord table (0 at a pointed tip).
pub const TABLE_CHORD_MM: Range = Range::closed(0.0, 1000.0, "mm");
/// Areal density of the wing membrane and veins.
pub const AREAL_DENSITY_G_PER_M2: Range = Range::positive_up_to(2000.0, "g/m^2");
/// Drag coefficient of the wing at mid-stroke.
pub const DRAG_COEFFICIENT: Range = Range::positive_up_to(10.0, "");
/// The wing's angle of attack at mid-stroke (its added mass goes as sin² of it).
pub const INCIDENCE_DEG: Range = Range::positive_up_to(90.0, "deg");
/// Density of the air the wing flaps in.
pub const AIR_DENSITY_KG_PER_M3: Range = Range::positive_up_to(10.0, "kg/m^3");
/// Wing or link inertia about the stroke axis.
pub const INERTIA_MG_MM2: Range = Range::closed(0.0, 1e9, "mg mm^2");
/// Wing drag coefficient `K` of the torque `K θ̇|θ̇|`.
pub const WING_DAMPING_NN_M_S2: Range = Range::positive_up_to(1e6, "nN m s^2");
/// Mass of a wing or of a transmission.
pub const PART_MASS_MG: Range = Range::closed(0.0, 1e6, "mg");
/// Coupler L1 or crank L3 of the linkage.
pub const LINK_LENGTH_MM: Range = Range::positive_up_to(1000.0, "mm");
/// The linkage's δ at the actuator's rest.
pub const LINK_OFFSET_MM: Range = Range::closed(-1000.0, 1000.0, "mm");
/// Coupler-to-crank ratio L1/L3 of a solved linkage.
pub const COUPLER_RATIO: Range = Range::closed(0.1, 100.0, "");
/// A transmission's ratio at rest, dθ/dx: published insect-scale transmissions run at about 2150-3333
/// rad/m; the range keeps the crank `1/T` within [`LINK_LENGTH_MM`].
pub const TRANSMISSION_RATIO_RAD_PER_M: Range = Range::closed(1.0, 1e6, "rad/m");
/// The stroke angle at which a ratio law's second published ratio holds.
pub const RATIO_STROKE_DEG: Range = Range::open(0.0, 90.0, "deg");
/// Actuator travel (one-sided) a linkage is solved for.
pub const TRAVEL_MM: Range = Range::positive_up_to(1000.0, "mm");
/// Rotational stiffness of the flexures about the wing hinge.
pub const FLEXURE_STIFFNESS_UNM_PER_RAD: Range = Range::closed(0.0, 1e9, "uN m/rad");

/// Cure temperatures a prepreg or Pyralux schedule can ask for, °C (`[cure] temperature_C`).
pub const CURE_C: Range = Range::closed(20.0, 400.0, "°C");
/// Cure times, minutes, up to a day (`[cure] time_min`).
pub const CURE_MIN: Range = Range::closed(1.0, 1440.0, "min");
/// Length of one flexure gap (drive `[transmission] flexure_length_um`).
pub const FLEXURE_LENGTH_UM: Range = Range::positive_up_to(10_000.0, "um");
/// Width of one flexure across the links.
pub const FLEXURE_WIDTH_MM: Range = Range::positive_up_to(100.0, "mm");
/// Flexure film thickness a drive file may choose.
pub const FILM_THICKNESS_UM: Range = Range::closed(1.0, 500.0, "um");

// The linkage laminate of a process template (`[linkage]`).

/// Young's modulus of a flexure film.
pub const FILM_MODULUS_GPA: Range = Range::closed(0.1, 500.0, "GPa");
/// Cyclic strain a flexure film takes.
pub const FATIGUE_STRAIN: Range = Range::open(0.0, 0.2, "");
/// Mounting hole of a linkage tab.
pub const HOLE_DIAMETER_MM: Range = Range::positive_up_to(50.0, "mm");
/// Shortest flexure in film thicknesses.
pub const FLEXURE_THICKNESSES: Range = Range::closed(1.0, 1000.0, "thicknesses");
/// Longest flexure as a share of the link beside it.
pub const FLEXURE_FRACTION: Range = Range::closed(0.01, 1.0, "");
