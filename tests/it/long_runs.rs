//! Long runs as a user meets them: progress as plain lines when stderr is
//! a file or a pipe (as here), progress from `isorad info`, and
//! `--time-limit`, which stops the solve and still writes the outputs.

use super::cli::{isorad, stderr};

#[test]
fn phases_show_as_lines_when_stderr_is_not_a_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let out = isorad(dir.path(), &["render", "--width", "32", "--height", "32"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let log = stderr(&out);
    for phase in ["shadow boundaries", "meshing", "ambient term"] {
        assert!(
            log.contains(&format!("{phase}: started")),
            "{phase}:\n{log}"
        );
        assert!(
            log.contains(&format!("{phase}: done in ")),
            "{phase}:\n{log}"
        );
    }
    // No terminal control codes in a log file.
    assert!(!log.contains('\u{1b}'), "{log:?}");
    let quiet = isorad(
        dir.path(),
        &["render", "--width", "32", "--height", "32", "-q"],
    );
    assert!(!stderr(&quiet).contains(": started"), "{}", stderr(&quiet));
}

#[test]
fn info_shows_its_phases() {
    let dir = tempfile::tempdir().unwrap();
    let out = isorad(dir.path(), &["info"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let log = stderr(&out);
    for phase in ["closed rooms", "dominance analysis", "shadow boundaries"] {
        assert!(
            log.contains(&format!("{phase}: done in ")),
            "{phase}:\n{log}"
        );
    }
    let quiet = isorad(dir.path(), &["info", "-q"]);
    assert!(stderr(&quiet).is_empty(), "{}", stderr(&quiet));
}

#[test]
fn a_time_limit_stops_the_solve_and_writes_the_outputs() {
    let dir = tempfile::tempdir().unwrap();
    // A solve to a tolerance it would take minutes to reach.
    let args = [
        "render",
        "--max-edge",
        "4",
        "--tolerance",
        "0.00001",
        "--width",
        "32",
        "--height",
        "32",
        "-q",
        "--time-limit",
        "3",
    ];
    let out = isorad(dir.path(), &args);
    assert!(out.status.success(), "{}", stderr(&out));
    let log = stderr(&out);
    assert!(log.contains("time limit: the solve stopped after"), "{log}");
    let shots: usize = log
        .split("stopped after ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|n| n.parse().ok())
        .expect("a shot count");
    assert!(shots < 2000, "stopped early: {shots} shots");
    let image = isorad::render::read_exr(&dir.path().join("isorad.exr")).unwrap();
    assert!(image.mean().g > 0.0, "the image holds the light so far");
    for bad in ["0", "-1", "nan", "soon"] {
        let out = isorad(dir.path(), &["render", "-q", "--time-limit", bad]);
        assert!(!out.status.success());
        assert!(stderr(&out).contains("--time-limit"), "{}", stderr(&out));
    }
}
