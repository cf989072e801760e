//! `effects.toml` (`calibrate --effects FILE`): effects a lab declares as compositions of the model's
//! physical primitives (docs/calibration.md, "Effects a lab declares"), each with one parameter, its
//! bounds and its null value.
//!
//! ```toml
//! [[effect]]
//! name = "soft-fibre"                 # not a library effect's name; unique in the file
//! parameter = "passive_e1_scale"      # optional (default: the name with `_` for `-`)
//! null = 1.0                          # the value that switches the effect off
//! bounds = [0.3, 1.2]                 # lo < hi, null inside
//! primitives = [{ kind = "scale", target = "passive", property = "E1" }]
//! ```
//!
//! Values are in the primitives' SI units (a length in m, a compliance in rad/(N·m)). Every refusal is
//! one [`InputError`] naming the file, the field, the value and what is allowed.

use super::{InputError, Range, TableReader};
use crate::calibrate::library::{DeclaredSpec, EffectId};
use actuator_model::effects::EFFECT_NAMES;
use actuator_model::primitives::{Link, Map, Primitive, Property, Target};
use std::path::Path;

/// Any finite number (bounds and null values are checked against the primitives afterwards).
const FINITE: Range = Range::open(f64::NEG_INFINITY, f64::INFINITY, "");

/// Primitive kinds as the file spells them (the parameter's unit is in docs/calibration.md).
const KINDS: [(&str, Option<Primitive>); 7] = [
    ("scale", None),
    ("inserted-layer", Some(Primitive::InsertedLayer)),
    ("field-dependent-d31", Some(Primitive::FieldDependentD31)),
    ("electrode-margin", Some(Primitive::ElectrodeMargin)),
    ("clamp-compliance", Some(Primitive::ClampCompliance)),
    (
        "clamp-compliance-per-width",
        Some(Primitive::ClampCompliancePerWidth),
    ),
    ("compliant-extension", Some(Primitive::CompliantExtension)),
];

const TARGETS: [(&str, Target); 2] = [("pzt", Target::Pzt), ("passive", Target::Passive)];

const PROPERTIES: [(&str, Property); 8] = [
    ("E1", Property::E1),
    ("E2", Property::E2),
    ("G12", Property::G12),
    ("nu12", Property::Nu12),
    ("d31", Property::D31),
    ("permittivity", Property::Permittivity),
    ("density", Property::Density),
    ("thickness", Property::Thickness),
];

const MAPS: [(&str, Map); 2] = [("identity", Map::Identity), ("reciprocal", Map::Reciprocal)];

fn names<T>(list: &[(&str, T)]) -> String {
    list.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
}

/// Look `name` up in `list`, or refuse it naming the allowed names.
fn one_of<T: Copy>(
    t: &TableReader<'_>,
    key: &str,
    what: &str,
    list: &[(&str, T)],
) -> Result<T, InputError> {
    let expected = format!("{what}: one of {}", names(list));
    let name = t.string(key, &expected)?;
    list.iter()
        .find(|(n, _)| *n == name)
        .map(|(_, v)| *v)
        .ok_or_else(|| {
            InputError::invalid(
                t.file(),
                &t.path(key),
                format!("{name:?}"),
                format!("unknown {expected}"),
            )
        })
}

/// Read and validate an effects file.
pub fn read_path(path: &Path) -> Result<Vec<DeclaredSpec>, InputError> {
    parse(path, &super::read_toml(path)?)
}

/// Validate a parsed effects file (named `file` in errors).
pub fn parse(file: &Path, table: &toml::Table) -> Result<Vec<DeclaredSpec>, InputError> {
    let root = TableReader::new(file, "", table);
    root.only_keys(&["effect"])?;
    let mut specs: Vec<DeclaredSpec> = Vec::new();
    for t in root.tables("effect")? {
        let spec = effect(&t)?;
        let clash = if EFFECT_NAMES.contains(&spec.name.as_str())
            || EffectId::StiffnessScale.name() == spec.name
        {
            Some("the name of a library effect; choose another name")
        } else if specs.iter().any(|s| s.name == spec.name) {
            Some("declared twice; each effect needs its own name")
        } else {
            None
        };
        if let Some(why) = clash {
            return Err(InputError::invalid(
                file,
                &t.path("name"),
                format!("{:?}", spec.name),
                why,
            ));
        }
        specs.push(spec);
    }
    Ok(specs)
}

