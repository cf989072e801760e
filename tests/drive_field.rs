//! `drive` under a model whose stiffness and blocked force per field depend on the field (the nonlinear
//! ceramic, docs/physics.md §18.5): the actuator is predicted at the field its operating point asks for,
//! a field that does not settle leaves no operating point, and the linkage stays the one sized at the
//! design's own field.

use crate::common;

use actuator_cam::DriveSpec;
use common::{drive_design, insect_linkage_by_stiffness};

#[test]
fn the_nonlinear_drive_predicts_the_actuator_at_its_operating_field() {
    // docs/physics.md §18.5: the nonlinear ceramic's stiffness and force per field change with the
    // field, so the drive predicts the actuator at the field its operating point needs.
    use actuator_model::model::{ModelChoice, ModelKind};
    // The insect-scale example's published actuator at ±15°, reached below the design's own field
    // (the biased signal's limit, 327 V/mm), so the two actuators differ.
    let (_dir, path) = insect_linkage_by_stiffness(155, 15, None);
    let spec = DriveSpec::load(&path).unwrap();
    let design = drive_design(&spec);
    let model = ModelChoice::Kind(ModelKind::Nonlinear);
    let a = actuator_cam::analyse_drive(&spec, &design, &model).unwrap();
    let r = &a.report;
    assert_eq!(r.model, "nonlinear");
    assert_eq!(r.unsettled_field, None);
    let field = a.operating_field.unwrap();
    // The report's field is the search's, in V/mm.
    assert!((r.operating.as_ref().unwrap().field_V_per_mm * 1e3 / field - 1.0).abs() < 1e-3);
    let at = |e: f64| {
        let mut d = design.clone();
        d.drive.field = e;
        actuator_cam::Prediction::with_model(&d, &model).unwrap()
    };
    let settled = at(field);
    assert!((r.actuator.stiffness_N_per_m / settled.stiffness_N_per_m - 1.0).abs() < 1e-3);
    // At the design's own field the actuator is another one: the settling is not vacuous.
    let own = at(design.drive.field);
    assert!((own.stiffness_N_per_m / settled.stiffness_N_per_m - 1.0).abs() > 0.01);
    // A field that does not settle leaves no operating point in the report or its JSON.
    let mut unsettled = a.clone();
    unsettled.refuse_operating_point("does not settle".into());
    let r = &unsettled.report;
    assert!(r.operating.is_none() && unsettled.state.is_none() && !r.reached);
    let json = serde_json::to_value(r).unwrap();
    assert!(json.get("operating").is_none_or(|o| o.is_null()), "{json}");
    assert_eq!(json["unsettled_field"], "does not settle");
}

/// A linkage solved for the stroke with no `travel_mm` takes the actuator's free deflection for its
/// travel (docs/physics.md §12.3: the crank `L3 = 2 travel / (g(θ+) - g(θ-))`), at the design's own
/// field: a field-dependent model's search (§18.5) moves the actuator, not the linkage it flaps through.
#[test]
fn a_solved_linkage_without_a_travel_takes_the_free_deflection_at_the_designs_field() {
    use actuator_cam::LinkageSpec;
    use actuator_model::model::{ModelChoice, ModelKind};
    use actuator_model::transmission::Linkage;
    let (_dir, path) = insect_linkage_by_stiffness(155, 15, None);
    let spec = DriveSpec::load(&path).unwrap();
    let LinkageSpec::Solve {
        angle_minus,
        angle_plus,
        coupler_ratio,
        travel: None,
    } = spec.transmission.linkage
    else {
        panic!("{:?}", spec.transmission.linkage);
    };
    let design = drive_design(&spec);
    let model = ModelChoice::Kind(ModelKind::Nonlinear);
    let crank_mm = |field: f64| {
        let mut d = design.clone();
        d.drive.field = field;
        let p = actuator_cam::Prediction::with_model(&d, &model).unwrap();
        let l = Linkage::solve(
            p.free_deflection_mm * 1e-3,
            angle_minus,
            angle_plus,
            coupler_ratio,
        );
        l.unwrap().crank * 1e3
    };
    let a = actuator_cam::analyse_drive(&spec, &design, &model).unwrap();
    assert_eq!(a.report.unsettled_field, None);
    let own = crank_mm(design.drive.field);
    let crank = a.report.linkage.crank_mm;
    assert!((crank / own - 1.0).abs() < 1e-9, "{crank} mm vs {own} mm");
    assert!((a.report.linkage.coupler_mm / (coupler_ratio * own) - 1.0).abs() < 1e-9);
    // At the operating field the free deflection is another: the crank is not that field's.
    let operating = crank_mm(a.operating_field.unwrap());
    assert!((operating / own - 1.0).abs() > 0.01, "{operating} vs {own}");
}
