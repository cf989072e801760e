//! The batch file (`batch.toml`): which designs, how many of each, the seed and optional sheet
//! overrides; validated once into a [`Batch`] that the planner trusts.

use super::linkage::{item_linkage, BatchLinkage};
use crate::cutsheet::{design_for_process, with_ground_tab, Template};
use crate::design::Design;
use crate::input::limits::{
    MAX_ITERATIONS, MAX_QUANTITY, MAX_STOCK, NEST_TIME_S, PRICE, PRICE_PER_M, SHEET_SIDE_MM,
    SPACING_MM,
};
use crate::input::{read_toml, InputError, TableReader};
use crate::parts::PartOrder;
use crate::process::template::SheetSpec;
use std::path::{Path, PathBuf};

mod parts;
mod stock;
use parts::part_orders;

/// A sheet override from `[sheets]`: size, and optionally stock and price; or, with
/// `strip = true`, roll stock of a width (no height, no stock), optionally priced by the metre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SheetOverride {
    /// Sheet (or roll) width, mm.
    pub width_mm: f64,
    /// Sheet height, mm (a roll keeps the template's, unused).
    pub height_mm: Option<f64>,
    /// Roll stock: nest one strip and report its used length.
    pub strip: bool,
    /// Sheets in stock.
    pub stock: Option<usize>,
    /// Price of one sheet.
    pub price_per_sheet: Option<f64>,
    /// Roll stock: its price per metre and the sheets it is compared with.
    pub roll_price: Option<RollPrice>,
}

/// What a metre of roll stock costs, and the cut sheets a lab would buy instead (`compare_with`,
/// by default the process template's sheet): the report nests the roll's parts on those sheets
/// too and sets the two costs side by side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RollPrice {
    /// Price of one metre of the roll (at its width), any currency.
    pub price_per_m: f64,
    /// The sheet alternative: width, mm.
    pub sheet_width_mm: f64,
    /// The sheet alternative: height, mm.
    pub sheet_height_mm: f64,
    /// The sheet alternative: price of one sheet, if known.
    pub price_per_sheet: Option<f64>,
}

impl SheetOverride {
    /// The template's sheet with this size, stock and price (a roll has no sheet price: it is
    /// priced by the metre, [`RollPrice`]).
    pub fn apply(&self, spec: &SheetSpec) -> SheetSpec {
        SheetSpec {
            width_mm: self.width_mm,
            height_mm: self.height_mm.unwrap_or(spec.height_mm),
            stock: if self.strip {
                None
            } else {
                self.stock.or(spec.stock)
            },
            price_per_sheet: if self.strip {
                None
            } else {
                self.price_per_sheet.or(spec.price_per_sheet)
            },
            roll: self.strip,
            ..spec.clone()
        }
    }
}

/// One `[[item]]`: a design (as its process builds it) and how many.
#[derive(Debug, Clone, PartialEq)]
pub struct BatchItem {
    /// The design, bond layers of the process included.
    pub design: Design,
    /// Actuators to build.
    pub quantity: usize,
    /// The ground tab the process added, mm, when the design has no base tab
    /// ([`crate::cutsheet::with_ground_tab`]); the design above includes it.
    pub ground_tab_mm: Option<f64>,
}

/// A validated batch.
#[derive(Debug, Clone, PartialEq)]
pub struct Batch {
    /// Batch name (drawing titles, panel labels, report).
    pub name: String,
    /// Seed of the nester.
    pub seed: u64,
    /// Designs and quantities, in file order.
    pub items: Vec<BatchItem>,
    /// The one process template of every design, with the `[sheets]` overrides applied.
    pub template: Template,
    /// Optimiser budget of the irregular nester, if given.
    pub iterations: Option<usize>,
    /// Wall-clock budget of the nest in seconds (`time_s`), if given.
    pub time_s: Option<f64>,
    /// Extra parts from drawings (`[[part]]`), in file order, then the items' linkage coupons.
    pub parts: Vec<PartOrder>,
    /// The items' linkages (`drive` on an `[[item]]`), in item order.
    pub linkages: Vec<BatchLinkage>,
    /// Prices of the prepreg roll (`[sheets] prepreg = { strip = true, price_per_m }`).
    pub prepreg_roll: Option<RollPrice>,
    /// Prices of the Pyralux roll.
    pub pyralux_roll: Option<RollPrice>,
    /// The batch file.
    pub source: PathBuf,
}

/// The template's sheet with the override `o` of the table `t` applied; the sizes the batch gives are
/// named as the batch writes them.
fn overridden(t: &TableReader<'_>, o: &SheetOverride, spec: &SheetSpec) -> SheetSpec {
    let mut sheet = o.apply(spec);
    sheet.origin.file = t.file().to_path_buf();
    sheet.origin.width_field = t.path("width_mm");
    if o.height_mm.is_some() {
        sheet.origin.height_field = t.path("height_mm");
    } else {
        // The height stays the template's, written in another file: name it with its file.
        sheet.origin.height_field = format!(
            "{} (in {})",
            spec.origin.height_field,
            spec.origin.file.display()
        );
    }
    sheet
}

