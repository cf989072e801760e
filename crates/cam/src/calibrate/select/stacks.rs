//! The distinct stacks of a data set: rows with the same materials, thicknesses, layup, drive mode and
//! field (and both with or both without an extension) have the same [`StackSection`] under any model, so
//! an evaluation that needs the stacks solved again solves each distinct one once, not once per actuator.
//! A lab's data set has a few stacks over many planforms, so this turns the cost of a stack effect from
//! the actuators' count to the stacks' (docs/benchmarks.md, "calibrate").

use crate::calibrate::csv::{Dataset, Measurement};
use actuator_model::effects::{PlanformTerms, StackBasis, StackSection};
use actuator_model::EffectModel;
use std::collections::HashMap;

/// Which distinct stack each row has, and a row of each.
#[derive(Debug, Clone, Default)]
pub(crate) struct Stacks {
    /// Per row, its stack.
    of_row: Vec<usize>,
    /// Per stack, the first row that has it.
    first_row: Vec<usize>,
    /// Per row, its planform's terms of the basis (an integral each, computed once).
    terms: Vec<PlanformTerms>,
    /// Per row, its design: the rows of one design (the same stack at any field, the same planform) give
    /// the same deflection and force per unit field under every model.
    design_of_row: Vec<usize>,
}

/// The numbers that decide a row's stack section, compared bit for bit (the materials beside them).
type Key = (u64, u64, Vec<u64>, u8, u64, bool);

fn key(r: &Measurement) -> Key {
    let a = r.actuator();
    (
        a.pzt_thickness.to_bits(),
        a.ply_thickness.to_bits(),
        a.layup_deg.iter().map(|x| x.to_bits()).collect(),
        a.drive.mode as u8,
        a.drive.field.to_bits(),
        a.planform.extension_ratio > 0.0,
    )
}

/// A row's [`Key`] at no field, with its planform's numbers: what decides its design.
fn design_key(r: &Measurement) -> (Key, [u64; 5]) {
    let pl = &r.planform;
    let (t_p, t_ply, layup, mode, _, extension) = key(r);
    (
        (t_p, t_ply, layup, mode, 0, extension),
        [
            pl.length,
            pl.extension_ratio,
            pl.base_width,
            pl.width_ratio,
            pl.base_tab,
        ]
        .map(f64::to_bits),
    )
}

/// Per row, the index of its class under `key` (rows with equal keys and materials share one), and the
/// first row of each class.
fn classes<K: std::hash::Hash + Eq>(
    data: &Dataset,
    key: impl Fn(&Measurement) -> K,
) -> (Vec<usize>, Vec<usize>) {
    let mut by_key: HashMap<K, Vec<usize>> = HashMap::new();
    let mut first_row: Vec<usize> = Vec::new();
    let of_row = data
        .rows
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let same = by_key.entry(key(r)).or_default();
            // Same numbers: the same class if the materials agree too.
            let found = same.iter().copied().find(|&s| {
                let first = &data.rows[first_row[s]];
                first.pzt == r.pzt && first.ply == r.ply
            });
            found.unwrap_or_else(|| {
                first_row.push(i);
                same.push(first_row.len() - 1);
                first_row.len() - 1
            })
        })
        .collect();
    (of_row, first_row)
}

impl Stacks {
    /// Index the rows of `data`.
    pub(crate) fn new(data: &Dataset) -> Stacks {
        let (of_row, first_row) = classes(data, key);
        let terms = data
            .rows
            .iter()
            .map(|r| PlanformTerms::of(&r.planform))
            .collect();
        Stacks {
            of_row,
            first_row,
            terms,
            design_of_row: classes(data, design_key).0,
        }
    }

    /// The design of row `row` ([`Stacks::design_of_row`]).
    pub(crate) fn design(&self, row: usize) -> usize {
        self.design_of_row[row]
    }

    /// Number of distinct stacks.
    pub(crate) fn len(&self) -> usize {
        self.first_row.len()
    }

    /// An empty set of solved stacks for one model.
    pub(crate) fn solver<'a>(&'a self, data: &'a Dataset, model: &'a EffectModel) -> Solver<'a> {
        Solver {
            stacks: self,
            data,
            model,
            solved: Vec::new(),
        }
    }
}

/// The stacks of a data set solved under one model as rows ask for them.
pub(crate) struct Solver<'a> {
    stacks: &'a Stacks,
    data: &'a Dataset,
    model: &'a EffectModel,
    /// Per stack: not yet solved (None), or its section (None inside where the model cannot evaluate it).
    /// Empty until a row asks: an evaluation that needs no stack solved allocates nothing.
    solved: Vec<Option<Option<StackSection>>>,
}

impl Solver<'_> {
    /// The stack basis of `row` under the model, as `EffectModel::basis` gives it (None where the model
    /// cannot evaluate it).
    pub(crate) fn basis(&mut self, row: usize) -> Option<StackBasis> {
        let s = self.stacks.of_row[row];
        let (data, model) = (self.data, self.model);
        let first = self.stacks.first_row[s];
        if self.solved.is_empty() {
            self.solved = vec![None; self.stacks.len()];
        }
        let section = *self.solved[s]
            .get_or_insert_with(|| model.stack_section(&data.rows[first].actuator()).ok());
        let terms = &self.stacks.terms[row];
        section.and_then(|x| x.basis_with(&data.rows[row].planform, terms).ok())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calibrate::csv::parse;

    #[test]
    fn rows_share_a_stack_only_when_every_stack_input_agrees_and_give_the_basis_of_their_own() {
        // Rows 0, 1 and 4 share a stack at 150 V (different planforms); row 2 has another voltage, row 3
        // another layup, row 5 an extension where row 0 has none.
        let data = parse(
            "id,l_tot_mm,l_r,w0_mm,w_r,t_p_mm,layup,voltage_V,mass_mg,free_deflection_mm,blocked_force_N\n\
             a,30,0,8,1.2,0.191,0/90/0,150,60,0.3,0.05\n\
             b,40,0,6,0.8,0.191,0/90/0,150,60,0.3,0.05\n\
             b,40,0,6,0.8,0.191,0/90/0,100,60,0.2,0.03\n\
             c,30,0,8,1.2,0.191,0/0/90/0/0,150,60,0.3,0.05\n\
             d,25,0,9,1.5,0.191,0/90/0,150,60,0.3,0.05\n\
             e,30,0.5,8,1.2,0.191,0/90/0,150,60,0.3,0.05\n",
        )
        .expect("valid rows");
        let stacks = Stacks::new(&data);
        assert_eq!(stacks.of_row, vec![0, 0, 1, 2, 0, 3]);
        let mut model = EffectModel::default();
        model.effects.bond_thickness = 20e-6;
        model.effects.ply_thickness_scale = 1.1;
        let mut solver = stacks.solver(&data, &model);
        for row in [4, 0, 5, 2, 1, 3] {
            let want = model
                .basis(&data.rows[row].actuator())
                .expect("a physical stack");
            assert_eq!(solver.basis(row), Some(want), "row {row}");
        }
    }
}