fn effect(t: &TableReader<'_>) -> Result<DeclaredSpec, InputError> {
    let name = t.name("name", "the effect's name")?;
    let parameter = match t.optional_string("parameter", "the parameter's name")? {
        Some(p) if !p.trim().is_empty() && p.len() <= 64 => p.to_string(),
        Some(p) => {
            return Err(InputError::invalid(
                t.file(),
                &t.path("parameter"),
                format!("{p:?}"),
                "expected 1 to 64 characters",
            ))
        }
        None => name.replace('-', "_"),
    };
    let null = t.number_in("null", FINITE)?;
    let bounds = t.numbers_in("bounds", FINITE, 2, 2)?;
    let (lo, hi) = (bounds[0], bounds[1]);
    let bad_bounds = |why: String| {
        InputError::invalid(t.file(), &t.path("bounds"), format!("[{lo}, {hi}]"), why)
    };
    if lo >= hi {
        return Err(bad_bounds("expected [lo, hi] with lo < hi".into()));
    }
    if !(lo..=hi).contains(&null) {
        return Err(bad_bounds(format!(
            "expected bounds that contain the null value {null}"
        )));
    }
    let primitives = primitives(t)?;
    for (i, link) in primitives.iter().enumerate() {
        // Numbered from 1, as the reader names `[[tables]]`.
        let field = t.path(&format!("primitives[{}]", i + 1));
        let at_null = link.map.of(null).unwrap_or(f64::NAN);
        let want = link.primitive.null();
        if (at_null - want).abs() > 1e-12 * want.abs().max(1.0) {
            return Err(InputError::invalid(
                t.file(),
                &t.path("null"),
                null,
                format!(
                    "at this value {field} is {at_null}, not its null value {want}: the null value must switch every primitive off"
                ),
            ));
        }
        // Identity and reciprocal are monotone: the ends of the bounds are the extremes, and the
        // reciprocal must not cross zero.
        let (p_lo, inclusive, p_hi) = link.primitive.physical_range();
        let crosses_zero = link.map == Map::Reciprocal && lo <= 0.0 && hi >= 0.0;
        for end in [lo, hi] {
            let v = link.map.of(end).unwrap_or(f64::NAN);
            if crosses_zero || !link.primitive.allows(v) {
                let open = if inclusive { '[' } else { '(' };
                return Err(bad_bounds(format!(
                    "{field} would take the value {v} at {end}; its physical range is {open}{p_lo}, {p_hi})"
                )));
            }
        }
    }
    t.finish()?;
    Ok(DeclaredSpec {
        name,
        parameter,
        null,
        lo,
        hi,
        primitives,
    })
}

