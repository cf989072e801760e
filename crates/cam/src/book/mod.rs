//! The build book: the thesis' manufacturing process (§3.2.1 method 1, §3.2.2 method 2, with the
//! lessons of §4.9) written out for one build, step by step, naming the files a technician cuts with
//! their stock, the order the plates snap in, what goes into the mold after which sheet, the cure, the
//! clean-up, the electrical checks and the wiring. `cut-sheet` and `nest` write the same book.

mod function;
mod laser;
mod press;

pub use function::Expected;
pub use press::pin_fit_text;

use crate::markdown;
use crate::pipeline::{Build, ClampBuild, MoldBand, PanelRun};
use crate::process::template::{BondSpec, CureStep, Template};
use serde::Serialize;

/// One section of the book: a stage of the process, its steps in order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Section {
    /// The stage (`Cut`, `Stack clamp 1`, …).
    pub title: String,
    /// The steps, in order, as CommonMark inline text: the user's names and the template's wording
    /// are escaped ([`markdown::text`]), file names are code spans.
    pub steps: Vec<String>,
}

/// What the book needs to know of each design in the build, to check and wire its actuators.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignFacts {
    /// Design name.
    pub name: String,
    /// Base tab length, mm: the ground wire's pad when it is not zero.
    pub base_tab_mm: f64,
    /// The base tab is the process's ground tab, added because the design has none.
    pub ground_tab_added: bool,
    /// What the functional check compares the actuators with, when the model gives a prediction.
    pub expected: Option<Expected>,
}

/// The build book of a build, stage by stage.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BuildBook {
    /// The stages in order.
    pub sections: Vec<Section>,
}

/// `°C` with its Fahrenheit, as the thesis gives its oven settings.
fn temperature(c: f64) -> String {
    format!("{c:.0} °C ({:.0} F)", c * 9.0 / 5.0 + 32.0)
}

/// A cure's time in hours and minutes.
fn duration(min: f64) -> String {
    let (h, m) = ((min / 60.0).floor(), min % 60.0);
    match (h > 0.0, m > 0.0) {
        (true, true) => format!("{h:.0} h {m:.0} min"),
        (true, false) => format!("{h:.0} h"),
        _ => format!("{m:.0} min"),
    }
}

/// A cure as the book and the linkage steps say it: time, temperature, how it is pressed, and the
/// pressure when the template gives it as a number.
pub(crate) fn cure_text(c: &CureStep) -> String {
    format!(
        "{} at {}, {}{}",
        duration(c.time_min),
        temperature(c.temperature_c),
        markdown::text(&c.pressure),
        c.pressure_kpa
            .map_or(String::new(), |p| format!(" ({p} kPa on the parts)"))
    )
}

