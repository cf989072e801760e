//! The geometric features the layer builders draw (score lines, part outlines, holes, labels, …) and the
//! laser operation each one gets: the `[features]` table of a process template. A template that leaves a
//! feature out keeps its default operation, so only the features a template names change its files.

use crate::drawing::model::Operation;
use crate::input::{InputError, TableReader};
use std::path::Path;

/// A kind of geometry a layer builder draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feature {
    /// Score lines of a PZT sheet (snap lines between the plates).
    PztScoreLine,
    /// The PZT sheet edge, an alignment reference.
    PztSheetOutline,
    /// Outer contour of a cut part (passive part, ply, Pyralux bond part).
    PartOutline,
    /// Silver-epoxy via through a Pyralux bond part.
    Via,
    /// Pin hole through every ply of a ply-by-ply part.
    RegistrationHole,
    /// Design name and copy number along a part's axis.
    PartLabel,
    /// Outline of a clamp panel.
    PanelOutline,
    /// Registration pin hole of a clamp panel.
    PinHole,
    /// Actuator cavity of a mold layer.
    MoldCavity,
    /// Stacking-order window onto the layers below.
    StackingWindow,
    /// Layer number inside a clamp layer's own stacking window.
    WindowNumber,
    /// Design, layer and panel number on the panel border.
    PanelLabel,
    /// Alignment crosshair of a clamp panel.
    Fiducial,
    /// A flexure gap slot of a linkage's carbon layer, or a window of its film or adhesive layer.
    LinkageCutOut,
    /// The cut through the laminated linkage stack that frees the linkage.
    LinkageRelease,
    /// Mounting hole of a linkage's airframe tab, cut with the release.
    LinkageHole,
    /// Name, material, thickness and size of a part sheet, where no part is.
    SheetLabel,
}

/// Operations that leave a part or panel cut out: `secondary` is the lab's second cut pass.
const THROUGH: &[Operation] = &[Operation::Cut, Operation::Secondary];
/// Operations that mark without cutting through: a cut label would riddle the part.
const MARK: &[Operation] = &[Operation::Engrave, Operation::Score, Operation::Secondary];
/// A score line may be scored, cut through (no snapping) or given the second pass; an engraved one
/// would be too shallow to snap along.
const SCORE_LINE: &[Operation] = &[Operation::Score, Operation::Cut, Operation::Secondary];
/// The sheet edge is only a guide: the never-run reference, or a mark. A cut along it would trace the
/// sheet edge with the laser.
const GUIDE: &[Operation] = &[Operation::Reference, Operation::Engrave, Operation::Score];

impl Feature {
    /// Every feature, in the order of the `[features]` table of the shipped templates: each outer
    /// contour followed by what lies inside it ([`Feature::inside`]).
    pub const ALL: [Feature; 17] = [
        Feature::PztScoreLine,
        Feature::PztSheetOutline,
        Feature::PartOutline,
        Feature::Via,
        Feature::RegistrationHole,
        Feature::PartLabel,
        Feature::PanelOutline,
        Feature::PinHole,
        Feature::MoldCavity,
        Feature::StackingWindow,
        Feature::WindowNumber,
        Feature::PanelLabel,
        Feature::Fiducial,
        Feature::LinkageCutOut,
        Feature::LinkageRelease,
        Feature::LinkageHole,
        Feature::SheetLabel,
    ];