/// `{ width_mm, height_mm, stock?, price_per_sheet? }`, or `{ width_mm, strip = true, price_per_m?,
/// compare_with? }` where `roll` says the material may come on a roll; `template` is the sheet the
/// template gives (a roll's default `compare_with`).
fn sheet_override(
    t: &TableReader<'_>,
    roll: bool,
    template: &SheetSpec,
) -> Result<SheetOverride, InputError> {
    let strip = t.optional_bool("strip")?.unwrap_or(false);
    if strip && !roll {
        return Err(InputError::invalid(
            t.file(),
            &t.path("strip"),
            "true",
            "PZT comes in plates, not on a roll: strip = true is for prepreg and pyralux",
        ));
    }
    let width_mm = t.number_in("width_mm", SHEET_SIDE_MM)?;
    let s = if strip {
        for (key, why) in [
            ("height_mm", "a roll (strip = true) has a width only: the nest uses the length it needs and reports it"),
            ("stock", "a roll (strip = true) has a width only: the nest uses the length it needs and reports it"),
            ("price_per_sheet", "a roll (strip = true) is priced by its length: price_per_m (the sheets it is compared with go in compare_with = { width_mm, height_mm, price_per_sheet })"),
        ] {
            if t.has(key) {
                return Err(InputError::invalid(t.file(), &t.path(key), "(given)", why));
            }
        }
        let price_per_m = t.optional_number_in("price_per_m", PRICE_PER_M)?;
        let compare = t.optional_table("compare_with")?;
        if compare.is_some() && price_per_m.is_none() {
            return Err(InputError::invalid(
                t.file(),
                &t.path("compare_with"),
                "(given)",
                "the sheet comparison is of costs: give the roll's price_per_m too",
            ));
        }
        let roll_price = match (price_per_m, compare) {
            (None, _) => None,
            (Some(price_per_m), None) => Some(RollPrice {
                price_per_m,
                sheet_width_mm: template.width_mm,
                sheet_height_mm: template.height_mm,
                price_per_sheet: template.price_per_sheet,
            }),
            (Some(price_per_m), Some(c)) => {
                let r = RollPrice {
                    price_per_m,
                    sheet_width_mm: c.number_in("width_mm", SHEET_SIDE_MM)?,
                    sheet_height_mm: c.number_in("height_mm", SHEET_SIDE_MM)?,
                    price_per_sheet: c.optional_number_in("price_per_sheet", PRICE)?,
                };
                c.finish()?;
                Some(r)
            }
        };
        SheetOverride {
            width_mm,
            height_mm: None,
            strip,
            stock: None,
            price_per_sheet: None,
            roll_price,
        }
    } else {
        for key in ["price_per_m", "compare_with"] {
            if t.has(key) {
                return Err(InputError::invalid(
                    t.file(),
                    &t.path(key),
                    "(given)",
                    "only roll stock (strip = true) is priced by the metre; a sheet has price_per_sheet",
                ));
            }
        }
        SheetOverride {
            width_mm,
            height_mm: Some(t.number_in("height_mm", SHEET_SIDE_MM)?),
            strip,
            stock: t.optional_count("stock", 1, MAX_STOCK)?,
            price_per_sheet: t.optional_number_in("price_per_sheet", PRICE)?,
            roll_price: None,
        }
    };
    t.finish()?;
    Ok(s)
}

/// A file the batch names at `key`, relative to the batch file's folder; refused (naming the key, the value as
/// written and the path looked for) when it is not there.
fn existing_file(
    t: &TableReader<'_>,
    key: &str,
    base: &Path,
    file: &str,
    missing: &str,
) -> Result<PathBuf, InputError> {
    let found = base.join(file);
    if found.is_file() {
        Ok(found)
    } else {
        Err(InputError::invalid(
            t.file(),
            &t.path(key),
            format!("{file:?}"),
            format!("{missing} ({})", found.display()),
        ))
    }
}

/// The batch's `[sheets]` overrides applied to `template`; the prices of the prepreg and Pyralux
/// rolls, if they come on priced rolls.
fn sheets_overrides(
    root: &TableReader<'_>,
    path: &Path,
    template: &mut Template,
) -> Result<(Option<RollPrice>, Option<RollPrice>), InputError> {
    let (mut prepreg_roll, mut pyralux_roll) = (None, None);
    if let Some(s) = root.optional_table("sheets")? {
        if let Some(t) = s.optional_table("pzt")? {
            let o = sheet_override(&t, false, &template.pzt)?;
            template.pzt = overridden(&t, &o, &template.pzt);
        }
        if let Some(t) = s.optional_table("prepreg")? {
            let o = sheet_override(&t, true, &template.passive)?;
            template.passive = overridden(&t, &o, &template.passive);
            prepreg_roll = o.roll_price;
        }
        if let Some(t) = s.optional_table("pyralux")? {
            let Some(b) = &mut template.bond else {
                return Err(InputError::invalid(
                    path,
                    &t.path("width_mm").replace(".width_mm", ""),
                    "(table)",
                    format!("process {:?} has no Pyralux layer", template.name),
                ));
            };
            let o = sheet_override(&t, true, &b.sheet)?;
            pyralux_roll = o.roll_price;
            b.sheet = overridden(&t, &o, &b.sheet);
        }
        if let Some(spacing) = s.optional_number_in("spacing_mm", SPACING_MM)? {
            template.passive.spacing_mm = spacing;
            if let Some(b) = &mut template.bond {
                b.sheet.spacing_mm = spacing;
            }
        }
        if let Some(edge_gap) = s.optional_number_in("edge_gap_mm", SPACING_MM)? {
            template.passive.edge_gap_mm = Some(edge_gap);
            if let Some(b) = &mut template.bond {
                b.sheet.edge_gap_mm = Some(edge_gap);
            }
        }
        s.finish()?;
    }
    Ok((prepreg_roll, pyralux_roll))
}

