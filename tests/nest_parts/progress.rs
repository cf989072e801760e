//! The nest observer and the terminal: every job, its sheets and density; a piped run prints nothing.

use super::*;

#[test]
fn the_observer_sees_every_job_its_sheets_and_the_best_density() {
    let (planned, recorder) = observed("batch.toml", 100);
    let layers = recorder.layers.borrow();
    // The example batch has two layups: two passive layers, nested one after the other.
    assert_eq!(
        layers
            .iter()
            .map(|l| (l.0, l.1, l.2.as_str()))
            .collect::<Vec<_>>(),
        vec![(0, 2, "passive"), (1, 2, "passive")]
    );
    // Parts per job: one passive part per actuator of its layup (C, B: 16; A, 1: 8).
    assert_eq!(layers.iter().map(|l| l.3).collect::<Vec<_>>(), vec![16, 8]);
    let reports = recorder.reports.borrow();
    for job in 1..=2 {
        let mine: Vec<&NestProgress> = reports
            .iter()
            .filter(|(l, _)| *l == job)
            .map(|(_, p)| p)
            .collect();
        assert!(!mine.is_empty(), "job {job} reported nothing");
        for p in &mine {
            assert!(p.sheets >= p.sheets_lower_bound && p.sheets_lower_bound >= 1);
            assert!(p.best_density > 0.0 && p.best_density <= 1.0);
        }
        let last = mine.last().unwrap();
        assert!(last.finished);
        // The last report is the layout drawn: its density is the report's used-length one (to
        // 1e-6: the engine measures its snapshot on its own copy of the placed outlines).
        let row = &planned.report.baseline[job - 1];
        assert!(
            (last.best_density - row.used_length_utilization).abs() < 1e-6,
            "{last:?} {row:?}"
        );
        assert_eq!(last.sheets, row.sheets);
    }
}

#[test]
fn a_piped_run_prints_no_progress() {
    // The roll batch too: its cost comparison nests are jobs of the same (silent) run.
    for example in ["batch.toml", "batch-roll.toml"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let o = run(&[
            "nest",
            example_path(example).to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--iterations",
            "30",
        ]);
        assert!(o.status.success(), "{example}: {}", stderr(&o));
        assert_eq!(
            stderr(&o),
            "",
            "{example}: stderr is not a terminal: nothing on it"
        );
    }
}
