//! The readable `nest-report.md`: one function a section, in the order they appear.

use super::{NestReport, COORDINATES};
use crate::markdown::{code, text as md};
use crate::pipeline::{BaselineRow, SearchRow, StockCount};
use std::fmt::Write;

/// A price or cost to two decimals, `-` when there is none.
fn money(x: Option<f64>) -> String {
    x.map(|v| format!("{v:.2}")).unwrap_or_else(|| "-".into())
}

impl NestReport {
    /// The readable report.
    pub fn markdown(&self) -> String {
        let mut s = String::new();
        self.heading_markdown(&mut s);
        self.drawn_parts_markdown(&mut s);
        self.linkages_markdown(&mut s);
        self.sheets_markdown(&mut s);
        self.baseline_markdown(&mut s);
        s.push_str(&self.search_markdown());
        self.totals_markdown(&mut s);
        self.rolls_markdown(&mut s);
        self.stock_list_markdown(&mut s);
        self.clamp_panels_markdown(&mut s);
        let _ = writeln!(s, "\n## Build book");
        let _ = write!(s, "{}", self.build_book.markdown());
        self.placements_markdown(&mut s);
        let _ = writeln!(s, "## Placement map\n");
        for line in &self.placement_map {
            let _ = writeln!(s, "- {}", md(line));
        }
        let _ = writeln!(s, "\n## Files\n");
        for f in &self.files {
            let _ = writeln!(s, "- `{f}`");
        }
        s
    }

    /// How each layer's search ended, when a time budget or an interrupt could end it: the
    /// iterations it reached, and whether `--iterations` replays it. Empty otherwise.
    fn search_markdown(&self) -> String {
        let rows: Vec<(&BaselineRow, &SearchRow)> = self
            .baseline
            .iter()
            .filter_map(|b| b.search.as_ref().map(|r| (b, r)))
            .collect();
        if rows.is_empty() {
            return String::new();
        }
        let mut s = String::new();
        let budget = self
            .time_budget_s
            .map_or(String::new(), |t| format!(" (time budget {t} s)"));
        let _ = writeln!(
            s,
            "## Search{budget}
"
        );
        let _ = writeln!(s, "How far a time budget gets depends on the machine and its load. The iterations a layer reached do not: `--iterations` with a layer's figure nests that layer the same way on any machine (a search cut before its base budget of 1000 iterations was done cannot be replayed).\n");
        let _ = writeln!(s, "| layer | iterations reached | ended by | replay |");
        let _ = writeln!(s, "|---|---|---|---|");
        for (b, r) in rows {
            let replay = if r.replayable {
                format!("`--iterations {}`", r.iterations)
            } else {
                "not replayable".into()
            };
            let ended = match r.over_budget_s {
                Some(t) => format!(
                    "{} (its first layout took {t:.1} s, past the budget)",
                    r.ended
                ),
                None => r.ended.clone(),
            };
            let _ = writeln!(s, "| {} | {} | {ended} | {replay} |", b.layer, r.iterations);
        }
        s.push('\n');
        s
    }

