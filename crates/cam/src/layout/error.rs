//! Why a scored plate layout could not be made. The layout itself is in the nester's vocabulary
//! ([`cam_nest::NestSolution`]), which every packer of the pipeline produces.

use cam_nest::NestBin;
use thiserror::Error;

/// Why a layout could not be made.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LayoutError {
    #[error("invalid sheet: {width_mm} x {height_mm} mm (both sides must be finite and > 0)")]
    InvalidSheet { width_mm: f64, height_mm: f64 },
    #[error("invalid {name}: {value} (must be finite and >= 0)")]
    InvalidParameter { name: &'static str, value: f64 },
    #[error("item {item} is invalid: {reason}")]
    InvalidItem { item: usize, reason: String },
    #[error(
        "item {item} is larger than the sheet: {width_mm:.1} x {height_mm:.1} mm on a \
         {sheet_width_mm:.1} x {sheet_height_mm:.1} mm sheet ({usable_width_mm:.2} x \
         {usable_height_mm:.2} mm usable inside the edge clearance, in no allowed rotation)"
    )]
    TooLarge {
        item: usize,
        width_mm: f64,
        height_mm: f64,
        sheet_width_mm: f64,
        sheet_height_mm: f64,
        usable_width_mm: f64,
        usable_height_mm: f64,
    },
    #[error("needs {needed} sheets but the stock is {stock}")]
    TooManySheets { needed: usize, stock: usize },
}

/// Checks that both sides of a sheet are finite and positive.
pub(crate) fn check_sheet(sheet: &NestBin) -> Result<(), LayoutError> {
    let ok = |v: f64| v.is_finite() && v > 0.0;
    if ok(sheet.width_mm) && ok(sheet.height_mm) {
        Ok(())
    } else {
        Err(LayoutError::InvalidSheet {
            width_mm: sheet.width_mm,
            height_mm: sheet.height_mm,
        })
    }
}

/// Checks that a length parameter (kerf, gap, margin) is finite and not negative.
pub(crate) fn check_length(name: &'static str, value: f64) -> Result<(), LayoutError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(LayoutError::InvalidParameter { name, value })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_read_well() {
        let e = LayoutError::TooManySheets {
            needed: 3,
            stock: 2,
        };
        assert_eq!(e.to_string(), "needs 3 sheets but the stock is 2");
    }
}
