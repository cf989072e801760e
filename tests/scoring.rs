//! Score lines run past the sheet edge by the template's overrun (docs/cam.md §4), and only there.

use crate::common;
use common::*;

/// The ends of every score line (blue path) of an SVG, in page coordinates, and the page width.
fn score_ends(svg: &str) -> (Vec<[f64; 2]>, f64) {
    let page = svg.split("viewBox=\"0 0 ").nth(1).unwrap();
    let width: f64 = page.split(' ').next().unwrap().parse().unwrap();
    let mut ends = Vec::new();
    for line in svg.lines().filter(|l| l.contains("stroke=\"#0000FF\"")) {
        let d = line
            .split("d=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap();
        let numbers: Vec<f64> = d
            .split(['M', 'L', ' '])
            .filter(|t| !t.is_empty())
            .map(|t| t.parse().unwrap())
            .collect();
        assert_eq!(numbers.len(), 4, "a score line is one segment: {d}");
        ends.push([numbers[0], numbers[1]]);
        ends.push([numbers[2], numbers[3]]);
    }
    (ends, width)
}

/// How far `p` lies outside the square sheet of side `side` drawn at `margin` on the page (0 inside).
fn outside(p: [f64; 2], margin: f64, side: f64) -> f64 {
    let d = |v: f64| (margin - v).max(v - margin - side).max(0.0);
    d(p[0]).max(d(p[1]))
}

#[test]
fn score_lines_overrun_the_sheet_edge_by_the_template_value() {
    let sheet_mm = 72.4;
    for (overrun, template) in [(0.5, None), (0.0, Some("0.0")), (1.2, Some("1.2"))] {
        let dir = tempfile::tempdir().unwrap();
        let design = match template {
            None => "examples/thesis-C.toml".to_string(),
            Some(value) => {
                let t = std::fs::read_to_string("templates/method-2.toml")
                    .unwrap()
                    .replace(
                        "score_overrun_mm = 0.5",
                        &format!("score_overrun_mm = {value}"),
                    );
                let tpl = dir.path().join("tpl.toml");
                std::fs::write(&tpl, t).unwrap();
                let d = design_c_with(&[("process", "process = \"tpl.toml\"")]);
                let path = dir.path().join("c.toml");
                std::fs::write(&path, d).unwrap();
                path.to_string_lossy().to_string()
            }
        };
        let out = dir.path().join("out");
        let o = cut_sheet(&design, &out, &[]);
        assert!(o.status.success(), "{}", stderr(&o));
        let svg = std::fs::read_to_string(layer_file(&out, "pzt-1.svg")).unwrap();
        let (ends, page) = score_ends(&svg);
        let margin = (page - sheet_mm) / 2.0;
        let beyond: Vec<f64> = ends
            .iter()
            .map(|&p| outside(p, margin, sheet_mm))
            .filter(|&d| d > 1e-6)
            .collect();
        if overrun == 0.0 {
            assert!(beyond.is_empty(), "no overrun asked: {beyond:?}");
            continue;
        }
        // The full-width strip lines end on both edges: their ends lie exactly the overrun outside.
        assert!(beyond.len() >= 2, "{overrun}: {beyond:?}");
        for d in &beyond {
            assert!(
                *d <= overrun + 1e-6,
                "{overrun}: an end {d} mm past the edge"
            );
        }
        assert!(
            beyond.iter().any(|d| (d - overrun).abs() < 1e-6),
            "{overrun}: {beyond:?}"
        );
    }
}
