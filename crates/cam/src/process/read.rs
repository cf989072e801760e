//! Reading a process template's tables (`name`, `[cure]`, `[clamp]`, `[layers.*]`, `[operations]`,
//! `[features]`, `[linkage]`) into a [`Template`]: one function a table, each checking its fields'
//! ranges and refusing unknown keys, in the order the file's errors are reported.

use super::features::FeatureMap;
use super::laser::LaserSettings;
use super::linkage::LinkageProcess;
use super::template::{
    BondSpec, ClampLayerSpec, ClampSpec, Cure, MoldStock, PassiveCut, SheetOrigin, SheetSpec,
    Template, DEFAULT_BOND_INSET_MM, DEFAULT_GROUND_TAB_MM, DEFAULT_MOLD_TOLERANCE_MM,
    DEFAULT_SCORE_OVERRUN_MM, DEFAULT_SNAP_STRIP_THICKNESSES,
};
use crate::drawing::model::Operation;
use crate::drawing::palette::Palette;
use crate::input::limits::{
    ACI, BOND_INSET_MM, DENSITY_KG_PER_M3 as DENSITY, DOWEL_DIAMETER_MM, FRACTION, GAP_MM,
    GROUND_TAB_MM, KERF_MM, LABEL_HEIGHT_MM, LAYER_THICKNESS_MM as THICKNESS_MM, MAX_STOCK,
    MIN_FEATURE_MM, PASSIVE_EDGE_MARGIN_MM, PIN_RADIUS_MM, PRICE, SCORE_OVERRUN_MM,
    SHEET_SIDE_MM as SHEET_MM, SNAP_STRIP_THICKNESSES, VIA_DIAMETER_MM,
};
use crate::input::{short_number, InputError, TableReader};
use std::collections::BTreeMap;
use std::path::Path;

impl Template {
    /// Validate a parsed template.
    pub fn from_table(path: &Path, table: &toml::Table) -> Result<Template, InputError> {
        let root = TableReader::new(path, "", table);
        let name = root.string("name", "a template name")?.to_string();
        let description = root
            .optional_string("description", "text")?
            .unwrap_or("")
            .to_string();
        let passive_cut = read_passive_cut(path, &root)?;
        let label_height_mm = root
            .optional_number_in("label_height_mm", LABEL_HEIGHT_MM)?
            .unwrap_or(1.0);
        let cure = Cure::read(&root)?;
        let clamp = read_clamp(&root)?;
        let layers = root.table("layers")?;
        let (pzt, pzt_edge_margin_mm) = read_pzt(&layers)?;
        let (passive, ground_tab_mm) = read_passive(&layers)?;
        let bond = read_bond(&layers)?;
        let (mold, mold_stock) = read_mold(&layers)?;
        let mut covers = BTreeMap::new();
        for key in layers.keys() {
            if !["pzt", "passive", "pyralux", "mold"].contains(&key) {
                let t = layers.table(key)?;
                let cover = read_clamp_layer(&t)?;
                t.finish()?;
                covers.insert(key.to_string(), cover);
            }
        }
        layers.finish()?;
        check_stack(path, &clamp, &covers)?;
        let widest_clamp_kerf = covers
            .values()
            .map(|l| l.kerf_mm)
            .fold(mold.kerf_mm, f64::max);
        check_pins(path, &clamp, widest_clamp_kerf)?;
        let palette = read_palette(path, &root)?;
        let features = FeatureMap::read(path, &root)?;
        let laser = {
            let mut names = vec!["pzt", "passive", "mold"];
            if bond.is_some() {
                names.push("pyralux");
            }
            names.extend(covers.keys().map(String::as_str));
            LaserSettings::read(&root, &names)?
        };
        let linkage = match root.optional_table("linkage")? {
            None => None,
            Some(t) => {
                let l = LinkageProcess::read(&t)?;
                t.finish()?;
                Some(l)
            }
        };
        root.finish()?;
        Ok(Template {
            source: path.to_path_buf(),
            name,
            description,
            passive_cut,
            label_height_mm,
            cure,
            clamp,
            pzt,
            passive,
            bond,
            mold,
            mold_stock,
            covers,
            palette,
            features,
            pzt_edge_margin_mm,
            linkage,
            laser,
            ground_tab_mm,
        })
    }
}

