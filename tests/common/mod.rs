//! Helpers shared by the integration tests: run the built binary, read what it printed, write scratch
//! files. Inputs the benches use as well live in `fixtures.rs`.
#![allow(dead_code)]

mod fixtures;
pub mod svg_read;
pub use fixtures::*;

use geo::{LineString, Polygon};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The built `actuator-cam`, to run from the crate root (so `examples/…` paths resolve); for runs that
/// need more than arguments, such as an environment variable.
pub fn bin() -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_actuator-cam"));
    cmd.current_dir(env!("CARGO_MANIFEST_DIR"));
    cmd
}

/// Run the built `actuator-cam` with arguments, from the crate root.
pub fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("the binary runs")
}

/// Run the built `actuator-cam` and require success; standard error goes into the failure message.
pub fn run_ok(args: &[&str]) -> Output {
    let o = run(args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    o
}

/// stdout as text.
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// stderr as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// stdout as text of a run that must have succeeded; standard error goes into the failure message.
pub fn ok_stdout(o: &Output) -> String {
    assert!(o.status.success(), "{}", stderr(o));
    stdout(o)
}

/// `actuator-cam cut-sheet DESIGN -o OUT EXTRA…`, from the crate root.
pub fn cut_sheet(design: &str, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["cut-sheet", design, "-o", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    run(&args)
}

/// The shipped linkage example cut into `out` (`robobee-jafferis2016-derated.toml` with the drive
/// that sizes its flexure linkage), which must succeed.
pub fn cut_linkage_example(out: &Path) {
    let o = cut_sheet(
        "examples/robobee-jafferis2016-derated.toml",
        out,
        &[
            "--drive",
            "examples/drive-robobee-jafferis2016-linkage.toml",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
}

/// `actuator-cam nest BATCH -o OUT --iterations N` (from the crate root), which must succeed; its
/// `nest-report.json`.
pub fn nest_ok(batch: &str, out: &Path, iterations: &str) -> serde_json::Value {
    let o = run(&[
        "nest",
        batch,
        "-o",
        out.to_str().unwrap(),
        "--iterations",
        iterations,
    ]);
    assert!(o.status.success(), "{batch}: {}", stderr(&o));
    nest_report_json(out)
}

/// The `nest-report.json` a nest wrote into `out`.
pub fn nest_report_json(out: &Path) -> serde_json::Value {
    let path = out.join("nest-report.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{path:?}: {e}"))
}

/// The `report.json` a command wrote into `out`.
pub fn report_json(out: &Path) -> serde_json::Value {
    let path = out.join("report.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{path:?}: {e}"))
}

/// stderr of a run that must have been refused with one line (the project's rule for bad input); the
/// caller checks what the line names.
pub fn refused_in_one_line(o: &Output) -> String {
    let err = stderr(o);
    assert!(!o.status.success(), "accepted: {}", stdout(o));
    assert_eq!(err.trim().lines().count(), 1, "one line: {err}");
    err
}

/// The staging folders of the output writer left in `dir` (what a failed or killed run could leave).
pub fn staging_left(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(actuator_cam::STAGING_PREFIX))
        .collect()
}

/// A valid design (thesis design C) as TOML text with one line replaced: `(key prefix, new line)`.
pub fn design_c_with(replace: &[(&str, &str)]) -> String {
    let base = std::fs::read_to_string(example("thesis-C.toml")).unwrap();
    base.lines()
        .map(|line| {
            replace
                .iter()
                .find(|(key, _)| line.starts_with(key))
                .map(|(_, new)| new.to_string())
                .unwrap_or_else(|| line.to_string())
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

/// Write text into a fresh file in a temp dir; returns the dir guard and the path.
pub fn write_temp(name: &str, text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

/// Every file of an output directory, by name.
pub fn files(out: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut m = BTreeMap::new();
    for e in std::fs::read_dir(out).unwrap() {
        let e = e.unwrap();
        m.insert(
            e.file_name().to_string_lossy().into_owned(),
            std::fs::read(e.path()).unwrap(),
        );
    }
    m
}

/// Shoelace area of a ring, mm².
pub fn area(ring: &[[f64; 2]]) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|i| ring[i][0] * ring[(i + 1) % n][1] - ring[(i + 1) % n][0] * ring[i][1])
        .sum::<f64>()
        .abs()
        / 2.0
}

/// A ring as a `geo` polygon.
pub fn polygon(ring: &[[f64; 2]]) -> Polygon<f64> {
    Polygon::new(
        LineString::from(ring.iter().map(|p| (p[0], p[1])).collect::<Vec<_>>()),
        vec![],
    )
}

/// A design file (the format of examples/thesis-B.toml) for one measured row.
pub fn design_of(m: &actuator_cam::Measurement) -> String {
    format!(
        "name = \"row\"\n[geometry]\nlength_mm = {}\nextension_ratio = {}\nbase_width_mm = {}\nwidth_ratio = {}\nbase_tab_mm = 0.0\n\
         [laminate]\npzt = \"PZT-5H\"\npzt_thickness_mm = {}\nply = \"CF-thesis\"\nlayup_deg = {:?}\n\
         [drive]\nmode = \"parallel\"\nfield_V_per_mm = {}\n",
        m.planform.length * 1e3,
        m.planform.extension_ratio,
        m.planform.base_width * 1e3,
        m.planform.width_ratio,
        m.pzt_thickness * 1e3,
        m.layup_deg,
        m.field * 1e-3
    )
}

/// The sheet a layer file is of, without the stock its name carries:
/// `mold-4-1_ptfe-non-porous-0.05mm.svg` → `mold-4-1.svg`; other names unchanged.
pub fn sheet_name(file: &str) -> String {
    match (file.split_once('_'), file.rsplit_once('.')) {
        (Some((stem, _)), Some((_, ext))) => format!("{stem}.{ext}"),
        _ => file.to_string(),
    }
}

/// Every file of an output directory, by sheet name ([`sheet_name`]).
pub fn sheet_files(out: &Path) -> BTreeMap<String, Vec<u8>> {
    files(out)
        .into_iter()
        .map(|(name, bytes)| (sheet_name(&name), bytes))
        .collect()
}

/// The path of the layer file of sheet `name` (`pzt-1.svg`) in `out`, whatever stock its name carries.
pub fn layer_file(out: &Path, name: &str) -> PathBuf {
    let found: Vec<PathBuf> = std::fs::read_dir(out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| sheet_name(&p.file_name().unwrap().to_string_lossy()) == name)
        .collect();
    assert_eq!(found.len(), 1, "{name} in {}: {found:?}", out.display());
    found.into_iter().next().unwrap()
}

/// `drive`'s analysis of a drive file in memory, its design built for its process, under the original
/// model (as `actuator-cam drive` runs it by default).
pub fn drive_analysis(path: &Path) -> actuator_cam::Analysis {
    let model =
        actuator_model::model::ModelChoice::Kind(actuator_model::model::ModelKind::Original);
    let spec = actuator_cam::DriveSpec::load(path).unwrap();
    actuator_cam::analyse_drive(&spec, &drive_design(&spec), &model).unwrap()
}

/// The design a drive file names, built for its process, as `drive` builds it.
pub fn drive_design(spec: &actuator_cam::DriveSpec) -> actuator_cam::Design {
    let design = actuator_cam::Design::load(&spec.design).unwrap();
    let template = actuator_cam::Template::resolve(&design.process, &design.source).unwrap();
    actuator_cam::design_for_process(&design, &template).unwrap()
}

/// A folder with the example drive file `name` and its design, the design's PZT-5H replaced by a user
/// material equal to it but for its depolarization field, raised to PZT-5H's coercive field (800 V/mm,
/// thesis Table 2.1). The examples drive their plates in parallel at 750-800 V/mm, past the library's
/// 300 V/mm depolarization field; with the limit at the coercive field the required stroke is within
/// every limit, so a test can study the physics there (docs/physics.md §2.1). Returns the folder and the
/// drive file's path in it (same file name).
pub fn coercive_copy(name: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let drive = std::fs::read_to_string(example_path(name)).unwrap();
    let design = drive
        .lines()
        .find_map(|l| l.strip_prefix("design = \""))
        .and_then(|l| l.strip_suffix('"'))
        .unwrap()
        .to_string();
    let text = std::fs::read_to_string(example_path(&design)).unwrap();
    assert!(text.contains("pzt = \"PZT-5H\""), "{design}");
    let text = text.replace("pzt = \"PZT-5H\"", "pzt = \"PZT-5H-coercive\"")
        + "\n[materials.PZT-5H-coercive]\ne1_GPa = 62\nnu12 = 0.31\ndensity_kg_per_m3 = 7800\n\
           d31_pm_per_V = -320\nrelative_permittivity = 3800\ndepolarization_field_V_per_mm = 800\n";
    std::fs::write(dir.path().join(&design), text).unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, drive).unwrap();
    (dir, path)
}

/// The insect-scale one-stage example (`drive-robobee-jafferis2016-linkage.toml`, its design copied
/// alongside by [`coercive_copy`], which its biased drive never feels) with its frequency, stroke and
/// `[transmission]` replaced: a slider-crank solved for the stroke with a coupler 4 cranks long, from
/// `travel_mm` (or the actuator's free deflection), its flexures given by their stiffness (5 µN·m/rad),
/// not their sizes.
pub fn insect_linkage_by_stiffness(
    frequency_hz: u32,
    stroke_deg: u32,
    travel_mm: Option<f64>,
) -> (tempfile::TempDir, PathBuf) {
    let (dir, path) = coercive_copy("drive-robobee-jafferis2016-linkage.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("frequency_Hz = 155\n") && text.contains("stroke_deg = 20\n"));
    let head = &text[..text.find("[transmission]").unwrap()];
    let travel = travel_mm.map_or(String::new(), |t| format!("travel_mm = {t}\n"));
    let text = head
        .replace(
            "frequency_Hz = 155\n",
            &format!("frequency_Hz = {frequency_hz}\n"),
        )
        .replace("stroke_deg = 20\n", &format!("stroke_deg = {stroke_deg}\n"))
        + "[transmission]\nsolve_for_stroke = true\ncoupler_ratio = 4\n"
        + &travel
        + "flexure_stiffness_uNm_per_rad = 5\nlink_inertia_mg_mm2 = 0\nmass_mg = 2\n";
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

/// `drive` on `path` (a drive file of [`insect_linkage_by_stiffness`], its design beside it in `dir`)
/// reports `why` as the reason its linkage cannot be built, in one line, and cut-sheet refuses to draw
/// the same linkage for the same reason.
pub fn drive_and_cut_sheet_refuse(dir: &tempfile::TempDir, path: &Path, why: &str) {
    let err = refused_in_one_line(&run(&["drive", path.to_str().unwrap()]));
    assert!(
        err.contains(
            "drive-robobee-jafferis2016-linkage.toml: transmission: the linkage cannot be built: "
        ) && err.contains(why.split(';').next().unwrap()),
        "{err}"
    );
    let out = tempfile::tempdir().unwrap();
    let cut = refused_in_one_line(&run(&[
        "cut-sheet",
        dir.path()
            .join("robobee-jafferis2016-derated.toml")
            .to_str()
            .unwrap(),
        "--drive",
        path.to_str().unwrap(),
        "-o",
        out.path().join("out").to_str().unwrap(),
    ]));
    assert!(cut.contains(why.split(';').next().unwrap()), "{cut}");
}
