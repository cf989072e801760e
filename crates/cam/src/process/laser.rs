//! Laser settings of a process template (`[laser.LAYER]`): power, speed, passes and focus of each
//! operation a layer's files run. They belong to a lab's laser, lens and stock, so the shipped
//! templates give none; where a template has none, the build book prints a starting point and the
//! test piece to find the setting on (docs/cam.md §6, "Laser settings").

use crate::drawing::model::Operation;
use crate::input::limits::{FOCUS_MM, LASER_POWER_PERCENT, LASER_SPEED_MM_PER_S, PASSES};
use crate::input::{InputError, TableReader};

/// One operation's setting on one layer's stock.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaserSetting {
    /// Power, % of the laser's full power.
    pub power_percent: f64,
    /// Head speed, mm/s.
    pub speed_mm_per_s: f64,
    /// Passes over each line.
    pub passes: usize,
    /// Focal plane below the stock's top surface, mm (0 = on the top surface; negative above it).
    pub focus_mm: f64,
}

impl LaserSetting {
    /// `20 % power, 100 mm/s, 4 passes, focus 0.1 mm below the top surface`.
    pub fn text(&self) -> String {
        let focus = if self.focus_mm == 0.0 {
            "focus on the top surface".to_string()
        } else if self.focus_mm > 0.0 {
            format!("focus {} mm below the top surface", self.focus_mm)
        } else {
            format!("focus {} mm above the top surface", -self.focus_mm)
        };
        format!(
            "{} % power, {} mm/s, {} pass{}, {focus}",
            self.power_percent,
            self.speed_mm_per_s,
            self.passes,
            if self.passes == 1 { "" } else { "es" }
        )
    }
}

/// The operations a template may set, by the name its `[operations]` table gives them. The
/// reference layer is never run.
const SET: [(&str, Operation); 4] = [
    ("cut", Operation::Cut),
    ("score", Operation::Score),
    ("secondary", Operation::Secondary),
    ("engrave", Operation::Engrave),
];

/// The template's name of `op` (`cut`, `score`, …).
pub fn operation_name(op: Operation) -> &'static str {
    SET.iter()
        .find(|(_, o)| *o == op)
        .map_or("reference", |(n, _)| n)
}

/// Every setting a template gives, by layer (the `[layers]` name: `pzt`, `passive`, `mold`, `felt`,
/// …) and operation.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LaserSettings {
    rows: Vec<(String, Operation, LaserSetting)>,
}

impl LaserSettings {
    /// `[laser]`, if the template has one: a table per layer of `layers` (the template's `[layers]`
    /// names), an inline table per operation.
    pub fn read(root: &TableReader<'_>, layers: &[&str]) -> Result<LaserSettings, InputError> {
        let Some(laser) = root.optional_table("laser")? else {
            return Ok(LaserSettings::default());
        };
        laser.only_keys(layers)?;
        let mut rows = Vec::new();
        for layer in laser.keys() {
            let t = laser.table(layer)?;
            for (name, op) in SET {
                if let Some(s) = t.optional_table(name)? {
                    rows.push((layer.to_string(), op, read_setting(&s)?));
                    s.finish()?;
                }
            }
            t.finish()?;
        }
        laser.finish()?;
        Ok(LaserSettings { rows })
    }

    /// The setting of `op` on `layer`, if the template gives one.
    pub fn get(&self, layer: &str, op: Operation) -> Option<&LaserSetting> {
        self.rows
            .iter()
            .find(|(l, o, _)| l == layer && *o == op)
            .map(|(_, _, s)| s)
    }
}

fn read_setting(t: &TableReader<'_>) -> Result<LaserSetting, InputError> {
    Ok(LaserSetting {
        power_percent: t.number_in("power_percent", LASER_POWER_PERCENT)?,
        speed_mm_per_s: t.number_in("speed_mm_per_s", LASER_SPEED_MM_PER_S)?,
        passes: t.count("passes", 1, PASSES)?,
        focus_mm: t.number_in("focus_mm", FOCUS_MM)?,
    })
}

/// Where the template has no setting for `op`: a starting point, and what the test piece must show
/// before the production sheet is run.
pub fn starting_point(op: Operation) -> &'static str {
    match op {
        Operation::Score => {
            "focus on the top surface, one pass at the lowest power that marks the ceramic; \
             add passes on the test coupon until it snaps along every line"
        }
        Operation::Engrave => {
            "focus on the top surface, one pass at the lowest power that leaves a legible mark"
        }
        _ => {
            "focus on the top surface, one pass; add passes on an offcut of the stock until a \
             test cut drops out free"
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn read(text: &str) -> Result<LaserSettings, InputError> {
        let table: toml::Table = text.parse().unwrap();
        let root = TableReader::new(Path::new("t.toml"), "", &table);
        LaserSettings::read(&root, &["pzt", "mold"])
    }

    #[test]
    fn settings_are_read_per_layer_and_operation() {
        let s = read(
            "[laser.pzt]\nscore = { power_percent = 20, speed_mm_per_s = 100, passes = 4, focus_mm = 0.1 }\n",
        )
        .unwrap();
        let score = s.get("pzt", Operation::Score).unwrap();
        assert_eq!(score.passes, 4);
        assert_eq!(
            score.text(),
            "20 % power, 100 mm/s, 4 passes, focus 0.1 mm below the top surface"
        );
        assert!(s.get("pzt", Operation::Cut).is_none());
        assert!(s.get("mold", Operation::Score).is_none());
    }

    #[test]
    fn an_unknown_layer_or_a_setting_out_of_range_is_refused_by_name() {
        let e = read("[laser.pztt]\n").unwrap_err().to_string();
        assert!(e.contains("laser.pztt") && e.contains("pzt"), "{e}");
        let e = read(
            "[laser.pzt]\nscore = { power_percent = 120, speed_mm_per_s = 100, passes = 4, focus_mm = 0 }\n",
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("laser.pzt.score.power_percent") && e.contains("120"),
            "{e}"
        );
        let e = read("[laser.pzt]\nscore = { power_percent = 20, speed_mm_per_s = 100, passes = 0, focus_mm = 0 }\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("passes"), "{e}");
        assert_eq!(operation_name(Operation::Secondary), "secondary");
    }
}
