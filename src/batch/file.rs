//! The batch file (`batch.toml`): which designs, how many of each, the seed and optional sheet
//! overrides; validated once into a [`Batch`] that the planner trusts.

use crate::cutsheet::{design_for_process, Template};
use crate::design::Design;
use crate::input::limits::{
    MAX_ITERATIONS, MAX_QUANTITY, MAX_STOCK, PRICE, SHEET_SIDE_MM, SPACING_MM,
};
use crate::input::{read_toml, InputError, TableReader};
use crate::process::template::SheetSpec;
use std::path::{Path, PathBuf};

/// A sheet override from `[sheets]`: size, and optionally stock and price.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SheetOverride {
    /// Sheet width, mm.
    pub width_mm: f64,
    /// Sheet height, mm.
    pub height_mm: f64,
    /// Sheets in stock.
    pub stock: Option<usize>,
    /// Price of one sheet.
    pub price_per_sheet: Option<f64>,
}

impl SheetOverride {
    /// The template's sheet with this size, stock and price.
    pub fn apply(&self, spec: &SheetSpec) -> SheetSpec {
        SheetSpec {
            width_mm: self.width_mm,
            height_mm: self.height_mm,
            stock: self.stock.or(spec.stock),
            price_per_sheet: self.price_per_sheet.or(spec.price_per_sheet),
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
    /// The batch file.
    pub source: PathBuf,
}

fn sheet_override(t: &TableReader<'_>) -> Result<SheetOverride, InputError> {
    let s = SheetOverride {
        width_mm: t.number_in("width_mm", SHEET_SIDE_MM)?,
        height_mm: t.number_in("height_mm", SHEET_SIDE_MM)?,
        stock: t.optional_count("stock", 1, MAX_STOCK)?,
        price_per_sheet: t.optional_number_in("price_per_sheet", PRICE)?,
    };
    t.finish()?;
    Ok(s)
}

impl Batch {
    /// Read and validate a batch file and every design it names.
    pub fn load(path: &Path) -> Result<Batch, InputError> {
        let table = read_toml(path)?;
        let root = TableReader::new(path, "", &table);
        let name = root.name("name", "a batch name (text)")?;
        let seed = root.optional_count("seed", 0, i64::MAX)?.unwrap_or(1) as u64;
        let iterations = root.optional_count("iterations", 0, MAX_ITERATIONS)?;
        let base = path.parent().unwrap_or(Path::new("."));
        let mut items: Vec<BatchItem> = Vec::new();
        let mut template: Option<(Template, String, String)> = None; // template, process, design file
        for t in root.tables("item")? {
            let file = t.string("design", "a design file path, relative to the batch file")?;
            let quantity = t.count("quantity", 1, MAX_QUANTITY)?;
            t.finish()?;
            let design_path = base.join(file);
            if !design_path.is_file() {
                return Err(InputError::invalid(
                    path,
                    &t.path("design"),
                    format!("{file:?}"),
                    format!("no such design file ({})", design_path.display()),
                ));
            }
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
            items.push(BatchItem { design, quantity });
        }
        let (mut template, _, _) = template.expect("tables() returns at least one item");
        if let Some(s) = root.optional_table("sheets")? {
            if let Some(t) = s.optional_table("pzt")? {
                template.pzt = sheet_override(&t)?.apply(&template.pzt);
            }
            if let Some(t) = s.optional_table("prepreg")? {
                template.passive = sheet_override(&t)?.apply(&template.passive);
            }
            if let Some(t) = s.optional_table("pyralux")? {
                let o = sheet_override(&t)?;
                match &mut template.bond {
                    Some(b) => b.sheet = o.apply(&b.sheet),
                    None => {
                        return Err(InputError::invalid(
                            path,
                            &t.path("width_mm").replace(".width_mm", ""),
                            "(table)",
                            format!("process {:?} has no Pyralux layer", template.name),
                        ))
                    }
                }
            }
            if let Some(spacing) = s.optional_number_in("spacing_mm", SPACING_MM)? {
                template.passive.spacing_mm = spacing;
                if let Some(b) = &mut template.bond {
                    b.sheet.spacing_mm = spacing;
                }
            }
            s.finish()?;
        }
        root.finish()?;
        Ok(Batch {
            name,
            seed,
            items,
            template,
            iterations,
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