    /// Key in the `[features]` table.
    pub fn key(self) -> &'static str {
        match self {
            Feature::PztScoreLine => "pzt-score-line",
            Feature::PztSheetOutline => "pzt-sheet-outline",
            Feature::PartOutline => "part-outline",
            Feature::Via => "via",
            Feature::RegistrationHole => "registration-hole",
            Feature::PartLabel => "part-label",
            Feature::PanelOutline => "panel-outline",
            Feature::PinHole => "pin-hole",
            Feature::MoldCavity => "mold-cavity",
            Feature::StackingWindow => "stacking-window",
            Feature::WindowNumber => "window-number",
            Feature::PanelLabel => "panel-label",
            Feature::Fiducial => "fiducial",
            Feature::LinkageCutOut => "linkage-cut-out",
            Feature::LinkageRelease => "linkage-release",
            Feature::LinkageHole => "linkage-hole",
            Feature::SheetLabel => "sheet-label",
        }
    }

    /// The operation this feature gets when the template's `[features]` table leaves it out.
    pub fn default_operation(self) -> Operation {
        match self {
            Feature::PztScoreLine => Operation::Score,
            Feature::PztSheetOutline | Feature::SheetLabel => Operation::Reference,
            Feature::PartLabel
            | Feature::WindowNumber
            | Feature::PanelLabel
            | Feature::Fiducial => Operation::Engrave,
            _ => Operation::Cut,
        }
    }

    /// Operations this feature may be given without spoiling the build.
    pub fn allowed(self) -> &'static [Operation] {
        match self {
            Feature::PztScoreLine => SCORE_LINE,
            Feature::PztSheetOutline | Feature::SheetLabel => GUIDE,
            Feature::PartLabel
            | Feature::WindowNumber
            | Feature::PanelLabel
            | Feature::Fiducial => MARK,
            _ => THROUGH,
        }
    }

    /// The features drawn inside this one's contour when it is an outer contour that frees a part or
    /// a panel: they must be cut (or marked) while it still holds, so before it (docs/cam.md §3).
    pub fn inside(self) -> &'static [Feature] {
        // `ALL` lists each outer contour with the features drawn inside it right after it.
        match self {
            Feature::PartOutline => &Feature::ALL[3..6],
            Feature::PanelOutline => &Feature::ALL[7..14],
            Feature::LinkageRelease => &Feature::ALL[15..16],
            _ => &[],
        }
    }

    /// Position in `ALL`, which lists the variants in declaration order (a unit test checks).
    fn index(self) -> usize {
        self as usize
    }
}

