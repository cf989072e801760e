//! The transmission cut with the actuator: the slider-crank of the drive (thesis eq. 2.5) as a
//! smart-composite-microstructure laminate (Wood et al., J. Mech. Des. 130, 2008): carbon links, a
//! polyimide film bridging the gaps between them as flexure hinges, sheet adhesive cut back from the
//! hinges, and a release cut through the stack after lamination (docs/cam.md §7, docs/physics.md §16).
//!
//! | file | concept |
//! |---|---|
//! | `flexures.rs` | each flexure checked (strain, bending, pivot, kerf) and re-sized where it can be |
//! | `pattern.rs` | the flat pattern: pivots, gaps, cut-outs of each layer, the release outline |
//! | `mass.rs` | mass and inertia from the drawn areas |
//! | `drawings.rs` | the layer files on the clamp panel, with the panel's pins |
//! | `coupon.rs` | one linkage's layers as coupons, the parts `nest` places on shared sheets |
//! | `jig.rs` | the jig plate the nested coupons stack, cure and release on |
//! | `checks.rs` | the cross-layer checks run on every linkage drawn, and the geometry read back |
//! | `checklist.rs` | the build steps of the laminate, for the cut sheet's checklist |

pub mod checklist;
pub mod checks;
pub mod coupon;
pub mod drawings;
pub mod flexures;
pub mod jig;
pub mod mass;
pub mod pattern;

pub use crate::design::transmission::FlexureRequest;
use crate::input::InputError;
use crate::process::linkage as process;
pub use crate::process::linkage::LinkageProcess;
use actuator_model::transmission::Linkage;
use flexures::{check_flexures, FlexureRow};
use mass::{linkage_mass, LinkageMass};
use pattern::{FlexureSize, Pattern, JOINTS};
use serde::Serialize;
use std::path::Path;

/// One linkage laminate, designed, checked and laid out.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkageLaminate {
    /// The linkage it draws.
    pub linkage: Linkage,
    /// The stroke's end angles the flexures are checked over, rad.
    pub end_angles: (f64, f64),
    /// Film thickness, mm.
    pub film_thickness_mm: f64,
    /// The flexures as checked.
    pub flexures: [FlexureRow; 3],
    /// The flat pattern.
    pub pattern: Pattern,
    /// Mass and inertia from the drawn areas.
    pub mass: LinkageMass,
    /// The process.
    pub process: LinkageProcess,
}

/// The linkage in a report (JSON `linkage`).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct LinkageReport {
    pub coupler_mm: f64,
    pub crank_mm: f64,
    pub pivots_mm: [f64; 3],
    pub strip_width_mm: f64,
    pub length_mm: f64,
    pub kerf_mm: f64,
    pub film_margin_mm: f64,
    pub adhesive_cutback_mm: f64,
    pub hole_diameter_mm: f64,
    /// Bottom to top: name, material, thickness, mass per area (mg/mm²), area of one linkage (mm²).
    pub layers: Vec<LayerMass>,
    pub flexures: Vec<FlexureRow>,
    pub flexure_stiffness_uNm_per_rad: f64,
    pub link_inertia_mg_mm2: f64,
    pub mass_mg: f64,
    /// The laminate's cure from the template's `[linkage.cure]`, as the steps say it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cure: Option<String>,
}

/// Flexures as checked, a text table: a line each, and why one was re-sized below it.
pub fn flexure_rows_table(rows: &[FlexureRow]) -> String {
    use std::fmt::Write as _;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "  joint                                     gap um  unbonded um  width mm  k uN m/rad  peak turn deg  fold deg  peak bend deg  strain %  limit %"
    );
    for f in rows {
        let _ = writeln!(
            out,
            "  {:<38} {:>9.1}  {:>11.1}  {:>8.2}  {:>10.3}  {:>13.1}  {:>8.1}  {:>13.1}  {:>8.2}  {:>7.2}",
            f.joint,
            f.length_um,
            f.unbonded_um,
            f.width_mm,
            f.stiffness_uNm_per_rad,
            f.peak_rotation_deg,
            f.assembly_fold_deg,
            f.peak_bend_deg,
            f.peak_strain * 100.0,
            f.strain_limit * 100.0
        );
        if let Some(why) = &f.resized {
            let _ = writeln!(out, "    re-sized: {why}");
        }
    }
    out
}

