//! Strip packing on instances in the JSON form of jagua-rs and sparrow (the ESICUP instances as
//! those projects distribute them): `cargo bench -p cam-nest --bench strip_instances`.
//!
//! Reads every `*.json` in the folder `NEST_STRIP_INSTANCES` names, else in `NEST_ESICUP_DIR` (a
//! folder holding the twelve public ESICUP instances as sparrow's repository distributes them in
//! `data/input`; they are not shipped here, their licences are not stated); without either, or if
//! the folder is missing, it says so and stops. `NEST_STRIP_INSTANCES=$PWD/crates/nest/benches/instances` runs the committed
//! instance. The form: `{"name", "strip_height", "items": [{"demand", "allowed_orientations",
//! "shape": {"type": "simple_polygon", "data": [[x, y], ...]}}]}`, where the strip runs along x
//! with the fixed height `strip_height`. Our strip runs along y with a fixed width, so every
//! outline is turned by -90° on reading, which keeps each part's orientation to the strip (and
//! an allowed angle stays allowed). `allowed_orientations` null (free rotation) becomes
//! 0/90/180/270°: the engine turns by listed angles only. Separation 0, as in the ESICUP
//! instances, 2 workers, seed 1 (`NEST_SEED` sets another).
//!
//! `NEST_TIME_S=30` gives each instance a 30 s time budget (the anytime search, iterations
//! unbounded unless `NEST_ITERATIONS` caps them); without it `NEST_ITERATIONS` iterations run
//! (the default budget if unset), which replays a timed run from the iterations it reached, or
//! runs a fixed amount of search whatever the machine's load. One line per instance: name,
//! parts, density (part area / (strip height x used length)), wall and CPU seconds, and the
//! iterations reached (`--iterations` replays a run whose time ran out in the anytime rounds).
//! The figures also go to `target/nest-bench/esicup-<budget>.json`, which
//! `tools/nest_reference.py --esicup` reads to run sparrow at the same budget beside them.
//!
//! The committed instance, `actuators-80.json`, is generated in that form from the fixtures
//! (seed 7201, used nowhere else) by `-- --write-example`. `-- --write-lab 9300 DIR` writes the
//! lab's measuring strips of seeds 9301-9308 in that form to `DIR` (absolute, as cargo runs the
//! bench in `crates/nest`), to run them at a time budget
//! beside sparrow as the ESICUP instances run.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use cam_nest::{nest_strip_until, verify, NestItem, NestSettings, SearchLimit};
use serde_json::{json, Value};

#[path = "../tests/fixtures/mod.rs"]
mod fixtures;

/// The instances' folder (see the module doc), if one is named.
fn instances_dir() -> Option<PathBuf> {
    std::env::var_os("NEST_STRIP_INSTANCES")
        .or_else(|| std::env::var_os("NEST_ESICUP_DIR"))
        .map(PathBuf::from)
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
    write_instance(dir, "actuators-80", &fixtures::random_designs(7201, 5, 16));
}

/// The lab's measuring strips of seeds `base + 1 ..= base + 8` (`fixtures::batches_from`) as
/// instances in `dir`, named `lab<base>-<batch>`, so that they run here at a time budget and
/// beside sparrow (`tools/nest_reference.py --esicup`) as the ESICUP instances do.
fn write_lab(base: u64, dir: &Path) {
    std::fs::create_dir_all(dir).expect("create the folder for the lab strips");
    for (name, items) in fixtures::batches_from(base) {
        write_instance(dir, &format!("lab{base}-{name}"), &items);
    }
}