/// `passive_cut`: the prepreg cut as the laid-up stack (the default) or ply by ply.
fn read_passive_cut(path: &Path, root: &TableReader<'_>) -> Result<PassiveCut, InputError> {
    match root
        .optional_string("passive_cut", "\"stack\" or \"ply-by-ply\"")?
        .unwrap_or("stack")
    {
        "stack" => Ok(PassiveCut::Stack),
        "ply-by-ply" => Ok(PassiveCut::PlyByPly),
        other => Err(InputError::invalid(
            path,
            "passive_cut",
            format!("{other:?}"),
            "expected \"stack\" or \"ply-by-ply\"",
        )),
    }
}

/// `[clamp]`: the clamp panel, its cavities, pins, fiducials and windows, and its stack of layers.
fn read_clamp(root: &TableReader<'_>) -> Result<ClampSpec, InputError> {
    let c = root.table("clamp")?;
    let clamp = ClampSpec {
        panel_width_mm: c.number_in("panel_width_mm", SHEET_MM)?,
        panel_height_mm: c.number_in("panel_height_mm", SHEET_MM)?,
        border_mm: c.number_in("border_mm", GAP_MM)?,
        cavity_clearance_mm: c.number_in("cavity_clearance_mm", GAP_MM)?,
        cavity_spacing_mm: c.number_in("cavity_spacing_mm", GAP_MM)?,
        pin_radius_mm: c.number_in("pin_radius_mm", PIN_RADIUS_MM)?,
        pin_inset_mm: c.number_in("pin_inset_mm", GAP_MM)?,
        dowel_diameter_mm: c.optional_number_in("dowel_diameter_mm", DOWEL_DIAMETER_MM)?,
        fiducial_size_mm: c.number_in("fiducial_size_mm", GAP_MM)?,
        window_width_mm: c.number_in("window_width_mm", GAP_MM)?,
        window_height_mm: c.number_in("window_height_mm", GAP_MM)?,
        stack: c.strings("stack", "an array of layer names, bottom to top")?,
    };
    c.finish()?;
    Ok(clamp)
}

/// `[layers.pzt]`: the PZT sheet, how it is scored and snapped, and the passive's margin from its
/// edge.
fn read_pzt(layers: &TableReader<'_>) -> Result<(SheetSpec, f64), InputError> {
    let t = layers.table("pzt")?;
    let mut spec = read_sheet(&t)?;
    spec.min_snap_strip_thicknesses = t
        .optional_number_in("min_snap_strip_thicknesses", SNAP_STRIP_THICKNESSES)?
        .unwrap_or(DEFAULT_SNAP_STRIP_THICKNESSES);
    spec.score_overrun_mm = t
        .optional_number_in("score_overrun_mm", SCORE_OVERRUN_MM)?
        .unwrap_or(DEFAULT_SCORE_OVERRUN_MM);
    let margin = t
        .optional_number_in("passive_edge_margin_mm", PASSIVE_EDGE_MARGIN_MM)?
        .unwrap_or(0.0);
    t.finish()?;
    Ok((spec, margin))
}

/// `[layers.passive]`: the prepreg sheet and the ground tab added to a design without a base tab.
fn read_passive(layers: &TableReader<'_>) -> Result<(SheetSpec, f64), InputError> {
    let t = layers.table("passive")?;
    let mut s = read_sheet(&t)?;
    s.edge_gap_mm = t.optional_number_in("edge_gap_mm", GAP_MM)?;
    let tab = t
        .optional_number_in("ground_tab_mm", GROUND_TAB_MM)?
        .unwrap_or(DEFAULT_GROUND_TAB_MM);
    t.finish()?;
    Ok((s, tab))
}