/// One layer's share of the linkage's mass.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LayerMass {
    pub layer: String,
    pub material: String,
    pub thickness_mm: f64,
    pub areal_density_mg_per_mm2: f64,
    pub area_mm2: f64,
    pub mass_mg: f64,
}

impl LinkageReport {
    /// The flexures and what the drive takes from them, as a text table.
    pub fn table(&self) -> String {
        use std::fmt::Write as _;
        let mut out = flexure_rows_table(&self.flexures);
        let _ = writeln!(
            out,
            "  about the wing hinge: flexures {:.3} uN m/rad, links {:.3} mg mm^2; mass {:.3} mg ({:.3} mm long, {:.3} mm wide)",
            self.flexure_stiffness_uNm_per_rad,
            self.link_inertia_mg_mm2,
            self.mass_mg,
            self.length_mm,
            self.strip_width_mm,
        );
        out
    }
}

impl LinkageLaminate {
    /// Design the laminate of `linkage` for the stroke between `end_angles` (rad): flexures checked and
    /// re-sized, the pattern laid out with every feature at least two kerfs, the mass from its areas.
    /// `drive_file` and `template` name the files a refusal points at.
    pub fn design(
        linkage: Linkage,
        end_angles: (f64, f64),
        request: &FlexureRequest,
        process: &LinkageProcess,
        drive_file: &Path,
        template: &Path,
    ) -> Result<LinkageLaminate, InputError> {
        // The film's stock thickness in mm to the nanometre: 7.6 µm read as 7.6e-6 m comes back as
        // 0.007599999999999999 mm, which the stock list would print as such.
        let film_thickness_mm = request
            .film_thickness
            .map_or(process.film.thickness_mm, |t| (t * 1e9).round() / 1e6);
        let process = &LinkageProcess {
            film: process::Sheet {
                thickness_mm: film_thickness_mm,
                ..process.film.clone()
            },
            ..process.clone()
        };
        let asked = [0, 1, 2].map(|i| FlexureSize {
            length_mm: FlexureRequest::pick(&request.lengths, i).map_or(0.0, |l| l * 1e3),
            width_mm: FlexureRequest::pick(&request.widths, i)
                .map_or(process.flexure_width_mm, |w| w * 1e3),
        });
        let (sizes, flexures) =
            check_flexures(&linkage, end_angles, asked, film_thickness_mm, process).map_err(
                |r| {
                    let (values, key, shown) = if r.what == "width" {
                        (&request.widths, "flexure_width_mm", r.value)
                    } else {
                        (&request.lengths, "flexure_length_um", r.value)
                    };
                    InputError::invalid(
                        drive_file,
                        &FlexureRequest::field(values, key, r.joint),
                        shown,
                        format!("flexure {}: {}", JOINTS[r.joint], r.allowed),
                    )
                },
            )?;
        let kerf = process.kerf_mm;
        // A flexure narrower than the links steps the release outline in by half the difference on
        // each side: a step under two kerfs is no feature the laser cuts.
        let widest = sizes.iter().map(|f| f.width_mm).fold(0.0, f64::max);
        for (i, f) in sizes.iter().enumerate() {
            if f.width_mm < widest && widest - f.width_mm < 4.0 * kerf {
                return Err(InputError::invalid(
                    drive_file,
                    &FlexureRequest::field(&request.widths, "flexure_width_mm", i),
                    f.width_mm,
                    format!(
                        "flexure {}: the widest flexure's {widest} mm, or at most {} mm (each side of the outline steps in by two kerfs or more)",
                        JOINTS[i],
                        widest - 4.0 * kerf
                    ),
                ));
            }
        }
        let (crank, coupler) = (linkage.crank * 1e3, linkage.coupler * 1e3);
        // Each link keeps carbon bonded past both cut-backs: two cut-backs and two kerfs of adhesive.
        let bond = 2.0 * process.adhesive_cutback_mm + 2.0 * kerf;
        for (name, length, ends) in [("crank", crank, (0, 1)), ("coupler", coupler, (1, 2))] {
            let rigid = length - 0.5 * (sizes[ends.0].length_mm + sizes[ends.1].length_mm);
            if rigid < bond {
                return Err(InputError::invalid(
                    drive_file,
                    "transmission",
                    format!("{name} {length:.3} mm"),
                    format!(
                        "a {name} whose carbon between its flexures ({rigid:.3} mm) is at least two adhesive cut-backs and two kerfs ({bond:.3} mm), so it stays bonded to the film: a longer travel or coupler, or shorter flexures"
                    ),
                ));
            }
        }
        let r = process.hole_diameter_mm / 2.0;
        let frame_needed = process.film_margin_mm + 2.0 * r + 4.0 * kerf;
        if process.frame_tab_mm < frame_needed {
            return Err(InputError::invalid(
                template,
                "linkage.frame_tab_mm",
                process.frame_tab_mm,
                format!("at least film_margin_mm + hole_diameter_mm + 4 kerfs = {frame_needed} mm, so the hole clears the film and the tab's edges by two kerfs"),
            ));
        }
        let tip_needed = process.adhesive_cutback_mm + 2.0 * kerf;
        if process.tip_tab_mm < tip_needed {
            return Err(InputError::invalid(
                template,
                "linkage.tip_tab_mm",
                process.tip_tab_mm,
                format!("at least adhesive_cutback_mm + 2 kerfs = {tip_needed} mm, so adhesive bonds the tab"),
            ));
        }
        let pattern = Pattern::new(crank, coupler, sizes, process);
        let mass = linkage_mass(&pattern, process);
        Ok(LinkageLaminate {
            linkage,
            end_angles,
            film_thickness_mm,
            flexures,
            pattern,
            mass,
            process: process.clone(),
        })
    }

