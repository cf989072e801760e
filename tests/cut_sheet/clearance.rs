//! What must not touch a cut part: labels in bonded zones, and anything that is never run.

use super::*;

#[test]
fn no_label_lies_in_a_bonded_zone_for_any_example_by_either_method() {
    for example in EXAMPLES {
        for method in ["method-1", "method-2"] {
            let (labels, crossing) = labels_on_bonded_zones(example, method);
            assert_eq!(
                crossing, 0,
                "{example} by {method}: {crossing} of {labels} label strokes lie in a bonded zone"
            );
            // Designs 1 and 7 have extensions wide enough for a label: they keep theirs.
            if example == "thesis-1.toml" || example == "thesis-7.toml" {
                assert!(labels > 0, "{example} by {method}: labels lost");
            }
        }
    }
}

#[test]
fn nothing_that_is_never_run_crosses_a_cut_part() {
    // LightBurn ignores layer locks and no-plot flags: a REFERENCE-layer shape left on is cut, so a
    // bonded-zone outline across a passive part's extension would cut each actuator in two. A never-run
    // shape may surround parts (the PZT sheet edge) but no point of it lies inside a cut part.
    for example in EXAMPLES {
        for method in ["method-1", "method-2"] {
            let path = Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("examples")
                .join(example);
            let template = Template::resolve(method, &path).unwrap();
            let design = design_for_process(&Design::load(&path).unwrap(), &template).unwrap();
            let names = Names {
                title: design.name.clone(),
                file: example.into(),
                name_designs: false,
            };
            let built =
                build_layers(&[(&design, 2)], &[], &template, &names, &Packing::Shelf).unwrap();
            let mut guides = 0;
            for d in &built.drawings {
                guides += d.drawing.guides().len();
                let parts: Vec<Polygon<f64>> = d
                    .drawing
                    .shapes_of(Operation::Cut)
                    .filter_map(|s| match s {
                        Shape::Polygon(r) => Some(polygon(r)),
                        _ => None,
                    })
                    .collect();
                for never_run in d.drawing.shapes_of(Operation::Reference) {
                    for q in path_points(never_run) {
                        let p = geo::Point::new(q[0], q[1]);
                        for part in &parts {
                            let inside = part.intersects(&p)
                                && Euclidean.distance(&p, part.exterior()) > 1e-6;
                            assert!(
                                !inside,
                                "{example} by {method}, {}: a never-run line at {q:?} crosses a cut part",
                                d.stem
                            );
                        }
                    }
                }
            }
            // The bonded zones are still in the files, as data: one per labelled part.
            let labelled = labels_on_bonded_zones(example, method).0 > 0;
            assert!(
                !labelled || guides > 0,
                "{example} by {method}: no bonded-zone guide"
            );
        }
    }
}
