//! Faces lit from both sides: a scene file's `two_sided` gives each face of
//! the named materials a twin facing the other way, and faces back to back
//! neither light each other nor show their backs.

use glam::DVec3;
use isorad::{Ambient, Settings, Solver, load_scene, phase::silent};

use crate::support::gather_at;

/// A 2 m board facing up, 1 m over a floor, under a lamp 1 m above it and
/// over a lamp 0.5 m under it (facing up and down), with `two_sided` as
/// given (`None`: the key left out).
fn board_folder(two_sided: Option<&str>) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let obj = "mtllib s.mtl\n\
        o floor\nusemtl grey\nv -5 0 -5\nv -5 0 5\nv 5 0 5\nv 5 0 -5\nf 1 2 3 4\n\
        o board\nusemtl board\nv -1 1 -1\nv -1 1 1\nv 1 1 1\nv 1 1 -1\nf 5 6 7 8\n\
        o lamp_above\nusemtl lamp\nv -0.2 2 -0.2\nv 0.2 2 -0.2\nv 0.2 2 0.2\nv -0.2 2 0.2\nf 9 10 11 12\n\
        o lamp_below\nusemtl lamp\nv -0.2 0.5 -0.2\nv -0.2 0.5 0.2\nv 0.2 0.5 0.2\nv 0.2 0.5 -0.2\nf 13 14 15 16\n";
    std::fs::write(dir.path().join("s.obj"), obj).unwrap();
    std::fs::write(
        dir.path().join("s.mtl"),
        "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl board\nKd 0.6 0.6 0.6\nnewmtl lamp\nKd 0 0 0\nKe 20 20 20\n",
    )
    .unwrap();
    let key = two_sided
        .map(|v| format!("two_sided = {v}\n"))
        .unwrap_or_default();
    std::fs::write(dir.path().join("s.toml"), format!("obj = \"s.obj\"\n{key}")).unwrap();
    dir
}

fn solve(dir: &tempfile::TempDir) -> Solver {
    let loaded = load_scene(dir.path().join("s.toml").to_str().unwrap()).unwrap();
    let mut solver = Solver::new(loaded.scene, Settings::default()).unwrap();
    solver.run();
    solver
}

#[test]
fn a_two_sided_board_is_lit_on_both_sides_and_one_sided_on_one() {
    let one = solve(&board_folder(None));
    let two = solve(&board_folder(Some("[\"board\"]")));
    assert_eq!(one.scene().surfaces.len(), 4);
    assert_eq!(two.scene().surfaces.len(), 5);
    let (one, two) = (
        one.solution(Ambient::Everywhere, &silent),
        two.solution(Ambient::Everywhere, &silent),
    );
    // The board's top, under the upper lamp: the same either way.
    let top = DVec3::new(0.3, 1.0, 0.2);
    let (a, b) = (
        gather_at(&one, top, Some(DVec3::Y)).irradiance.g,
        gather_at(&two, top, Some(DVec3::Y)).irradiance.g,
    );
    assert!((a / b - 1.0).abs() < 0.02, "top {a} vs {b}");
    // Its underside: one-sided, nothing to light it; two-sided, the lower
    // lamp's light, E = L F with F the square's factor from 0.5 m below.
    let under = DVec3::new(0.0, 1.0, 0.0);
    let point = isorad::scene::ProbePoint {
        position: under,
        normal: Some(DVec3::NEG_Y),
        line: 1,
    };
    let unlit = one.probe(&point, isorad::ProbeMode::Gather);
    assert!(unlit.is_err(), "one-sided: the board has no underside");
    let lit = gather_at(&two, under, Some(DVec3::NEG_Y));
    // Lambert's factor of a 0.4 m square seen on axis from 0.5 m.
    let (a, h) = (0.2_f64, 0.5_f64);
    let f = 2.0 / std::f64::consts::PI
        * (2.0 * a / (a * a + h * h).sqrt() * (a / (a * a + h * h).sqrt()).atan());
    let direct = std::f64::consts::PI * 20.0 * f;
    let ratio = lit.irradiance.g / direct;
    // Its own direct light, and a little reflected from the floor.
    assert!(
        (1.0..1.15).contains(&ratio),
        "underside ×{ratio} of the lamp's direct light"
    );
    // Its radiosity is what it reflects (Kd 0.6, read as a 32-bit float).
    assert!((lit.radiosity.g / (0.6 * lit.irradiance.g) - 1.0).abs() < 1e-6);
}

#[test]
fn two_sided_naming_no_material_is_an_error_with_its_line() {
    let dir = board_folder(Some("[\"board\",\n  \"bord\"]"));
    let error = load_scene(dir.path().join("s.toml").to_str().unwrap())
        .err()
        .unwrap()
        .to_string();
    assert!(
        error.contains("s.toml") && error.contains("line 3: two_sided: \"bord\""),
        "{error}"
    );
}
