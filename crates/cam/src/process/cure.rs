//! The cures of a process template: the clamp stack's (`[cure]`), the passive layup's before it is cut
//! (`[cure.passive]`, method 1) and the linkage laminate's (`[linkage.cure]`), each a temperature, a
//! time and how the stack is pressed.

use crate::input::limits::{CURE_C, CURE_MIN, PRESSURE_KPA};
use crate::input::{InputError, TableReader};

/// A cure: temperature and time, and how the stack is pressed (`[cure]`, `[cure.passive]`).
#[derive(Debug, Clone, PartialEq)]
pub struct CureStep {
    /// Oven or press temperature, °C.
    pub temperature_c: f64,
    /// Time at temperature, minutes.
    pub time_min: f64,
    /// How the stack is pressed, in the lab's words (a C-clamp, a press and its pressure).
    pub pressure: String,
    /// The pressure on the parts, kPa (`pressure_kPa`), when the template gives it as a number: the
    /// book turns it into the force on each panel's parts.
    pub pressure_kpa: Option<f64>,
}

impl CureStep {
    /// One cure table: `temperature_C`, `time_min`, `pressure`, `pressure_kPa`.
    pub fn read(t: &TableReader<'_>) -> Result<CureStep, InputError> {
        Ok(CureStep {
            temperature_c: t.number_in("temperature_C", CURE_C)?,
            time_min: t.number_in("time_min", CURE_MIN)?,
            pressure: t
                .string("pressure", "how the stack is pressed, in words")?
                .to_string(),
            pressure_kpa: t.optional_number_in("pressure_kPa", PRESSURE_KPA)?,
        })
    }

    /// The sub-table `key` of `t`, if it has one, read as a cure.
    pub fn optional(t: &TableReader<'_>, key: &str) -> Result<Option<CureStep>, InputError> {
        match t.optional_table(key)? {
            Some(c) => {
                let step = CureStep::read(&c)?;
                c.finish()?;
                Ok(Some(step))
            }
            None => Ok(None),
        }
    }
}

/// The cures a process needs: the clamp stack in the oven, and (method 1) the passive layup pressed
/// and cured before it is cut.
#[derive(Debug, Clone, PartialEq)]
pub struct Cure {
    /// The clamp stack's cure.
    pub clamp: CureStep,
    /// The passive layup's own cure before cutting (method 1), if the process has one.
    pub passive: Option<CureStep>,
}

impl Cure {
    /// `[cure]`: the clamp's cure, and `[cure.passive]`, the passive stack's own cure, if it has one.
    pub fn read(root: &TableReader<'_>) -> Result<Cure, InputError> {
        let t = root.table("cure")?;
        let clamp = CureStep::read(&t)?;
        let passive = CureStep::optional(&t, "passive")?;
        t.finish()?;
        Ok(Cure { clamp, passive })
    }
}