/// `names` as a list of code spans.
fn listed(names: &[String]) -> String {
    names
        .iter()
        .map(|n| markdown::code(n))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Clamp files, one per run of identical panels, each with the sheets it is cut for when that is more
/// than one: `` `mold-1-1to6_…` (6 sheets) ``.
fn listed_runs(files: &[String], runs: &[PanelRun]) -> String {
    files
        .iter()
        .zip(runs)
        .map(|(f, run)| {
            if run.count == 1 {
                markdown::code(f)
            } else {
                format!("{} ({} sheets)", markdown::code(f), run.count)
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

impl BuildBook {
    /// The book of `built`, made by `template`'s process, for `designs` (in job order).
    pub fn new(template: &Template, built: &Build, designs: &[DesignFacts]) -> BuildBook {
        let mut sections = vec![Section {
            title: "Cut".into(),
            steps: cut_steps(template, built),
        }];
        for (k, clamp) in built.clamps.iter().enumerate() {
            let mut section = stack_section(k, clamp, template.bond.as_ref());
            section.steps[0] = format!(
                "{} {}",
                press::dowel_text(template, clamp),
                section.steps[0]
            );
            sections.push(section);
        }
        sections.push(cure_section(template, built));
        let mut release = release_section();
        release.steps.extend(function::weigh_steps(designs));
        sections.push(release);
        sections.push(checks_section(designs, built));
        sections.push(wiring_section(designs));
        sections.push(Section {
            title: "Functional check".into(),
            steps: function::function_steps(designs),
        });
        BuildBook { sections }
    }

    /// The book as a Markdown checklist, steps numbered through the whole book.
    pub fn markdown(&self) -> String {
        let mut s = String::new();
        let mut n = 0;
        for section in &self.sections {
            s.push_str(&format!("\n### {}\n\n", section.title));
            for step in &section.steps {
                n += 1;
                s.push_str(&format!("{n}. [ ] {step}\n"));
            }
        }
        s
    }
}

/// The cutting steps: the files of every layer with their stock, in the order the process cuts them.
fn cut_steps(template: &Template, built: &Build) -> Vec<String> {
    let method_1 = template.bond.is_some();
    let sheets_of = |layer: &dyn Fn(&str) -> bool| -> Vec<String> {
        built
            .sheets
            .iter()
            .filter(|s| layer(&s.layer))
            .map(|s| s.file_stem.clone())
            .collect()
    };
    let pzt = sheets_of(&|l| l == "pzt");
    let passive = sheets_of(&|l| l.starts_with("passive"));
    let bond = sheets_of(&|l| l == "pyralux");
    let ply_by_ply = built.sheets.iter().any(|s| s.layer.starts_with("passive-"));

    let mut cut = vec![format!(
        "Every file below is named by its sheet and its stock (material, thickness): take that \
         stock off the shelf, lay the sheet's lower-left corner on the file's origin (the DXF's (0, 0), \
         the lower-left corner of the SVG page, which is the sheet), and load the `.svg` or `.dxf` \
         of that name. Red cuts, blue scores, black engraves, green is a second cut pass; keep the \
         grey REFERENCE layer's output off."
    )];
    cut.push(laser::settings_step(template, built));
    cut.push(press::measure_step(template, built));
    let passive_cut = if ply_by_ply {
        format!(
            "Cut each prepreg ply on its own sheet, laid with its fibres along the sheet's y axis (up \
             the page); each part is turned to its ply angle in the file: {}. Stack the plies on the \
             registration pins through their holes.",
            listed(&passive)
        )
    } else {
        format!(
            "Lay up the prepreg plies in the design's layup order, each at its angle from the stack's \
             0° direction, and cut the passive parts from the stack laid with that direction along \
             the sheet's y axis (up the page), as each file says: {}.",
            listed(&passive)
        )
    };
    if method_1 {
        // Thesis §3.2.1: the passive layer is cured first, then cut; the Pyralux is cut on porous
        // Teflon; the PZT is scored and snapped; then the molds and the clamp covers.
        if let Some(pre) = &template.cure.passive {
            cut.push(format!(
                "Lay up the prepreg plies and cure the layup before cutting it: {}.",
                cure_text(pre)
            ));
        }
        cut.push(format!(
            "Cut the passive parts from the cured layup, laid with its 0° fibres along the sheet's \
             y axis (up the page), as each file says: {}.",
            listed(&passive)
        ));
        cut.push(format!(
            "Peel the Pyralux off its backing, lay it on a sheet of porous Teflon and cut the bond \
             parts with their vias: {}. Leave the vias empty: the silver epoxy goes in at stacking.",
            listed(&bond)
        ));
    }
    cut.extend(laser::coupon_step(built));
    cut.push(format!(
        "Lay each PZT sheet on the bed with its + face (the supplier's pole mark) up and score it \
         along the blue lines with the setting the coupon passed, to 1/3-1/2 of its thickness: {}. \
         Scored from the + face, every plate's bevelled score edge marks its + face.",
        listed(&pzt)
    ));
    let guides: Vec<String> = built.snap_guides.iter().map(|(n, _)| n.clone()).collect();
    cut.push(format!(
        "Snap the plates off in the order the numbers give, line 1 first: {} (one picture per \
         PZT sheet, its score lines numbered). The lines that cross the whole sheet come first, \
         each strip pressed over a straight edge, then the slanted lines between the plates of each \
         strip, one plate at a time from one end; a slanted line breaks cleanly only once its strip \
         is free. Lift each plate off + face up, never turned over, onto one of two trays, one plate \
         per actuator on each: the lower plates and the upper plates. Dot the + face of every upper \
         plate near its tip end with a fine permanent marker: it becomes the actuator's outer + face, \
         free in the stack, where the red wire goes. Mark no lower plate: its + face is bonded to the \
         passive layer, and ink there is a void in the bond line at the root, where the stress is \
         highest; its + face is the one whose edges carry the smooth laser-cut bevel (a loupe shows \
         it), the - face's the rough fracture.",
        listed(&guides)
    ));
    cut.extend(clamp_cut_steps(built, method_1));
    if !method_1 {
        // Thesis §3.2.2 step 4: the prepreg is cut last, just before it goes into the mold.
        cut.push(format!(
            "{passive_cut} Cut it last, just before stacking: the prepreg must still be tacky."
        ));
    }
    cut
}

/// The cutting steps of every clamp stack's mold sheets and covers.
fn clamp_cut_steps(built: &Build, method_1: bool) -> Vec<String> {
    let mut cut = Vec::new();
    for (k, clamp) in built.clamps.iter().enumerate() {
        let stack = if built.clamps.len() > 1 {
            format!(" of clamp stack {}", k + 1)
        } else {
            String::new()
        };
        let of_kind = |mold: bool| {
            clamp
                .stack
                .iter()
                .zip(&clamp.files)
                .filter(|(name, _)| name.starts_with("mold-") == mold)
                .map(|(_, f)| listed_runs(f, &clamp.runs))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let repeats = if clamp.runs.iter().any(|r| r.count > 1) {
            " A file marked with a number of sheets is cut that many times, once per panel of \
             the panels its name gives."
        } else {
            ""
        };
        cut.push(format!(
            "Cut the mold sheets{stack} from non-porous Teflon, each from the film its name gives \
             (the films differ: the mold must match the laminate band by band): {}.{repeats}",
            of_kind(true)
        ));
        cut.push(format!(
            "Cut the clamp covers{stack} (felt, Teflon{}): {}.",
            if method_1 {
                ""
            } else {
                ", porous Teflon, bleeder cloth"
            },
            of_kind(false)
        ));
    }
    cut
}

/// The stacking of clamp stack `k`: its sheets bottom to top, and the parts that go into the mold
/// after each.
fn stack_section(k: usize, clamp: &ClampBuild, bond: Option<&BondSpec>) -> Section {
    // Every panel of the stack: a file of a run of identical panels is cut once per panel.
    let panels = clamp.panels.len();
    let title = if panels > 1 {
        format!(
            "Stack clamp {} (panels {}-{})",
            k + 1,
            clamp.first_panel,
            clamp.first_panel + panels - 1
        )
    } else {
        format!("Stack clamp {} (panel {})", k + 1, clamp.first_panel)
    };
    let mut steps = vec![format!(
        "On the clamp's lower plate, bottom to top, each sheet over the registration pins \
         through its pin holes{}:",
        if panels > 1 {
            "; one sheet of each layer per panel, each panel its own stack"
        } else {
            ""
        }
    )];
    let holds = &clamp.mold.bands;
    let last_of = |band: MoldBand| -> Option<usize> {
        holds
            .iter()
            .rposition(|b| *b == band)
            .map(|j| format!("mold-{}", j + 1))
            .and_then(|name| clamp.stack.iter().position(|s| *s == name))
    };
    let (lower, core, upper) = (
        last_of(MoldBand::LowerPlate),
        last_of(MoldBand::Core),
        last_of(MoldBand::UpperPlate),
    );
    for (level, (name, files)) in clamp.stack.iter().zip(&clamp.files).enumerate() {
        steps.push(format!("Lay {name}: {}.", listed_runs(files, &clamp.runs)));
        if Some(level) == lower {
            steps.push(
                "Put a PZT plate from the lower tray in each cavity, + face up (the bevelled edge \
                 up, checked under a loupe; this plate carries no mark, its + face is bonded)."
                    .into(),
            );
            steps.extend(bond.map(bond_step));
        }
        if Some(level) == core {
            steps.push(if bond.is_some() {
                "Put the cured passive part in each cavity, flat on the Pyralux.".into()
            } else {
                "Put the uncured passive part in each cavity, pressed flat onto the plate.".into()
            });
        }
        if Some(level) == upper {
            steps.push(format!(
                "Put the second PZT plate in each cavity, from the upper tray, dot up{}: + face \
                     up like the first, so both plates are poled the same way (parallel drive).",
                if bond.is_some() {
                    ", its Pyralux part down"
                } else {
                    ""
                }
            ));
        }
    }
    steps.push(
        "Look down the stacking windows: each shows its layer number, 1 at the bottom, in \
         order; a missing or repeated number is a sheet out of place."
            .into(),
    );
    Section { title, steps }
}

/// Method 1's bond: each Pyralux part tacked onto its plate where it must lie, its via filled with
/// the epoxy it holds. A bond part lies inside its plate's outline, in the plate's band of the mold.
fn bond_step(b: &BondSpec) -> String {
    // The via's volume, π (d/2)² t, mm³: what fills it level with the film.
    let via_mm3 = std::f64::consts::PI * (b.via_diameter_mm / 2.0).powi(2) * b.thickness_mm;
    format!(
        "Onto each lower plate, a Pyralux part, laid with the plate's {} mm margin (the template's \
         {}) showing evenly all round under a loupe and tacked there with a tacking iron at its tip \
         end: the cavity is wider than the plate, and a loose part slides over the plate's edge. \
         Fill its via with silver epoxy level with the film: {via_mm3:.4} mm³, the via's π (d/2)² t \
         (Ø{} mm through {} mm), a dab from a pin's tip, never a drop standing proud of the film: \
         the excess spreads along the bond line to the plate's edge, the short of thesis §4.9.3. \
         Tack the second Pyralux part onto the - face of each upper plate the same way and fill its \
         via.",
        b.inset_mm,
        markdown::code("layers.pyralux.inset_mm"),
        b.via_diameter_mm,
        b.thickness_mm
    )
}

/// Closing the clamp and the cure.
fn cure_section(template: &Template, built: &Build) -> Section {
    let c = &template.cure.clamp;
    let close = match press::force_text(template, built) {
        Some(force) => format!(
            "Close the clamp to {force}. {}.",
            markdown::text(&c.pressure)
        ),
        None => format!("Close the clamp: {}.", markdown::text(&c.pressure)),
    };
    Section {
        title: "Cure and clamp".into(),
        steps: vec![
            close,
            format!(
                "Cure in the oven {} at {}.",
                duration(c.time_min),
                temperature(c.temperature_c)
            ),
            "Let the stack cool to room temperature in the clamp before opening it.".into(),
        ],
    }
}

/// Opening the clamp and cleaning the actuators up.
fn release_section() -> Section {
    Section {
        title: "Release and trim".into(),
        steps: vec![
            "Open the clamp and lift the sheets off one by one; push each actuator out of its cavity \
             from below, never levering on the PZT."
                .into(),
            "Trim any flash from the outline by hand with a sharp blade.".into(),
            "Scrape the squeeze-out off every edge with a sharp knife, along the PZT edges \
             especially: resin or silver epoxy bridging a plate's electrode to the carbon shorts \
             the actuator (thesis §4.9.3)."
                .into(),
        ],
    }
}

/// The electrical checks of each design's actuators.
fn checks_section(designs: &[DesignFacts], built: &Build) -> Section {
    let mut checks = Vec::new();
    for (d, g) in designs.iter().zip(&built.geometry) {
        let area = cam_geometry::signed_area(&g.pzt_outline()).abs();
        checks.push(function::capacitance_step(d, area));
    }
    checks.push(
        "Check for shorts: each outer face to the carbon and face to face reads open on a meter's \
         highest resistance range. A short is squeeze-out: scrape again, then re-measure."
            .into(),
    );
    Section {
        title: "Electrical checks".into(),
        steps: checks,
    }
}

/// The wiring of each design's actuators.
fn wiring_section(designs: &[DesignFacts]) -> Section {
    let mut wiring = Vec::new();
    for d in designs {
        let ground = if d.ground_tab_added {
            format!(
                "ground tab behind the PZT root ({} mm of bare carbon, added by the process: \
                 the design has no base tab)",
                d.base_tab_mm
            )
        } else if d.base_tab_mm > 0.0 {
            format!("base tab ({} mm of bare carbon)", d.base_tab_mm)
        } else {
            "edge at the root end, the only carbon this design exposes (0.2-0.3 mm: it has no base \
             tab, and the process's ground_tab_mm is 0; a base tab of 1 mm or more gives the wire \
             a pad)"
                .to_string()
        };
        wiring.push(format!(
            "{}: wires on with silver epoxy, cured with a heat gun: white to the carbon {ground}; \
             red to the + face (the dotted face); black to the - face.",
            markdown::text(&d.name)
        ));
    }
    Section {
        title: "Wiring".into(),
        steps: wiring,
    }
}