    /// The flexures' stiffness about the wing hinge, `Σ k_i (dφ_i/dθ)²` at rest, N·m/rad
    /// (docs/physics.md §16.4).
    pub fn flexure_stiffness(&self) -> f64 {
        let rates = self
            .linkage
            .joint_rates_at_rest()
            .unwrap_or([1.0, 1.0, 0.0]);
        self.flexures
            .iter()
            .zip(rates)
            .map(|(f, rate)| f.stiffness_uNm_per_rad * 1e-6 * rate * rate)
            .sum()
    }

    /// The links' inertia about the wing hinge, linearised at rest: the crank's own, and the coupler
    /// and tip tab moving with the actuator tip, `m (dδ/dθ)²`, kg·m² (docs/physics.md §16.5).
    pub fn link_inertia(&self) -> f64 {
        let rest = self.linkage.stroke_angle(0.0).unwrap_or(0.0);
        let lever = 1.0 / self.linkage.ratio_at_angle(rest);
        self.mass.crank_inertia_mg_mm2 * 1e-12 + self.mass.tip_side_mg * 1e-6 * lever * lever
    }

    /// Thickness of the laminated stack, mm.
    pub fn stack_thickness_mm(&self) -> f64 {
        let p = &self.process;
        2.0 * p.carbon.thickness_mm + 2.0 * p.adhesive.thickness_mm + p.film.thickness_mm
    }

    /// The linkage's mass, kg.
    pub fn mass(&self) -> f64 {
        self.mass.total_mg * 1e-6
    }