/// `[layers.pyralux]`, if the process bonds with Pyralux: its sheet, bond film and vias.
fn read_bond(layers: &TableReader<'_>) -> Result<Option<BondSpec>, InputError> {
    let Some(t) = layers.optional_table("pyralux")? else {
        return Ok(None);
    };
    let mut sheet = read_sheet(&t)?;
    sheet.edge_gap_mm = t.optional_number_in("edge_gap_mm", GAP_MM)?;
    let b = BondSpec {
        sheet,
        bond_material: t
            .string("bond_material", "a material name from the library")?
            .to_string(),
        thickness_mm: t.number_in("thickness_mm", THICKNESS_MM)?,
        density_kg_per_m3: t.number_in("density_kg_per_m3", DENSITY)?,
        via_diameter_mm: t.number_in("via_diameter_mm", VIA_DIAMETER_MM)?,
        via_position: t.number_in("via_position", FRACTION)?,
        inset_mm: t
            .optional_number_in("inset_mm", BOND_INSET_MM)?
            .unwrap_or(DEFAULT_BOND_INSET_MM),
    };
    t.finish()?;
    Ok(Some(b))
}

/// The fields of a clamp layer (mold or cover); the caller checks for unknown keys.
fn read_clamp_layer(t: &TableReader<'_>) -> Result<ClampLayerSpec, InputError> {
    Ok(ClampLayerSpec {
        material: t.string("material", "a material description")?.to_string(),
        thickness_mm: t.number_in("thickness_mm", THICKNESS_MM)?,
        density_kg_per_m3: t.number_in("density_kg_per_m3", DENSITY)?,
        kerf_mm: t.number_in("kerf_mm", KERF_MM)?,
    })
}

/// `[layers.mold]`: the mold layer and the films it is stacked from.
fn read_mold(layers: &TableReader<'_>) -> Result<(ClampLayerSpec, MoldStock), InputError> {
    let mold_table = layers.table("mold")?;
    let mold = read_clamp_layer(&mold_table)?;
    let mold_stock = MoldStock {
        films_mm: mold_table
            .optional_numbers_in("stock_thicknesses_mm", THICKNESS_MM, 1, 6)?
            .unwrap_or_else(|| vec![mold.thickness_mm]),
        tolerance_mm: mold_table
            .optional_number_in("height_tolerance_mm", GAP_MM)?
            .unwrap_or(DEFAULT_MOLD_TOLERANCE_MM),
    };
    mold_table.finish()?;
    Ok((mold, mold_stock))
}

/// Every layer of `clamp.stack` names a `[layers.NAME]` table, and the stack holds the mold.
fn check_stack(
    path: &Path,
    clamp: &ClampSpec,
    covers: &BTreeMap<String, ClampLayerSpec>,
) -> Result<(), InputError> {
    for (i, name) in clamp.stack.iter().enumerate() {
        if name != "mold" && !covers.contains_key(name) {
            return Err(InputError::invalid(
                path,
                &format!("clamp.stack[{i}]"),
                format!("{name:?}"),
                "names no [layers.NAME] table",
            ));
        }
    }
    if !clamp.stack.iter().any(|n| n == "mold") {
        return Err(InputError::invalid(
            path,
            "clamp.stack",
            "(no mold)",
            "must contain \"mold\"",
        ));
    }
    Ok(())
}

/// The sheet fields of a cut layer (`material`, `sheet_width_mm`, `sheet_height_mm`, `kerf_mm`, optional
/// `spacing_mm`, `edge_margin_mm`, `stock`, `price_per_sheet`); the caller checks for unknown keys.
fn read_sheet(t: &TableReader<'_>) -> Result<SheetSpec, InputError> {
    Ok(SheetSpec {
        material: t.string("material", "a material description")?.to_string(),
        width_mm: t.number_in("sheet_width_mm", SHEET_MM)?,
        height_mm: t.number_in("sheet_height_mm", SHEET_MM)?,
        kerf_mm: t.number_in("kerf_mm", KERF_MM)?,
        spacing_mm: t.optional_number_in("spacing_mm", GAP_MM)?.unwrap_or(0.0),
        edge_gap_mm: None,
        edge_margin_mm: t
            .optional_number_in("edge_margin_mm", GAP_MM)?
            .unwrap_or(0.0),
        stock: t.optional_count("stock", 1, MAX_STOCK)?,
        price_per_sheet: t.optional_number_in("price_per_sheet", PRICE)?,
        roll: false,
        min_snap_strip_thicknesses: 0.0,
        score_overrun_mm: 0.0,
        origin: SheetOrigin::of(t, "sheet_width_mm", "sheet_height_mm"),
        drawn: Vec::new(),
    })
}

