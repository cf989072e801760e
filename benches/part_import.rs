//! `cargo bench --bench part_import`: time of `parts::import` (read, flatten, the simple-ring and
//! crossing checks, nesting contours into parts) on one closed contour of 10,000 and 50,000
//! vertices, drawn as a DXF LWPOLYLINE and as an SVG path: a wavy ring, so that every vertex is a
//! corner the checks must look at. Prints the median and the slowest of 5 runs per drawing, and the
//! machine's load.

use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// `n` vertices on a circle of radius 50 mm whose radius wobbles by 1 mm, 7 waves round: a simple
/// ring with no three consecutive vertices on one line.
fn wavy_ring(n: usize) -> Vec<[f64; 2]> {
    (0..n)
        .map(|i| {
            let a = 2.0 * PI * i as f64 / n as f64;
            let r = 50.0 + (7.0 * a).sin();
            [60.0 + r * a.cos(), 60.0 + r * a.sin()]
        })
        .collect()
}

fn dxf(ring: &[[f64; 2]]) -> String {
    let mut text = String::from(
        "  0\nSECTION\n  2\nHEADER\n  9\n$ACADVER\n  1\nAC1015\n  9\n$INSUNITS\n 70\n4\n  0\nENDSEC\n  0\nSECTION\n  2\nENTITIES\n",
    );
    let _ = write!(
        text,
        "  0\nLWPOLYLINE\n  5\n2F\n100\nAcDbEntity\n  8\nPARTS\n100\nAcDbPolyline\n 90\n{}\n 70\n1\n",
        ring.len()
    );
    for [x, y] in ring {
        let _ = write!(text, " 10\n{x}\n 20\n{y}\n");
    }
    text + "  0\nENDSEC\n  0\nEOF\n"
}

fn svg(ring: &[[f64; 2]]) -> String {
    let mut d = String::new();
    for (i, [x, y]) in ring.iter().enumerate() {
        let _ = write!(d, "{}{x} {y} ", if i == 0 { "M" } else { "L" });
    }
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"120mm\" height=\"120mm\" viewBox=\"0 0 120 120\"><path id=\"ring\" d=\"{d}Z\"/></svg>"
    )
}

fn time(path: &Path) -> (f64, f64) {
    let mut times = Vec::new();
    for _ in 0..5 {
        let start = Instant::now();
        let parts = actuator_cam::import_parts(path).expect("the ring imports");
        assert_eq!(parts.len(), 1);
        std::hint::black_box(parts);
        times.push(start.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    (times[times.len() / 2], times[times.len() - 1])
}

fn main() {
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "part import, one closed contour (5 runs); /proc/loadavg {}",
        load.trim()
    );
    // Other sizes on the command line (`-- 2000 4000`), to see how the time grows.
    let sizes: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let sizes = if sizes.is_empty() {
        vec![10_000, 50_000]
    } else {
        sizes
    };
    let dir = tempfile::tempdir().expect("a scratch folder");
    for n in sizes {
        let ring = wavy_ring(n);
        for (kind, text) in [("DXF LWPOLYLINE", dxf(&ring)), ("SVG path", svg(&ring))] {
            let ext = if kind.starts_with("DXF") {
                "dxf"
            } else {
                "svg"
            };
            let path = dir.path().join(format!("ring-{n}.{ext}"));
            std::fs::write(&path, text).expect("the drawing is written");
            let (median, slowest) = time(&path);
            println!("{kind}, {n} vertices: median {median:.1} ms, slowest {slowest:.1} ms");
        }
    }
}
