//! Kerf compensation: the laser removes a strip of material `kerf` wide centred on the path, so a
//! part's outer contour is offset outwards by kerf/2 and a hole's contour inwards by kerf/2 (the
//! reverse for a pocket or mold cavity that must come out to size); docs/cam.md §4. The offset
//! itself is the geometry kernel's [`cam_geometry::offset::offset_ring`]. Kerf depends on the
//! material and the laser settings: a template's kerfs are starting points only, calibrated by
//! cutting a coupon and measuring it.