/// The pin holes must stay inside the panel's border: clear of the panel outline by a web of at least
/// [`MIN_FEATURE_MM`] (the kerf of both cuts falls outside that web: the hole is cut inside its radius,
/// the outline outside the panel), and clear of the cavity region inside `border_mm`.
fn check_pins(path: &Path, clamp: &ClampSpec, kerf_mm: f64) -> Result<(), InputError> {
    let (r, inset) = (clamp.pin_radius_mm, clamp.pin_inset_mm);
    if let Some(d) = clamp.dowel_diameter_mm.filter(|d| *d > 2.0 * r) {
        // A film forced over a larger dowel tears or buckles around the hole, and every sheet after it
        // sits off its pins by the buckle.
        return Err(InputError::invalid(
            path,
            "clamp.dowel_diameter_mm",
            short_number(d),
            format!(
                "larger than the pin holes (2 x clamp.pin_radius_mm = {} mm); allowed range (0, {}] mm",
                short_number(2.0 * r),
                short_number(2.0 * r)
            ),
        ));
    }
    let largest = (inset - MIN_FEATURE_MM).min(clamp.border_mm - inset);
    if r <= largest && r > kerf_mm / 2.0 {
        return Ok(());
    }
    let why = if r <= kerf_mm / 2.0 {
        format!("the hole vanishes in the {kerf_mm} mm kerf")
    } else if inset + r > clamp.border_mm {
        format!(
            "the pin holes, centred clamp.pin_inset_mm = {inset} mm from the panel edges, would cut into \
             the cavities inside the {} mm border",
            clamp.border_mm
        )
    } else {
        format!(
            "the pin holes, centred clamp.pin_inset_mm = {inset} mm from the panel edges, would cut \
             through the panel outline"
        )
    };
    let allowed = if largest > kerf_mm / 2.0 {
        format!(
            "allowed range ({}, {}] mm with this inset and border",
            short_number(kerf_mm / 2.0),
            short_number(largest)
        )
    } else {
        "no radius fits: raise clamp.pin_inset_mm or clamp.border_mm".to_string()
    };
    Err(InputError::invalid(
        path,
        "clamp.pin_radius_mm",
        short_number(r),
        format!("{why}; {allowed}"),
    ))
}

/// The optional `[operations]` table: `[operations.cut] colour = "#FF0000", aci = 1`, and likewise `score`,
/// `engrave`, `secondary`; operations not named keep their default colour.
fn read_palette(path: &Path, root: &TableReader<'_>) -> Result<Palette, InputError> {
    let mut palette = Palette::default();
    let Some(ops) = root.optional_table("operations")? else {
        return Ok(palette);
    };
    for op in Operation::ALL {
        let key = op.template_key();
        let Some(t) = ops.optional_table(key)? else {
            continue;
        };
        let colour = t.string("colour", "an SVG colour #RRGGBB")?;
        let aci = t.number_in("aci", ACI)?;
        let field = format!("operations.{key}");
        if aci.fract() != 0.0 {
            return Err(InputError::invalid(
                path,
                &format!("{field}.aci"),
                aci,
                "an AutoCAD colour index, a whole number 1-255",
            ));
        }
        palette
            .set(op, colour, aci as i64)
            .map_err(|e| InputError::invalid(path, &field, colour, e.to_string()))?;
        t.finish()?;
    }
    ops.finish()?;
    palette
        .check_distinct()
        .map_err(|e| InputError::invalid(path, "operations", "(colours)", e.to_string()))?;
    Ok(palette)
}