    /// The title, the run that made the files and the designs built.
    fn heading_markdown(&self, s: &mut String) {
        let _ = writeln!(s, "# Nest: {}\n", md(&self.name));
        let _ = writeln!(
            s,
            "Process {}; batch file {}; seed {}, {} optimiser iterations on {} workers (same batch and seed, same files).\n",
            code(&self.process),
            code(&self.batch_file),
            self.seed,
            self.iterations,
            self.workers
        );
        let _ = writeln!(
            s,
            "| design | quantity | PZT mm | layup | ground tab added mm | file |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|");
        for i in &self.items {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} |",
                md(&i.design),
                i.quantity,
                i.pzt_thickness_mm,
                i.layup_deg,
                i.ground_tab_mm.map_or("-".into(), |t| t.to_string()),
                code(&i.file)
            );
        }
    }

    /// The extra parts from drawings, if any.
    fn drawn_parts_markdown(&self, s: &mut String) {
        if !self.parts.is_empty() {
            let _ = writeln!(s, "\n## Parts from drawings\n");
            let _ = writeln!(
                s,
                "| part | quantity | sheet | fibre axis in the drawing ° | rotations ° | area mm² | cut-outs | drawing | entity |"
            );
            let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
            for p in &self.parts {
                let rotations: Vec<String> =
                    p.rotations_deg.iter().map(|r| r.to_string()).collect();
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {} | {} | {:.3} | {} | {} | {} |",
                    md(&p.name),
                    p.quantity,
                    md(&p.sheet),
                    p.fibre_axis_deg.map_or("-".into(), |a| a.to_string()),
                    rotations.join("/"),
                    p.area_mm2,
                    p.cutouts,
                    code(&p.file),
                    md(&p.entity)
                );
            }
            let _ = writeln!(
                s,
                "\nA prepreg part is turned so that its fibre axis lies along the sheet's fibres (the sheet's y axis), then rotated; a part's rotation below is from that turned position. In the sheet lists below an extra part's design column holds its name and the actuator column its copy number.\n"
            );
        }
    }

    /// Each item's linkage: the coupon and its laminate's layers.
    fn linkages_markdown(&self, s: &mut String) {
        for l in &self.linkages {
            let _ = writeln!(
                s,
                "\n## Linkages of {} (docs/cam.md §7)\n\n{} linkage(s) of {}, each cut as five {:.3} x {:.3} mm coupons ({}) and released from its laminated coupon by {}; the coupon's files {} are its layers as nested, checked across layers:\n\n```text\n{}```",
                md(&l.design),
                l.quantity,
                code(&l.drive_file),
                l.coupon_width_mm,
                l.coupon_height_mm,
                md(&l.sheets.join("; ")),
                code(&format!("{}{}-release-1", l.prefix, l.laminate.layers.len() + 1)),
                code(&format!("{}*", l.prefix)),
                l.laminate.table()
            );
        }
    }

    /// The cut sheets and their utilisation; the strips of roll stock.
    fn sheets_markdown(&self, s: &mut String) {
        let _ = writeln!(s, "\n## Sheets\n");
        let _ = writeln!(
            s,
            "| file | layer | material | size mm | parts | utilisation |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|");
        for sh in &self.sheets {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} x {} | {} | {:.1}% |",
                code(&sh.file_stem),
                md(&sh.layer),
                md(&sh.material),
                sh.width_mm,
                sh.height_mm,
                sh.parts.len(),
                sh.utilization * 100.0
            );
        }
        for sh in &self.sheets {
            if let Some(file) = &sh.stock {
                let _ = writeln!(
                    s,
                    "\n{} is cut from the drawn sheet {}: lay that piece on the outline the file draws, where it lay on its sheet, with the sheet's corner at the file's origin.",
                    code(&sh.file_stem),
                    code(file)
                );
            }
        }
        let remnants: Vec<String> = self
            .sheets
            .iter()
            .filter_map(|sh| sh.remnant.as_ref())
            .map(|r| format!("{} ({:.0} mm² free)", code(&r.file_stem), r.free_area_mm2))
            .collect();
        if !remnants.is_empty() {
            let _ = writeln!(
                s,
                "\nRemnants, each a drawing a later batch can nest on first (`[[stock]]`): {}.",
                remnants.join(", ")
            );
        }
        for sh in self.sheets.iter().filter(|sh| sh.roll) {
            let _ = writeln!(
                s,
                "\n{} is a strip of roll stock {} mm wide: {} mm of the roll used.",
                code(&sh.file_stem),
                sh.width_mm,
                sh.height_mm
            );
        }
    }

    /// Each layer nested against the bounding-box baseline.
    fn baseline_markdown(&self, s: &mut String) {
        let _ = writeln!(s, "\n## Irregular nest against the bounding-box baseline\n");
        let _ = writeln!(
            s,
            "| layer | material | parts | sheets | utilisation | used-length utilisation | baseline sheets | baseline utilisation | baseline used-length utilisation |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
        for b in &self.baseline {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.1}% | {:.1}% | {} | {:.1}% | {:.1}% |",
                md(&b.layer),
                md(&b.material),
                b.parts,
                b.sheets,
                b.utilization * 100.0,
                b.used_length_utilization * 100.0,
                b.baseline_sheets,
                b.baseline_utilization * 100.0,
                b.baseline_used_length_utilization * 100.0
            );
        }
        let _ = writeln!(
            s,
            "\nUsed-length utilisation counts the emptiest sheet only up to its highest part (plus the separation): the rest stays usable as a remnant.\n"
        );
    }

    /// Sheets and strips of each material, with their cost when priced.
    fn totals_markdown(&self, s: &mut String) {
        let _ = writeln!(s, "\n## Totals\n");
        let _ = writeln!(s, "| layer | material | sheets | price/sheet | cost |");
        let _ = writeln!(s, "|---|---|---|---|---|");
        for r in &self.totals {
            let (sheets, price) = match r.roll_length_mm {
                Some(length) => (
                    format!("{} strip(s), {length:.1} mm of roll", r.sheets),
                    r.price_per_m
                        .map(|p| format!("{p:.2}/m"))
                        .unwrap_or_else(|| "-".into()),
                ),
                None => (r.sheets.to_string(), money(r.price_per_sheet)),
            };
            let _ = writeln!(
                s,
                "| {} | {} | {sheets} | {price} | {} |",
                md(&r.layer),
                md(&r.material),
                money(r.cost)
            );
        }
        if let Some(c) = self.total_cost {
            let _ = writeln!(s, "\nMaterial cost of the priced sheets: **{c:.2}**.");
        }
    }

    /// Each priced strip of roll stock against the cut sheets it replaces, if any.
    fn rolls_markdown(&self, s: &mut String) {
        if !self.rolls.is_empty() {
            let _ = writeln!(s, "\n## Roll stock against cut sheets\n");
            let _ = writeln!(
                s,
                "| strip | material | width mm | roll used mm | price/m | roll cost | same parts on sheets | sheet cost |"
            );
            let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
            for r in &self.rolls {
                let sheets = r
                    .on_sheets
                    .as_ref()
                    .map(|a| format!("{} x {} mm: {}", a.width_mm, a.height_mm, a.sheets))
                    .unwrap_or_else(|| "-".into());
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {:.1} | {} | {} | {sheets} | {} |",
                    code(&r.file_stem),
                    md(&r.material),
                    r.width_mm,
                    r.length_mm,
                    money(r.price_per_m),
                    money(r.cost),
                    money(r.on_sheets.as_ref().and_then(|a| a.cost))
                );
            }
            let _ = writeln!(
                s,
                "\nA roll is priced by the length used as drawn (the nest's used length rounded up to 0.1 mm); the sheets are the same parts nested on the sheets the batch compares the roll with (`compare_with`, by default the process template's sheet), each sheet counted whole (its unused rest may be kept as a remnant)."
            );
        }
    }

    /// The stock the files are cut from.
    fn stock_list_markdown(&self, s: &mut String) {
        let _ = writeln!(s, "\n## Stock list\n");
        let _ = write!(s, "{}", StockCount::markdown(&self.stock_list));
        if let Some(note) = crate::pipeline::unlabelled_note(self.sheets_without_stock_label) {
            let _ = writeln!(s, "\n{note}");
        }
    }

    /// Each clamp panel: its layers, mold films and actuators.
    fn clamp_panels_markdown(&self, s: &mut String) {
        let _ = writeln!(s, "\n## Clamp panels\n");
        for p in &self.clamp_panels {
            let who: Vec<String> = p
                .actuators
                .iter()
                .map(|a| format!("{} #{}", md(&a.design), a.actuator))
                .collect();
            let films: Vec<String> = p.mold_films_mm.iter().map(|t| t.to_string()).collect();
            let fits: Vec<String> = p.press_fit.iter().map(|f| f.text()).collect();
            let _ = writeln!(
                s,
                "- panel {} ({} layers: {}; mold films bottom to top {} mm; press fit: {}): {}",
                p.index,
                p.stacking_order.len(),
                p.stacking_order
                    .iter()
                    .map(|l| md(l))
                    .collect::<Vec<_>>()
                    .join(" → "),
                films.join(" + "),
                fits.join("; "),
                who.join(", ")
            );
        }
    }

    /// Where every part lies on its sheet.
    fn placements_markdown(&self, s: &mut String) {
        let _ = writeln!(s, "\n## Parts on each sheet\n");
        let _ = writeln!(s, "Position: {COORDINATES}\n");
        for sh in &self.sheets {
            let _ = writeln!(s, "### {} ({})\n", code(&sh.file_stem), md(&sh.material));
            let _ = writeln!(s, "| design | actuator | part | rotation ° | x mm | y mm |");
            let _ = writeln!(s, "|---|---|---|---|---|---|");
            for p in &sh.parts {
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {} | {:.3} | {:.3} |",
                    md(&p.design),
                    p.actuator,
                    md(&p.part),
                    p.rotation_deg,
                    p.x_mm,
                    p.y_mm
                );
            }
            let _ = writeln!(s);
        }
    }
}