    /// The linkage as reports print it.
    pub fn report(&self) -> LinkageReport {
        let p = &self.pattern;
        let layers = pattern::STACK
            .iter()
            .enumerate()
            .map(|(k, (ply, name))| {
                let sheet = match ply {
                    pattern::Ply::Carbon => &self.process.carbon,
                    pattern::Ply::Adhesive => &self.process.adhesive,
                    pattern::Ply::Film => &self.process.film,
                };
                let sigma = mass::areal_density(&self.process, *ply);
                LayerMass {
                    layer: format!("{}-{name}", k + 1),
                    material: sheet.material.clone(),
                    thickness_mm: sheet.thickness_mm,
                    areal_density_mg_per_mm2: sigma,
                    area_mm2: self.mass.layer_areas_mm2[k],
                    mass_mg: sigma * self.mass.layer_areas_mm2[k],
                }
            })
            .collect();
        LinkageReport {
            coupler_mm: self.linkage.coupler * 1e3,
            crank_mm: self.linkage.crank * 1e3,
            pivots_mm: p.pivots_mm,
            strip_width_mm: p.strip_width_mm,
            length_mm: p.length_mm,
            kerf_mm: self.process.kerf_mm,
            film_margin_mm: p.film_margin_mm,
            adhesive_cutback_mm: p.adhesive_cutback_mm,
            hole_diameter_mm: p.hole_diameter_mm,
            layers,
            flexures: self.flexures.to_vec(),
            flexure_stiffness_uNm_per_rad: self.flexure_stiffness() * 1e6,
            link_inertia_mg_mm2: self.link_inertia() * 1e12,
            mass_mg: self.mass.total_mg,
            cure: self.process.cure.as_ref().map(crate::book::cure_text),
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::process::template::Template;
    use actuator_model::flexure::Flexure;
    use std::f64::consts::PI;

    /// The linkage examples/drive-hawkmoth.toml solves: ±60° from ±0.75 mm, coupler 4 cranks; method 2's
    /// `[linkage]`, flexure lengths the shortest the film allows.
    pub(crate) fn hawkmoth() -> (LinkageLaminate, Template) {
        let template = Template::resolve("method-2", Path::new("d.toml")).unwrap();
        let linkage = Linkage::solve(0.75e-3, -PI / 3.0, PI / 3.0, 4.0).unwrap();
        let l = LinkageLaminate::design(
            linkage,
            (-PI / 3.0, PI / 3.0),
            &FlexureRequest::default(),
            template.linkage.as_ref().unwrap(),
            Path::new("drive.toml"),
            &template.source,
        )
        .unwrap();
        (l, template)
    }

    fn process() -> LinkageProcess {
        Template::resolve("method-2", Path::new("d.toml"))
            .unwrap()
            .linkage
            .unwrap()
    }

    fn design(linkage: Linkage, request: &FlexureRequest) -> Result<LinkageLaminate, InputError> {
        LinkageLaminate::design(
            linkage,
            (-PI / 3.0, PI / 3.0),
            request,
            &process(),
            Path::new("drive.toml"),
            Path::new("method-2.toml"),
        )
    }

    #[test]
    fn flexures_are_lengthened_to_the_film_strain_and_report_why() {
        // The MFI-like linkage: coupler 6 mm, crank 1 mm, 7.6 µm film, 50 µm asked at every joint, all
        // 2 mm wide, the adhesive cut back 20 µm: each joint's film is unbonded over its gap + 40 µm.
        let request = FlexureRequest {
            lengths: Some(vec![50e-6]),
            widths: Some(vec![2e-3]),
            film_thickness: Some(7.6e-6),
        };
        let process = LinkageProcess {
            adhesive_cutback_mm: 0.02,
            ..process()
        };
        let l = LinkageLaminate::design(
            Linkage::new(6e-3, 1e-3, 0.0).unwrap(),
            (-PI / 3.0, PI / 3.0),
            &request,
            &process,
            Path::new("drive.toml"),
            Path::new("method-2.toml"),
        )
        .unwrap();
        let limit = l.process.film_fatigue_strain;
        for (i, f) in l.flexures.iter().enumerate() {
            assert!(f.peak_strain <= limit + 1e-12, "{i}: {}", f.peak_strain);
            assert!((f.unbonded_um - f.length_um - 40.0).abs() < 1e-9);
            // Equal widths: the flexure is the unbonded film (docs/physics.md §16.6).
            let closed = Flexure {
                length: f.unbonded_um * 1e-6,
                width: f.width_mm * 1e-3,
                thickness: 7.6e-6,
                modulus: 2.5e9,
            };
            assert!((f.stiffness_uNm_per_rad - closed.stiffness() * 1e6).abs() < 1e-9);
        }
        // Hinge O turns by the whole ±60°: t φ / (2 ε) = 7.6 · (π/3) / 0.06 = 132.65 µm unbonded, a gap of
        // 92.65 µm, rounded up.
        assert!(
            (l.flexures[0].length_um - 92.7).abs() < 1e-9,
            "{}",
            l.flexures[0].length_um
        );
        assert!(l.flexures[0]
            .resized
            .as_ref()
            .unwrap()
            .contains("over its fatigue strain"));
        // Joint A barely turns: 50 µm stays (5 film thicknesses is 38 µm).
        assert_eq!(l.flexures[2].length_um, 50.0);
        assert!(l.flexures[2].resized.is_none());
        // The reflected stiffness is k_O + k_B (1 - ψ')² + k_A ψ'² at rest (δ0 = 0 here: ψ' = 0).
        let k: f64 = l.flexures[..2]
            .iter()
            .map(|f| f.stiffness_uNm_per_rad)
            .sum();
        assert!((l.flexure_stiffness() * 1e6 - k).abs() < 1e-12 * k);
    }

    #[test]
    fn joint_b_is_sized_for_its_assembly_fold_and_the_flight_turn() {
        // docs/physics.md §16.7: B's film is bent β(θ) = π/2 + θ - ψ(θ) from the flat row O-B-A, the fold
        // set at assembly and the turn on it. For the hawk moth (±60°, coupler 4 cranks) the largest is at
        // θ+ = 60°, where ψ = asin(L3 (1 - cos 60°) / 4 L3) = asin(1/8): β = 150° - 7.18° = 142.82°.
        let (l, _) = hawkmoth();
        let b = &l.flexures[1];
        let beta = 5.0 * PI / 6.0 - (0.125f64).asin();
        assert!((b.peak_bend_deg - beta.to_degrees()).abs() < 1e-9, "{b:?}");
        let rest = l.linkage.stroke_angle(0.0).unwrap();
        let fold = PI / 2.0 + rest - l.linkage.coupler_angle(rest).unwrap();
        assert!((b.assembly_fold_deg - fold.to_degrees()).abs() < 1e-9);
        // ε = t β / (2 L_e) in closed form, B as wide as the strip: L_e the gap and both cut-backs.
        let t = l.film_thickness_mm;
        let strain = t * beta / (2.0 * b.unbonded_um * 1e-3);
        assert!((b.peak_strain - strain).abs() < 1e-12, "{}", b.peak_strain);
        assert!(b.peak_strain <= 0.03, "{}", b.peak_strain);
        // The shortest gap for it, up to 0.1 µm: t β / (2 · 3 %) less 2 · 100 µm of cut-back.
        let gap = ((t * beta / 0.06 - 0.2) * 1e4).ceil() / 10.0;
        assert!((b.length_um - gap).abs() < 1e-9, "{} vs {gap}", b.length_um);
        assert!(b.resized.as_ref().unwrap().contains("folded"), "{b:?}");
        // The stiffness is of that unbonded length (§16.1, §16.6).
        let k = 2.5e9 * 2e-3 * (t * 1e-3).powi(3) / (12.0 * b.unbonded_um * 1e-6);
        assert!((b.stiffness_uNm_per_rad - k * 1e6).abs() < 1e-9 * k * 1e6);
        // The flight alone turns B less than the fold and the turn bend it.
        assert!(b.peak_rotation_deg < b.peak_bend_deg - 60.0);
    }

    #[test]
    fn a_fold_the_film_cannot_take_within_the_pivot_bound_is_refused() {
        // 12.7 µm film on the hawk moth's 0.866 mm crank: 12.7 · 2.4927 / 0.06 = 527.6 µm of unbonded
        // film at B, a gap of 327.6 µm, over 0.3 of the crank (259.8 µm).
        let request = FlexureRequest {
            film_thickness: Some(12.7e-6),
            ..FlexureRequest::default()
        };
        let err = design(
            Linkage::solve(0.75e-3, -PI / 3.0, PI / 3.0, 4.0).unwrap(),
            &request,
        )
        .unwrap_err()
        .to_string();
        assert!(
            err.starts_with("drive.toml: transmission.flexure_length_um = 0: flexure B"),
            "{err}"
        );
        assert!(err.contains("327.6 to 259.8 µm"), "{err}");
        assert!(
            err.contains("bent 142.8°, folded 91.8° at assembly")
                && err.contains("3.00 % fatigue strain of 12.7 µm film"),
            "{err}"
        );
        assert!(!err.contains('\n'));
    }

    #[test]
    fn a_flexure_that_cannot_be_made_is_refused_in_one_line() {
        // 400 µm at O is more than 0.3 of the 1 mm crank.
        let request = FlexureRequest {
            lengths: Some(vec![400e-6, 100e-6, 100e-6]),
            widths: None,
            film_thickness: Some(7.6e-6),
        };
        let err = design(Linkage::new(6e-3, 1e-3, 0.0).unwrap(), &request)
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with("drive.toml: transmission.flexure_length_um[0] = 400: flexure O"),
            "{err}"
        );
        assert!(err.contains("at most 0.3 of the 1.000 mm link"), "{err}");
        assert!(!err.contains('\n'));
        // A width under two kerfs.
        let narrow = FlexureRequest {
            widths: Some(vec![0.03e-3]),
            ..FlexureRequest::default()
        };
        let err = design(Linkage::new(6e-3, 1e-3, 0.0).unwrap(), &narrow)
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with("drive.toml: transmission.flexure_width_mm = 0.03"),
            "{err}"
        );
        // A crank too short to keep its carbon bonded between two flexures.
        let err = design(
            Linkage::new(2e-3, 0.3e-3, 0.0).unwrap(),
            &FlexureRequest::default(),
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("crank"), "{err}");
    }