fn primitives(t: &TableReader<'_>) -> Result<Vec<Link>, InputError> {
    t.tables("primitives")?
        .iter()
        .map(|p| {
            // `scale` alone takes a target and a property.
            let primitive = match one_of(p, "kind", "primitive", &KINDS)? {
                Some(primitive) => primitive,
                None => Primitive::Scale {
                    target: one_of(p, "target", "material target", &TARGETS)?,
                    property: one_of(p, "property", "material property", &PROPERTIES)?,
                },
            };
            let map = if p.has("map") {
                one_of(p, "map", "map from the parameter", &MAPS)?
            } else {
                Map::Identity
            };
            p.finish()?;
            Ok(Link { primitive, map })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Vec<DeclaredSpec>, InputError> {
        let file = Path::new("effects.toml");
        parse(file, &super::super::parse_toml(file, text)?)
    }

    const SOFT: &str = r#"
[[effect]]
name = "soft-fibre"
null = 1.0
bounds = [0.3, 1.2]
primitives = [{ kind = "scale", target = "passive", property = "E1" }]
"#;

    #[test]
    fn a_good_declaration_reads_into_its_composition() {
        let specs = read(&format!(
            "{SOFT}\n[[effect]]\nname = \"wide-clamp\"\nparameter = \"c_w_rad_m_per_N_m\"\nnull = 0\nbounds = [0, 0.05]\nprimitives = [{{ kind = \"clamp-compliance-per-width\" }}]\n"
        ))
        .unwrap();
        assert_eq!(specs.len(), 2);
        let s = &specs[0];
        assert_eq!(
            (s.name.as_str(), s.parameter.as_str(), s.null, s.lo, s.hi),
            ("soft-fibre", "soft_fibre", 1.0, 0.3, 1.2)
        );
        assert_eq!(
            s.primitives,
            vec![Link {
                primitive: Primitive::Scale {
                    target: Target::Passive,
                    property: Property::E1
                },
                map: Map::Identity
            }]
        );
        assert_eq!(
            specs[1].primitives[0].primitive,
            Primitive::ClampCompliancePerWidth
        );
        assert_eq!(specs[1].parameter, "c_w_rad_m_per_N_m");
    }

    /// Each kind of bad declaration, with the one line it gets (file, field, value, what is allowed).
    #[test]
    fn bad_declarations_are_refused_in_one_line() {
        let soft = |from: &str, to: &str| SOFT.replace(from, to);
        let cases = [
            (
                soft("kind = \"scale\"", "kind = \"stretch\""),
                "effects.toml: effect[1].primitives[1].kind = \"stretch\": unknown primitive: one of scale, inserted-layer,",
            ),
            (
                soft("bounds = [0.3, 1.2]", "bounds = [1.1, 1.2]"),
                "effects.toml: effect[1].bounds = [1.1, 1.2]: expected bounds that contain the null value 1",
            ),
            (
                soft("bounds = [0.3, 1.2]", "bounds = [1.2, 0.3]"),
                "effects.toml: effect[1].bounds = [1.2, 0.3]: expected [lo, hi] with lo < hi",
            ),
            (
                soft("bounds = [0.3, 1.2]", "bounds = [1.0, 1.0]"),
                "effects.toml: effect[1].bounds = [1, 1]: expected [lo, hi] with lo < hi",
            ),
            (
                soft("null = 1.0", "null = nan"),
                "effects.toml: effect[1].null = NaN: outside the allowed range (-inf, inf)",
            ),
            (
                soft("bounds = [0.3, 1.2]", "bounds = [0.3, nan]"),
                "effects.toml: effect[1].bounds[1] = NaN: outside the allowed range (-inf, inf)",
            ),
            (
                soft("target = \"passive\"", "target = \"bond\""),
                "effects.toml: effect[1].primitives[1].target = \"bond\": unknown material target: one of pzt, passive",
            ),
            (
                soft("property = \"E1\"", "property = \"E3\""),
                "effects.toml: effect[1].primitives[1].property = \"E3\": unknown material property: one of E1, E2,",
            ),
            (
                format!("{SOFT}{SOFT}"),
                "effects.toml: effect[2].name = \"soft-fibre\": declared twice; each effect needs its own name",
            ),
            (
                soft("soft-fibre", "clamp-compliance"),
                "effects.toml: effect[1].name = \"clamp-compliance\": the name of a library effect; choose another name",
            ),
            (
                soft("bounds = [0.3, 1.2]", "bounds = [-0.5, 1.2]"),
                "effects.toml: effect[1].bounds = [-0.5, 1.2]: effect[1].primitives[1] would take the value -0.5 at -0.5; its physical range is (0, inf)",
            ),
            (
                soft("null = 1.0", "null = 0.5"),
                "effects.toml: effect[1].null = 0.5: at this value effect[1].primitives[1] is 0.5, not its null value 1",
            ),
            (
                soft("name = \"soft-fibre\"", "name = \"soft-fibre\"\nsize = 3"),
                "effects.toml: effect[1].size = 3: unknown key",
            ),
            (
                "[effects]\nname = \"x\"\n".to_string(),
                "effects.toml: effects = (table): unknown key; known keys here: effect",
            ),
        ];
        for (text, want) in cases {
            let e = read(&text).unwrap_err().to_string();
            assert!(e.starts_with(want), "{e}\n  expected to start with\n{want}");
            assert!(!e.contains('\n'), "{e}");
        }
    }
}
