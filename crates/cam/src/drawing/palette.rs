//! Colours of the laser operations: the SVG stroke colour and DXF layer colour (ACI) that laser software
//! maps to a process. The default is docs/cam.md §3's pure primaries; a process template may name others
//! (`[operations.cut] colour = "#FF0000", aci = 1`) to match a lab's LightBurn or Epilog set-up.

use super::model::Operation;

/// Colour of one operation in both file formats.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OperationColour {
    /// SVG stroke, `#RRGGBB` (upper case).
    pub svg: String,
    /// AutoCAD Colour Index of the DXF layer, 1-255.
    pub aci: u8,
}

/// One colour per operation, indexed in [`Operation::ALL`] order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Palette {
    colours: [OperationColour; 5],
}

impl Default for Palette {
    fn default() -> Self {
        Palette {
            colours: Operation::ALL.map(|op| OperationColour {
                svg: op.svg_colour().to_string(),
                aci: op.aci(),
            }),
        }
    }
}

fn index(op: Operation) -> usize {
    Operation::ALL
        .iter()
        .position(|o| *o == op)
        .unwrap_or_default()
}

/// Why a palette was refused.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PaletteError {
    /// Not `#RRGGBB`.
    NotHex(String),
    /// ACI outside 1-255.
    Aci(i64),
    /// Two operations share a colour, so laser software could not tell them apart.
    Shared(Operation, Operation),
}

impl std::fmt::Display for PaletteError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PaletteError::NotHex(s) => write!(f, "{s:?} is not a colour #RRGGBB"),
            PaletteError::Aci(i) => write!(f, "ACI {i} is outside 1-255"),
            PaletteError::Shared(a, b) => write!(
                f,
                "{} and {} share a colour; laser software maps colours to processes, so each operation needs its own",
                a.layer_name(),
                b.layer_name()
            ),
        }
    }
}

impl Palette {
    /// SVG stroke colour of `op`.
    pub fn svg_colour(&self, op: Operation) -> &str {
        &self.colours[index(op)].svg
    }

    /// ACI colour of `op`'s DXF layer.
    pub fn aci(&self, op: Operation) -> u8 {
        self.colours[index(op)].aci
    }

    /// Set `op`'s colours, after checking them (`svg` as `#RRGGBB`, `aci` 1-255).
    pub fn set(&mut self, op: Operation, svg: &str, aci: i64) -> Result<(), PaletteError> {
        let hex = svg.strip_prefix('#').unwrap_or("");
        if hex.len() != 6 || !hex.chars().all(|c| c.is_ascii_hexdigit()) {
            return Err(PaletteError::NotHex(svg.to_string()));
        }
        let aci = u8::try_from(aci)
            .ok()
            .filter(|a| *a >= 1)
            .ok_or(PaletteError::Aci(aci))?;
        self.colours[index(op)] = OperationColour {
            svg: svg.to_ascii_uppercase(),
            aci,
        };
        Ok(())
    }

    /// Every operation distinguishable: no two share an SVG colour or an ACI.
    pub fn check_distinct(&self) -> Result<(), PaletteError> {
        for (i, a) in Operation::ALL.iter().enumerate() {
            for b in &Operation::ALL[i + 1..] {
                let (ca, cb) = (&self.colours[index(*a)], &self.colours[index(*b)]);
                if ca.svg == cb.svg || ca.aci == cb.aci {
                    return Err(PaletteError::Shared(*a, *b));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_is_the_pure_primaries() {
        let p = Palette::default();
        assert_eq!(p.svg_colour(Operation::Cut), "#FF0000");
        assert_eq!(p.svg_colour(Operation::Score), "#0000FF");
        assert_eq!(p.aci(Operation::Secondary), 3);
        assert_eq!(p.check_distinct(), Ok(()));
    }

    #[test]
    fn set_checks_the_colour_and_the_index() {
        let mut p = Palette::default();
        p.set(Operation::Secondary, "#ff00ff", 6).unwrap();
        assert_eq!(p.svg_colour(Operation::Secondary), "#FF00FF");
        assert_eq!(p.aci(Operation::Secondary), 6);
        assert_eq!(
            p.set(Operation::Cut, "red", 1),
            Err(PaletteError::NotHex("red".into()))
        );
        assert_eq!(
            p.set(Operation::Cut, "#FF0000", 0),
            Err(PaletteError::Aci(0))
        );
        assert_eq!(
            p.set(Operation::Cut, "#FF0000", 256),
            Err(PaletteError::Aci(256))
        );
        p.set(Operation::Engrave, "#0000FF", 7).unwrap();
        assert_eq!(
            p.check_distinct(),
            Err(PaletteError::Shared(Operation::Engrave, Operation::Score))
        );
    }
}