impl Batch {
    /// The price of the roll a cut layer (`passive…` or `pyralux`) is nested on, if it is priced.
    pub fn roll_price(&self, layer: &str) -> Option<RollPrice> {
        if layer == "pyralux" {
            self.pyralux_roll
        } else {
            self.prepreg_roll
        }
    }

    /// Read and validate a batch file and every design it names.
    pub fn load(path: &Path) -> Result<Batch, InputError> {
        let table = read_toml(path)?;
        let root = TableReader::new(path, "", &table);
        let name = root.name("name", "a batch name (text)")?;
        let seed = root.optional_count("seed", 0, i64::MAX)?.unwrap_or(1) as u64;
        let iterations = root.optional_count("iterations", 0, MAX_ITERATIONS)?;
        let time_s = root.optional_number_in("time_s", NEST_TIME_S)?;
        let base = path.parent().unwrap_or(Path::new("."));
        let mut items: Vec<BatchItem> = Vec::new();
        let mut template: Option<(Template, String, String)> = None; // template, process, design file
        let mut drives: Vec<(String, Option<PathBuf>)> = Vec::new(); // per item: field, drive file
        for t in root.tables("item")? {
            let file = t.string("design", "a design file path, relative to the batch file")?;
            let quantity = t.count("quantity", 1, MAX_QUANTITY)?;
            let drive = t
                .optional_string(
                    "drive",
                    "a drive file whose linkage is cut with the item's actuators, relative to the batch file",
                )?
                .map(|drive| existing_file(&t, "drive", base, drive, "no such drive file"))
                .transpose()?;
            drives.push((t.path("drive"), drive));
            t.finish()?;
            let design_path = existing_file(&t, "design", base, file, "no such design file")?;
            let design = Design::load(&design_path)?;
            let this = Template::resolve(&design.process, &design.source)?;
            match &template {
                None => template = Some((this, design.process.clone(), file.to_string())),
                Some((first, process, first_file)) if *first != this => {
                    return Err(InputError::invalid(
                        path,
                        &t.path("design"),
                        format!("{file:?}"),
                        format!(
                            "its process {:?} differs from process {process:?} of {first_file:?}; one batch is built with one process",
                            design.process
                        ),
                    ))
                }
                Some(_) => {}
            }
            let (tpl, _, _) = template.as_ref().expect("set above");
            let design = design_for_process(&design, tpl).map_err(|e| {
                InputError::invalid(path, &t.path("design"), format!("{file:?}"), e.to_string())
            })?;
            let (design, ground_tab_mm) = with_ground_tab(design, tpl);
            items.push(BatchItem {
                design,
                quantity,
                ground_tab_mm,
            });
        }
        let (mut template, _, _) = template.expect("tables() returns at least one item");
        let (prepreg_roll, pyralux_roll) = sheets_overrides(&root, path, &mut template)?;
        if root.has("stock") {
            for t in root.tables("stock")? {
                stock::stock_sheet(&t, base, &items, &mut template)?;
            }
        }
        let mut parts = Vec::new();
        if root.has("part") {
            for t in root.tables("part")? {
                parts.extend(part_orders(&t, base, &items, &template)?);
            }
        }
        let mut linkages = Vec::new();
        let designs: Vec<(&Design, usize)> =
            items.iter().map(|i| (&i.design, i.quantity)).collect();
        for (item, (field, drive)) in drives.iter().enumerate() {
            if let Some((linkage, orders)) =
                item_linkage(path, field, drive.as_deref(), item, &designs, &template)?
            {
                linkages.push(linkage);
                parts.extend(orders);
            }
        }
        root.finish()?;
        Ok(Batch {
            name,
            seed,
            items,
            template,
            iterations,
            time_s,
            parts,
            linkages,
            prepreg_roll,
            pyralux_roll,
            source: path.to_path_buf(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bad_field_is_one_line_naming_file_field_value_and_range() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("batch.toml");
        std::fs::write(
            &path,
            "name = \"b\"\n[[item]]\ndesign = \"d.toml\"\nquantity = 2.5\n",
        )
        .unwrap();
        let err = Batch::load(&path).unwrap_err().to_string();
        assert_eq!(
            err,
            format!(
                "{}: item[1].quantity = 2.5: expected a whole number in [1, 100000]",
                path.display()
            )
        );
    }
}
