//! `effects.toml` (`calibrate --effects FILE`): effects a lab declares as compositions of the model's
//! physical primitives (docs/calibration.md, "Effects a lab declares"), each with its parameters, their
//! bounds and null values.
//!
//! One parameter for the whole effect (it drives every primitive, each through its `map`):
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
//! Or one parameter per primitive, fitted jointly (the effect has no `null` or `bounds` of its own):
//!
//! ```toml
//! [[effect]]
//! name = "held-root"
//! primitives = [
//!   { kind = "electrode-margin", parameter = "root_length_m", null = 0.0, bounds = [0.0, 5e-3] },
//!   { kind = "clamp-compliance-per-width", parameter = "c_w_rad_m_per_N_m", null = 0.0, bounds = [0.0, 0.05] },
//! ]
//! ```
//!
//! Values are in the primitives' SI units (a length in m, a compliance in rad/(N·m)). Every refusal is
//! one [`InputError`] naming the file, the field, the value and what is allowed.

use super::library::{DeclaredParameter, DeclaredSpec, EffectId};
use crate::input::{short_number, InputError, Range, TableReader};
use actuator_model::effects::EFFECT_NAMES;
use actuator_model::primitives::{Link, Map, Primitive, Property, Target};
use std::path::Path;

/// Any finite number (bounds and null values are checked against the primitives afterwards).
const FINITE: Range = Range::open(f64::NEG_INFINITY, f64::INFINITY, "");

/// Primitive kinds as the file spells them (the parameter's unit is in docs/calibration.md).
const KINDS: [(&str, Option<Primitive>); 15] = [
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
    ("rigid-root", Some(Primitive::RigidRoot)),
    ("edge-margin", Some(Primitive::EdgeMargin)),
    (
        "inactive-surface-layer",
        Some(Primitive::InactiveSurfaceLayer),
    ),
    ("d31-thickness-power", Some(Primitive::D31ThicknessPower)),
    ("added-mass", Some(Primitive::AddedMass)),
    ("added-mass-per-length", Some(Primitive::AddedMassPerLength)),
    ("added-mass-per-area", Some(Primitive::AddedMassPerArea)),
    ("tip-mass", Some(Primitive::TipMass)),
];

const TARGETS: [(&str, Target); 3] = [
    ("pzt", Target::Pzt),
    ("passive", Target::Passive),
    ("bond", Target::Bond),
];

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

const MAPS: [(&str, Map); 3] = [
    ("identity", Map::Identity),
    ("reciprocal", Map::Reciprocal),
    ("micro", Map::Micro),
];

fn names<T>(list: &[(&str, T)]) -> String {
    list.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
}

