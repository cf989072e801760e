//! `actuator-cam weibull`: one column, named once.

use crate::common;
use common::*;

#[test]
fn a_repeated_column_or_flag_is_refused_in_one_line() {
    // The header names `field` twice: which one a run would read is not the user's choice, so none.
    let (_d, path) = write_temp("f.csv", "field,field\n850,1\n900,2\n910,3\n");
    let o = run(&["weibull", path.to_str().unwrap(), "--column", "field"]);
    let err = stderr(&o);
    assert!(
        !o.status.success() && err.trim().lines().count() == 1,
        "{err}"
    );
    assert!(
        err.contains(
            "f.csv: header, column \"field\" = field,field: the column appears twice; keep one"
        ),
        "{err}"
    );
    // `--column` given twice: refused rather than one winning, naming both.
    let (_d2, ok) = write_temp("g.csv", "a,b\n850,1\n900,2\n910,3\n870,2\n");
    let o = run(&[
        "weibull",
        ok.to_str().unwrap(),
        "--column",
        "a",
        "--column",
        "b",
    ]);
    let err = stderr(&o);
    assert!(
        !o.status.success() && err.trim().lines().count() == 1,
        "{err}"
    );
    assert!(err.contains("--column given 2 times (a, b)"), "{err}");
    // Once is fine.
    let o = run(&["weibull", ok.to_str().unwrap(), "--column", "b"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("in column b"));
}