    #[test]
    fn the_mass_is_each_layer_area_times_its_mass_per_area() {
        // Equal widths and far-apart flexures: closed-form areas.
        let request = FlexureRequest {
            lengths: Some(vec![140e-6, 140e-6, 60e-6]),
            widths: Some(vec![2.5e-3]),
            film_thickness: Some(7.6e-6),
        };
        let l = design(Linkage::new(6e-3, 1e-3, 0.0).unwrap(), &request).unwrap();
        let p = &l.pattern;
        let pr = &l.process;
        let w = 2.5;
        let gaps: f64 = p.flexures.iter().map(|f| f.length_mm).sum();
        let hole = PI * (pr.hole_diameter_mm / 2.0).powi(2);
        let carbon = w * (p.length_mm - gaps) - hole;
        let adhesive = w * (p.length_mm - gaps - 6.0 * pr.adhesive_cutback_mm) - hole;
        let film = w * (gaps + 6.0 * pr.film_margin_mm);
        let expected = 2.0 * carbon * pr.carbon.areal_density_mg_per_mm2()
            + 2.0 * adhesive * pr.adhesive.areal_density_mg_per_mm2()
            + film * pr.film.areal_density_mg_per_mm2();
        assert!(
            (l.mass.total_mg - expected).abs() < 1e-12 * expected,
            "{} vs {expected}",
            l.mass.total_mg
        );
        // The film is the drive file's 7.6 µm: 1420 kg/m³ · 7.6 µm = 0.010792 mg/mm².
        assert!((pr.film.areal_density_mg_per_mm2() - 0.010792).abs() < 1e-15);
        // The crank's inertia about O against a midpoint sum over 20 000 slices.
        let [o, b, _] = p.pivots_mm;
        let n = 20_000;
        let mut sum = 0.0;
        for (ply, _) in pattern::STACK {
            let spans = p.material_spans(ply);
            let sigma = mass::areal_density(pr, ply);
            for i in 0..n {
                let x = o + (b - o) * (i as f64 + 0.5) / n as f64;
                if spans.iter().any(|(s0, s1)| *s0 <= x && x <= *s1) {
                    sum += sigma * p.width_at(x) * (x - o).powi(2) * (b - o) / n as f64;
                }
            }
        }
        assert!(
            (l.mass.crank_inertia_mg_mm2 - sum).abs() < 1e-6 * sum,
            "{} vs {sum}",
            l.mass.crank_inertia_mg_mm2
        );
    }
}
