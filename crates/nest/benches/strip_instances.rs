//! Strip packing on instances in the JSON form of jagua-rs and sparrow (the ESICUP instances as
//! those projects distribute them): `cargo bench -p cam-nest --bench strip_instances`.
//!
//! Reads every `*.json` in `benches/instances/` (or in the folder `NEST_STRIP_INSTANCES` names):
//! `{"name", "strip_height", "items": [{"demand", "allowed_orientations", "shape": {"type":
//! "simple_polygon", "data": [[x, y], ...]}}]}`, where the strip runs along x with the fixed
//! height `strip_height`. Our strip runs along y with a fixed width, so every outline is turned
//! by -90° on reading, which keeps each part's orientation to the strip (and an allowed angle
//! stays allowed). `allowed_orientations` null (free rotation) becomes 0/90/180/270°: the
//! engine turns by listed angles only. Separation 0, as in the ESICUP instances. Prints density
//! (part area / (strip height x used length)) and wall time with the default settings.
//!
//! The committed instance, `actuators-80.json`, is generated in that form from the fixtures
//! (seed 7201, used nowhere else) by `-- --write-example`; the public ESICUP instances are not
//! shipped here (their licences are not stated), but any of them in this form can be dropped in.

use std::path::{Path, PathBuf};
use std::time::Instant;

use cam_nest::{nest_strip, verify, NestItem, NestSettings};
use serde_json::{json, Value};

#[path = "../tests/fixtures/mod.rs"]
mod fixtures;

fn instances_dir() -> PathBuf {
    std::env::var_os("NEST_STRIP_INSTANCES").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("benches/instances"),
        PathBuf::from,
    )
}

/// Our items and strip width from an instance, or why it cannot be read.
fn read_instance(text: &str) -> Result<(String, f64, Vec<NestItem>), String> {
    let v: Value = serde_json::from_str(text).map_err(|e| e.to_string())?;
    let name = v["name"].as_str().unwrap_or("?").to_string();
    let width = v["strip_height"]
        .as_f64()
        .ok_or("strip_height: missing or not a number")?;
    let items = v["items"]
        .as_array()
        .ok_or("items: missing or not a list")?
        .iter()
        .enumerate()
        .map(|(i, item)| {
            let shape = &item["shape"];
            let data = match shape["type"].as_str() {
                Some("simple_polygon") => &shape["data"],
                Some("polygon") => &shape["data"]["outer"],
                other => return Err(format!("items[{i}].shape.type: {other:?} is not supported")),
            };
            let outline = data
                .as_array()
                .ok_or(format!("items[{i}].shape.data: not a list of points"))?
                .iter()
                .map(|p| match (p[0].as_f64(), p[1].as_f64()) {
                    // Their (x along the strip, y across) is our (x across, y along).
                    (Some(x), Some(y)) => Ok([y, -x]),
                    _ => Err(format!("items[{i}].shape.data: {p} is not a point")),
                })
                .collect::<Result<Vec<_>, _>>()?;
            let rotations_deg = match &item["allowed_orientations"] {
                Value::Array(a) => a.iter().filter_map(Value::as_f64).collect(),
                _ => vec![0.0, 90.0, 180.0, 270.0],
            };
            Ok(NestItem {
                outline,
                demand: item["demand"].as_u64().unwrap_or(1) as usize,
                rotations_deg,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    Ok((name, width, items))
}

/// The committed example: an actuator batch in the instance form (our outlines turned by +90°,
/// the inverse of reading).
fn write_example(dir: &Path) {
    let items = fixtures::random_designs(7201, 5, 16);
    let instance = json!({
        "name": "actuators-80",
        "strip_height": 150.0,
        "items": items.iter().enumerate().map(|(id, item)| json!({
            "id": id,
            "demand": item.demand,
            "allowed_orientations": item.rotations_deg,
            "shape": {
                "type": "simple_polygon",
                "data": item.outline.iter().map(|p| [-p[1], p[0]]).collect::<Vec<_>>(),
            },
        })).collect::<Vec<_>>(),
    });
    std::fs::write(
        dir.join("actuators-80.json"),
        serde_json::to_string_pretty(&instance).expect("json") + "\n",
    )
    .expect("write the example instance");
}

fn main() {
    let dir = instances_dir();
    if std::env::args().any(|a| a == "--write-example") {
        write_example(&dir);
        return;
    }
    let settings = NestSettings {
        separation_mm: 0.0,
        seed: 1,
        ..NestSettings::default()
    };
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    paths.sort();
    println!(
        "strip instances in {}: separation 0, {} iterations, {} workers, seed 1",
        dir.display(),
        settings.iterations,
        settings.workers
    );
    println!(
        "{:<16} {:>6} {:>9} {:>10} {:>8}",
        "instance", "parts", "width", "density %", "wall s"
    );
    for path in paths {
        let text = std::fs::read_to_string(&path).expect("read instance");
        let (name, width, items) = match read_instance(&text) {
            Ok(instance) => instance,
            Err(e) => {
                println!("{}: {e}", path.display());
                continue;
            }
        };
        let started = Instant::now();
        let strip = nest_strip(&items, width, &settings, &|_| {}).expect("nest");
        let seconds = started.elapsed().as_secs_f64();
        verify(&items, &strip.bin, &settings, &strip.solution, 1e-6).expect("layout verifies");
        let parts: usize = items.iter().map(|i| i.demand).sum();
        println!(
            "{name:<16} {parts:>6} {width:>9.1} {:>10.2} {seconds:>8.2}",
            strip.density * 100.0
        );
    }
}