/// `items` on a 150 mm strip, in the instances' JSON form, as `dir/<name>.json`.
fn write_instance(dir: &Path, name: &str, items: &[NestItem]) {
    let instance = json!({
        "name": name,
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
        dir.join(format!("{name}.json")),
        serde_json::to_string_pretty(&instance).expect("json") + "\n",
    )
    .expect("write the instance");
}

/// `NEST_TIME_S`, `NEST_SEED` (1 if unset) and `NEST_ITERATIONS` (see the module doc).
fn budget_from_env() -> (Option<f64>, u64, Option<usize>) {
    let time_s: Option<f64> = std::env::var("NEST_TIME_S").ok().map(|t| {
        t.parse()
            .ok()
            .filter(|t: &f64| t.is_finite() && *t > 0.0)
            .unwrap_or_else(|| panic!("NEST_TIME_S = {t:?}: a number of seconds above 0"))
    });
    let seed: u64 = std::env::var("NEST_SEED").ok().map_or(1, |s| {
        s.parse()
            .unwrap_or_else(|_| panic!("NEST_SEED = {s:?}: a whole number"))
    });
    let iterations: Option<usize> = std::env::var("NEST_ITERATIONS").ok().map(|n| {
        n.parse()
            .ok()
            .filter(|n: &usize| *n > 0)
            .unwrap_or_else(|| panic!("NEST_ITERATIONS = {n:?}: a whole number above 0"))
    });
    (time_s, seed, iterations)
}

fn main() {
    if std::env::args().any(|a| a == "--write-example") {
        write_example(&Path::new(env!("CARGO_MANIFEST_DIR")).join("benches/instances"));
        return;
    }
    let args: Vec<String> = std::env::args().collect();
    if let Some(at) = args.iter().position(|a| a == "--write-lab") {
        let base = args.get(at + 1).and_then(|b| b.parse().ok());
        let (Some(base), Some(dir)) = (base, args.get(at + 2)) else {
            panic!("--write-lab BASE DIR: a seed base (e.g. 9300) and a folder");
        };
        write_lab(base, Path::new(dir));
        return;
    }
    let Some(dir) = instances_dir() else {
        println!(
            "strip instances: set NEST_ESICUP_DIR (the ESICUP instances) or NEST_STRIP_INSTANCES; nothing to measure"
        );
        return;
    };
    let (time_s, seed, iterations) = budget_from_env();
    let settings = NestSettings {
        separation_mm: 0.0,
        seed,
        // A time budget runs the anytime search until its deadline, or until `NEST_ITERATIONS`
        // if that comes first (as `--iterations` caps `--time`).
        iterations: match (time_s, iterations) {
            (_, Some(n)) => n,
            (Some(_), None) => usize::MAX / 2,
            (None, None) => NestSettings::default().iterations,
        },
        ..NestSettings::default()
    };
    let Ok(entries) = std::fs::read_dir(&dir) else {
        println!(
            "strip instances: no folder {} (set NEST_ESICUP_DIR or NEST_STRIP_INSTANCES); nothing to measure",
            dir.display()
        );
        return;
    };
    let mut paths: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    paths.sort();
    // The budget as the header says it and as the figures' file is named: a capped time budget
    // is not the plain one, so its figures never stand in for a plain run's beside sparrow.
    let (budget, file_name) = match (time_s, iterations) {
        (Some(t), None) => (format!("{t} s each"), format!("esicup-{t}s.json")),
        (Some(t), Some(n)) => (
            format!("{t} s each, at most {n} iterations"),
            format!("esicup-{t}s-at-most-{n}-iterations.json"),
        ),
        (None, _) => (
            format!("{} iterations", settings.iterations),
            format!("esicup-{}-iterations.json", settings.iterations),
        ),
    };
    println!(
        "strip instances in {}: separation 0, {budget}, {} workers, seed {seed}",
        dir.display(),
        settings.workers
    );
    println!(
        "{:<16} {:>6} {:>10} {:>8} {:>8} {:>10}",
        "instance", "parts", "density %", "wall s", "CPU s", "iterations"
    );
    let mut rows = Vec::new();
    for path in paths {
        let text = std::fs::read_to_string(&path).expect("read instance");
        let (name, width, items) = match read_instance(&text) {
            Ok(instance) => instance,
            Err(e) => {
                println!("{}: {e}", path.display());
                continue;
            }
        };
        let (started, cpu_started) = (Instant::now(), fixtures::cpu_seconds());
        let limit = SearchLimit {
            deadline: time_s.map(|t| started + Duration::from_secs_f64(t)),
            interrupt: None,
        };
        let (strip, reached) =
            nest_strip_until(&items, width, &settings, &limit, &|_| {}).expect("nest");
        let (seconds, cpu) = (
            started.elapsed().as_secs_f64(),
            fixtures::cpu_seconds() - cpu_started,
        );
        verify(&items, &strip.bin, &settings, &strip.solution, 1e-6).expect("layout verifies");
        let parts: usize = items.iter().map(|i| i.demand).sum();
        let iterations = if reached.replayable {
            reached.iterations.to_string()
        } else {
            "base cut".into()
        };
        println!(
            "{name:<16} {parts:>6} {:>10.2} {seconds:>8.2} {cpu:>8.2} {iterations:>10}",
            strip.density * 100.0
        );
        rows.push(json!({
            "name": name,
            "instance": path.canonicalize().unwrap_or(path),
            "parts": parts,
            "density": strip.density,
            "wall_s": seconds,
            "cpu_s": cpu,
            "iterations": reached.replayable.then_some(reached.iterations),
            "time_budget_s": time_s,
        }));
    }
    let out = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/nest-bench");
    let file = out.join(file_name);
    std::fs::create_dir_all(&out).expect("create target/nest-bench");
    std::fs::write(
        &file,
        serde_json::to_string_pretty(&rows).expect("json") + "\n",
    )
    .expect("write the figures");
    println!("written {}", file.display());
}
