//! Kerf compensation: the laser removes a strip of material `kerf` wide centred on the path, so a
//! part's outer contour is offset outwards by kerf/2 and a hole's contour inwards by kerf/2 (the
//! reverse for a pocket or mold cavity that must come out to size); docs/cam.md §4. The offset
//! itself is the geometry kernel's [`cam_geometry::offset::offset_ring`]. Kerf depends on the
//! material and the laser settings: the defaults below are starting points only, calibrate them by
//! cutting a coupon and measuring it.

/// Starting kerf for polyimide (Pyralux) and similar films, mm (docs/cam.md §4: 20-30 µm).
pub const DEFAULT_KERF_FILM_MM: f64 = 0.025;
/// Starting kerf for PZT-5H sheet, mm (docs/cam.md §4: 25-40 µm).
pub const DEFAULT_KERF_PZT_MM: f64 = 0.035;
/// Starting kerf for carbon-fibre prepreg, mm: wider because of resin damage; a guess to
/// be replaced by a coupon measurement.
pub const DEFAULT_KERF_PREPREG_MM: f64 = 0.05;