/// A primitive's fields as an effects file spells them (`kind = "scale", target = "passive",
/// property = "E1"`), for the files calibrate writes (`suggested-effects.toml`); [`parse`] reads them
/// back to the same primitive.
pub fn primitive_fields(p: Primitive) -> String {
    fn spelled<T: PartialEq>(list: &[(&'static str, T)], x: T) -> &'static str {
        list.iter().find(|(_, v)| *v == x).map_or("?", |(n, _)| *n)
    }
    match p {
        Primitive::Scale { target, property } => format!(
            "kind = \"scale\", target = \"{}\", property = \"{}\"",
            spelled(&TARGETS, target),
            spelled(&PROPERTIES, property)
        ),
        other => format!("kind = \"{}\"", spelled(&KINDS, Some(other))),
    }
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
    parse(path, &crate::input::read_toml(path)?)
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

/// The keys a primitive takes when it has its own parameter.
const OWN_PARAMETER: [&str; 3] = ["parameter", "null", "bounds"];

fn effect(t: &TableReader<'_>) -> Result<DeclaredSpec, InputError> {
    let name = t.name("name", "the effect's name")?;
    let readers = t.tables("primitives")?;
    // One parameter for the effect when it has bounds of its own; else one per primitive.
    let shared = t
        .keys()
        .iter()
        .any(|k| ["null", "bounds", "parameter"].contains(k));
    let parameters = if shared {
        if let Some((p, key)) = readers.iter().find_map(|p| {
            let keys = p.keys();
            OWN_PARAMETER
                .into_iter()
                .find(|k| keys.contains(k))
                .map(|k| (p, k))
        }) {
            return Err(InputError::invalid(
                t.file(),
                &p.path(key),
                "(given)",
                format!(
                    "{} has one parameter ({}); give parameter, null and bounds on every primitive or on none",
                    t.prefix_or("effect"),
                    t.path("bounds")
                ),
            ));
        }
        let parameter = parameter_name(t, name.replace('-', "_"))?;
        let links = readers.iter().map(link).collect::<Result<Vec<_>, _>>()?;
        vec![parameter_of(t, parameter, links, false)?]
    } else {
        let mut parameters: Vec<DeclaredParameter> = Vec::new();
        for (k, p) in readers.iter().enumerate() {
            let parameter = parameter_name(p, format!("{}_{}", name.replace('-', "_"), k + 1))?;
            if parameters.iter().any(|q| q.name == parameter) {
                return Err(InputError::invalid(
                    t.file(),
                    &p.path("parameter"),
                    format!("{parameter:?}"),
                    "named twice in this effect; each parameter needs its own name",
                ));
            }
            let l = link(p)?;
            parameters.push(parameter_of(p, parameter, vec![l], true)?);
        }
        parameters
    };
    t.finish()?;
    Ok(DeclaredSpec { name, parameters })
}

/// The optional `parameter` name of `t`, else `default`.
fn parameter_name(t: &TableReader<'_>, default: String) -> Result<String, InputError> {
    match t.optional_string("parameter", "the parameter's name")? {
        Some(p) if !p.trim().is_empty() && p.len() <= 64 => Ok(p.to_string()),
        Some(p) => Err(InputError::invalid(
            t.file(),
            &t.path("parameter"),
            format!("{p:?}"),
            "expected 1 to 64 characters",
        )),
        None => Ok(default),
    }
}

/// The parameter whose `null` and `bounds` are keys of `t` (the effect's table, or the primitive's own
/// when `own`), driving `primitives`; refused when the null value does not switch every primitive off
/// or the bounds take one outside its physical range.
fn parameter_of(
    t: &TableReader<'_>,
    name: String,
    primitives: Vec<Link>,
    own: bool,
) -> Result<DeclaredParameter, InputError> {
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
    for (i, link) in primitives.iter().enumerate() {
        // The primitive's own table when it has its own parameter; numbered from 1, as the reader
        // names `[[tables]]`.
        let field = if own {
            t.prefix_or("primitive")
        } else {
            t.path(&format!("primitives[{}]", i + 1))
        };
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
        // Every map is monotone: the ends of the bounds are the extremes, and the reciprocal must not
        // cross zero.
        let (p_lo, inclusive, p_hi) = link.primitive.physical_range();
        let crosses_zero = link.map == Map::Reciprocal && lo <= 0.0 && hi >= 0.0;
        for end in [lo, hi] {
            let v = link.map.of(end).unwrap_or(f64::NAN);
            if crosses_zero || !link.primitive.allows(v) {
                let physical = Range {
                    lo: p_lo,
                    lo_inclusive: inclusive,
                    hi: p_hi,
                    hi_inclusive: false,
                    unit: "",
                };
                return Err(bad_bounds(format!(
                    "{field} would take the value {}, at {}: outside its physical range, {}",
                    short_number(v),
                    short_number(end),
                    physical.bounds()
                )));
            }
        }
    }
    Ok(DeclaredParameter {
        name,
        null,
        lo,
        hi,
        primitives,
    })
}

/// One entry of `primitives`: its kind (with target and property for `scale`) and map. Keys of its own
/// parameter are read by [`parameter_of`], so `finish` is left to the caller's table when shared.
fn link(p: &TableReader<'_>) -> Result<Link, InputError> {
    // `scale` alone takes a target and a property.
    let primitive = match one_of(p, "kind", "primitive", &KINDS)? {
        Some(primitive) => primitive,
        None => {
            let target = one_of(p, "target", "material target", &TARGETS)?;
            let property = one_of(p, "property", "material property", &PROPERTIES)?;
            if let Err(why) = target.scalable(property) {
                let given = p.string("property", "")?;
                return Err(InputError::invalid(
                    p.file(),
                    &p.path("property"),
                    format!("{given:?}"),
                    why,
                ));
            }
            Primitive::Scale { target, property }
        }
    };
    let map = if p.has("map") {
        one_of(p, "map", "map from the parameter", &MAPS)?
    } else {
        Map::Identity
    };
    // Its own parameter's keys, when it has one, are checked by the caller.
    for k in OWN_PARAMETER {
        p.has(k);
    }
    p.finish()?;
    Ok(Link { primitive, map })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Vec<DeclaredSpec>, InputError> {
        let file = Path::new("effects.toml");
        parse(file, &crate::input::parse_toml(file, text)?)
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
        assert_eq!(s.name, "soft-fibre");
        let p = &s.parameters[0];
        assert_eq!(
            (p.name.as_str(), p.null, p.lo, p.hi),
            ("soft_fibre", 1.0, 0.3, 1.2)
        );
        assert_eq!(
            p.primitives,
            vec![Link {
                primitive: Primitive::Scale {
                    target: Target::Passive,
                    property: Property::E1
                },
                map: Map::Identity
            }]
        );
        assert_eq!(
            specs[1].parameters[0].primitives[0].primitive,
            Primitive::ClampCompliancePerWidth
        );
        assert_eq!(specs[1].parameters[0].name, "c_w_rad_m_per_N_m");
    }

    const HELD_ROOT: &str = r#"
[[effect]]
name = "held-root"
primitives = [
  { kind = "electrode-margin", parameter = "root_length_m", null = 0.0, bounds = [0.0, 5e-3] },
  { kind = "clamp-compliance-per-width", null = 0.0, bounds = [0.0, 0.05] },
  { kind = "scale", target = "bond", property = "E1", null = 1.0, bounds = [0.2, 2.0] },
]
"#;

    #[test]
    fn an_effect_with_a_parameter_per_primitive_reads_into_its_parameters() {
        let specs = read(HELD_ROOT).unwrap();
        let p = &specs[0].parameters;
        assert_eq!(p.len(), 3);
        assert_eq!(
            (p[0].name.as_str(), p[0].null, p[0].lo, p[0].hi),
            ("root_length_m", 0.0, 0.0, 5e-3)
        );
        // Unnamed: the effect's name and the primitive's position.
        assert_eq!(p[1].name, "held_root_2");
        assert_eq!(
            p[1].primitives[0].primitive,
            Primitive::ClampCompliancePerWidth
        );
        assert_eq!(
            p[2].primitives[0].primitive,
            Primitive::Scale {
                target: Target::Bond,
                property: Property::E1
            }
        );
    }

    /// A layer thickness given in µm (`map = "micro"`) reads with its bounds in µm and is refused below
    /// zero like one in m; the d31 power of the plate thickness takes an exponent of either sign.
    #[test]
    fn a_micro_map_and_the_d31_thickness_power_read() {
        let layer = |bounds: &str| {
            format!(
                "[[effect]]\nname = \"skin\"\nparameter = \"skin_um\"\nnull = 0.0\nbounds = {bounds}\nprimitives = [{{ kind = \"inactive-surface-layer\", map = \"micro\" }}]\n"
            )
        };
        let specs = read(&layer("[0.0, 40.0]")).unwrap();
        let p = &specs[0].parameters[0];
        assert_eq!(p.primitives[0].map, Map::Micro);
        assert_eq!(p.applied(15.0).next().unwrap().value, 15e-6);
        let e = read(&layer("[-2.0, 40.0]")).unwrap_err().to_string();
        assert!(e.contains("effect[1].bounds") && e.contains("-2e-6"), "{e}");
        let power = "[[effect]]\nname = \"trend\"\nnull = 0.0\nbounds = [-0.5, 0.5]\nprimitives = [{ kind = \"d31-thickness-power\" }]\n";
        let specs = read(power).unwrap();
        let p = &specs[0].parameters[0];
        assert_eq!(p.primitives[0].primitive, Primitive::D31ThicknessPower);
        assert_eq!((p.lo, p.hi), (-0.5, 0.5));
    }

    /// The rigid root, the edge margins, the inactive surface layer and the added masses read by their
    /// names (SI, null 0), and a bound below zero is refused in one line naming the field, the value and the
    /// physical range.
    #[test]
    fn the_root_edge_and_surface_kinds_read_and_refuse_negative_lengths() {
        for (kind, primitive, hi) in [
            ("rigid-root", Primitive::RigidRoot, "5e-3"),
            ("edge-margin", Primitive::EdgeMargin, "1e-3"),
            (
                "inactive-surface-layer",
                Primitive::InactiveSurfaceLayer,
                "50e-6",
            ),
            ("added-mass", Primitive::AddedMass, "1e-5"),
            (
                "added-mass-per-length",
                Primitive::AddedMassPerLength,
                "1e-4",
            ),
            ("added-mass-per-area", Primitive::AddedMassPerArea, "0.05"),
        ] {
            let text = format!(
                "[[effect]]\nname = \"x\"\nnull = 0.0\nbounds = [0.0, {hi}]\nprimitives = [{{ kind = \"{kind}\" }}]\n"
            );
            let specs = read(&text).unwrap();
            let p = &specs[0].parameters[0];
            assert_eq!(p.primitives[0].primitive, primitive, "{kind}");
            assert_eq!((p.null, p.lo, p.hi), (0.0, 0.0, hi.parse().unwrap()));
            let e = read(&text.replace("[0.0,", "[-1e-4,"))
                .unwrap_err()
                .to_string();
            let want = format!(
                "effects.toml: effect[1].bounds = [-0.0001, {}]: effect[1].primitives[1] would take the value -0.0001, at -0.0001: outside its physical range, at least 0",
                hi.parse::<f64>().unwrap()
            );
            assert_eq!(e, want);
            let e = read(&text.replace("null = 0.0", "null = 1e-5"))
                .unwrap_err()
                .to_string();
            assert!(
                e.starts_with("effects.toml: effect[1].null = 0.00001: at this value effect[1].primitives[1] is 0.00001, not its null value 0"),
                "{e}"
            );
        }
    }

    /// The refusals of the one-parameter-per-primitive form name the primitive's own field.
    #[test]
    fn bad_parameters_of_a_primitive_are_refused_at_their_index_path() {
        let held = |from: &str, to: &str| HELD_ROOT.replace(from, to);
        let cases = [
            (
                held("bounds = [0.0, 0.05]", "bounds = [0.05, 0.0]"),
                "effects.toml: effect[1].primitives[2].bounds = [0.05, 0]: expected [lo, hi] with lo < hi",
            ),
            (
                held("null = 0.0, bounds = [0.0, 0.05]", "null = 0.1, bounds = [0.0, 0.05]"),
                "effects.toml: effect[1].primitives[2].bounds = [0, 0.05]: expected bounds that contain the null value 0.1",
            ),
            (
                held("bounds = [0.0, 5e-3]", "bounds = [-1e-3, 5e-3]"),
                "effects.toml: effect[1].primitives[1].bounds = [-0.001, 0.005]: effect[1].primitives[1] would take the value -0.001, at -0.001: outside its physical range, at least 0",
            ),
            (
                held(", null = 0.0, bounds = [0.0, 0.05]", ""),
                "effects.toml: effect[1].primitives[2].null: missing",
            ),
            (
                held("parameter = \"root_length_m\"", "parameter = \"held_root_2\""),
                "effects.toml: effect[1].primitives[2].parameter = \"held_root_2\": named twice in this effect",
            ),
            (
                held("name = \"held-root\"", "name = \"held-root\"\nnull = 0.0\nbounds = [0.0, 1.0]"),
                "effects.toml: effect[1].primitives[1].parameter = (given): effect[1] has one parameter (effect[1].bounds); give parameter, null and bounds on every primitive or on none",
            ),
            (
                held("property = \"E1\"", "property = \"d31\""),
                "effects.toml: effect[1].primitives[3].property = \"d31\": the model's bond layer has no such property (it is not piezoelectric); allowed for the bond: E1, nu12, density, thickness",
            ),
            (
                held("property = \"E1\"", "property = \"G12\""),
                "effects.toml: effect[1].primitives[3].property = \"G12\": the bond layer is isotropic",
            ),
            (
                held("kind = \"electrode-margin\",", "kind = \"electrode-margin\", lo = 0,"),
                "effects.toml: effect[1].primitives[1].lo = 0: unknown key",
            ),
        ];
        for (text, want) in cases {
            let e = read(&text).unwrap_err().to_string();
            assert!(e.starts_with(want), "{e}\n  expected to start with\n{want}");
            assert!(!e.contains('\n'), "{e}");
        }
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
                "effects.toml: effect[1].null = NaN: outside the allowed range: any finite number",
            ),
            (
                soft("bounds = [0.3, 1.2]", "bounds = [0.3, nan]"),
                "effects.toml: effect[1].bounds[1] = NaN: outside the allowed range: any finite number",
            ),
            (
                soft("target = \"passive\"", "target = \"glue\""),
                "effects.toml: effect[1].primitives[1].target = \"glue\": unknown material target: one of pzt, passive, bond",
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
                "effects.toml: effect[1].bounds = [-0.5, 1.2]: effect[1].primitives[1] would take the value -0.5, at -0.5: outside its physical range, greater than 0",
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
                "effects.toml: effects = (table): unknown key; did you mean `effect`? known keys here: effect",
            ),
        ];
        for (text, want) in cases {
            let e = read(&text).unwrap_err().to_string();
            assert!(e.starts_with(want), "{e}\n  expected to start with\n{want}");
            assert!(!e.contains('\n'), "{e}");
        }
    }
}