fn op_names(ops: &[Operation]) -> String {
    ops.iter()
        .map(|op| format!("\"{}\"", op.template_key()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The operation of every feature.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FeatureMap {
    ops: [Operation; Feature::ALL.len()],
}

impl Default for FeatureMap {
    fn default() -> Self {
        FeatureMap {
            ops: Feature::ALL.map(Feature::default_operation),
        }
    }
}

impl FeatureMap {
    /// The operation that draws `feature`.
    pub fn op(&self, feature: Feature) -> Operation {
        self.ops[feature.index()]
    }

    /// The optional `[features]` table of a template: `pzt-score-line = "score"`, … Features not named
    /// keep their default; an unknown key, an unknown operation or one the feature may not take is an
    /// error naming the file, the field, the value and what is allowed.
    pub fn read(path: &Path, root: &TableReader<'_>) -> Result<FeatureMap, InputError> {
        let mut map = FeatureMap::default();
        let Some(table) = root.optional_table("features")? else {
            return Ok(map);
        };
        for feature in Feature::ALL {
            let key = feature.key();
            let Some(name) = table.optional_string(key, "an operation name")? else {
                continue;
            };
            let field = table.path(key);
            let op = Operation::ALL
                .into_iter()
                .find(|op| op.template_key() == name)
                .ok_or_else(|| {
                    InputError::invalid(
                        path,
                        &field,
                        format!("{name:?}"),
                        format!("unknown operation; expected {}", op_names(&Operation::ALL)),
                    )
                })?;
            if !feature.allowed().contains(&op) {
                return Err(InputError::invalid(
                    path,
                    &field,
                    format!("{name:?}"),
                    format!(
                        "a {} may only be one of {}",
                        key.replace('-', " "),
                        op_names(feature.allowed())
                    ),
                ));
            }
            map.ops[feature.index()] = op;
        }
        table.finish()?;
        map.check_cut_order(path, &table)?;
        Ok(map)
    }

    /// Every outer contour runs no earlier than the features inside it: the operations run in their
    /// order (engrave, score, secondary, cut), so an outline on the second pass with a hole inside it
    /// on `cut` would free the part before its hole is cut.
    fn check_cut_order(&self, path: &Path, table: &TableReader<'_>) -> Result<(), InputError> {
        for outer in Feature::ALL {
            let late = outer
                .inside()
                .iter()
                .find(|inner| self.op(**inner) > self.op(outer));
            if let Some(inner) = late {
                return Err(InputError::invalid(
                    path,
                    &table.path(outer.key()),
                    format!("{:?}", self.op(outer).template_key()),
                    format!(
                        "the {} inside it is on {:?}, which runs after it and would cut a part \
                         already free; give the {} no later an operation than {:?} (in the order {})",
                        inner.key().replace('-', " "),
                        self.op(*inner).template_key(),
                        outer.key().replace('-', " "),
                        self.op(outer).template_key(),
                        op_names(&Operation::ALL)
                    ),
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<FeatureMap, InputError> {
        let table: toml::Table = text.parse().unwrap();
        FeatureMap::read(
            Path::new("t.toml"),
            &TableReader::new(Path::new("t.toml"), "", &table),
        )
    }

    #[test]
    fn defaults_allowed_and_keys_unique() {
        for f in Feature::ALL {
            assert!(f.allowed().contains(&f.default_operation()), "{f:?}");
            assert_eq!(Feature::ALL[f.index()], f);
        }
        let mut keys: Vec<_> = Feature::ALL.iter().map(|f| f.key()).collect();
        keys.sort();
        keys.dedup();
        assert_eq!(keys.len(), Feature::ALL.len());
        assert_eq!(read("").unwrap(), FeatureMap::default());
    }

    #[test]
    fn an_outline_never_runs_before_what_lies_inside_it() {
        assert_eq!(
            Feature::PartOutline.inside(),
            [Feature::Via, Feature::RegistrationHole, Feature::PartLabel]
        );
        assert_eq!(Feature::LinkageRelease.inside(), [Feature::LinkageHole]);
        let panel = Feature::PanelOutline.inside();
        assert!(panel.contains(&Feature::PinHole) && panel.contains(&Feature::LinkageCutOut));
        assert!(
            !panel.contains(&Feature::LinkageRelease) && !panel.contains(&Feature::PanelOutline)
        );
        // The defaults cut every inner feature on or before its outline's operation.
        let map = FeatureMap::default();
        for outer in Feature::ALL {
            for inner in outer.inside() {
                assert!(map.op(*inner) <= map.op(outer), "{outer:?} {inner:?}");
            }
        }
        // The second pass runs before `cut`: an outline on it with its via on `cut` frees the part first.
        let e = read("[features]\npart-outline = \"secondary\"").unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("features.part-outline")
                && text.contains("the via inside it is on \"cut\""),
            "{text}"
        );
        assert_eq!(text.trim().lines().count(), 1, "{text}");
        // Inner features on the second pass too, or marks engraved, keep the order.
        let ok = read(
            "[features]\npart-outline = \"secondary\"\nvia = \"secondary\"\n\
             registration-hole = \"secondary\"",
        )
        .unwrap();
        assert_eq!(ok.op(Feature::PartOutline), Operation::Secondary);
    }

    #[test]
    fn sheet_outline_is_a_reference_never_a_cut() {
        // A sheet outline on a cut operation (red, or the green second pass) would trace the sheet edge.
        assert_eq!(
            FeatureMap::default().op(Feature::PztSheetOutline),
            Operation::Reference
        );
        for op in ["cut", "secondary"] {
            let e = read(&format!("[features]\npzt-sheet-outline = \"{op}\"")).unwrap_err();
            assert_eq!(e.field, "features.pzt-sheet-outline");
        }
        // No through-cut feature may be given the never-run reference: the part would stay in.
        let e = read("[features]\npart-outline = \"reference\"").unwrap_err();
        assert!(e.expected.contains("\"cut\", \"secondary\""), "{e}");
    }

    #[test]
    fn remap_and_errors() {
        let m = read("[features]\npzt-score-line = \"cut\"").unwrap();
        assert_eq!(m.op(Feature::PztScoreLine), Operation::Cut);
        assert_eq!(m.op(Feature::PartOutline), Operation::Cut);
        let e = read("[features]\npzt-score-line = \"etch\"").unwrap_err();
        assert_eq!(e.field, "features.pzt-score-line");
        assert!(
            e.value.contains("etch") && e.expected.contains("\"engrave\""),
            "{e}"
        );
        let e = read("[features]\npart-outline = \"engrave\"").unwrap_err();
        assert!(e.expected.contains("\"cut\", \"secondary\""), "{e}");
        let e = read("[features]\nscore-lines = \"score\"").unwrap_err();
        assert_eq!(e.field, "features.score-lines");
        assert!(e.expected.contains("pzt-score-line"), "{e}");
    }
}
