//! `isorad grid`'s obstructed points (issue 57, item 8): a cabinet standing
//! flush against a wall encloses the work-plane and wall points inside and
//! behind it; they, and the points closer than the clearance to another
//! surface, are left out of Emin, Eavg and U₀, with their reason in the
//! CSV's `status` column and counted in the summary.

use std::path::Path;

/// The office: 4 × 2.8 × 3 m (x, y, z), its six faces facing in and named
/// (`floor`, `ceiling`, `wall_west` at x = 0, …), grey (ρ 0.5), lit by a
/// 1 m ceiling panel (emitted radiance 10) 1 cm under the ceiling.
fn office_obj() -> String {
    let (x, y, z) = (4.0, 2.8, 3.0);
    let mut obj = String::from("mtllib scene.mtl\n");
    let mut quad = |name: &str, material: &str, corners: [[f64; 3]; 4]| {
        obj.push_str(&format!("o {name}\nusemtl {material}\n"));
        for [a, b, c] in corners {
            obj.push_str(&format!("v {a} {b} {c}\n"));
        }
        obj.push_str("f -4 -3 -2 -1\n");
    };
    let p = 0.01;
    quad(
        "floor",
        "grey",
        [[0., 0., 0.], [0., 0., z], [x, 0., z], [x, 0., 0.]],
    );
    quad(
        "ceiling",
        "grey",
        [[0., y, 0.], [x, y, 0.], [x, y, z], [0., y, z]],
    );
    quad(
        "wall_west",
        "grey",
        [[0., 0., 0.], [0., y, 0.], [0., y, z], [0., 0., z]],
    );
    quad(
        "wall_east",
        "grey",
        [[x, 0., 0.], [x, 0., z], [x, y, z], [x, y, 0.]],
    );
    quad(
        "wall_north",
        "grey",
        [[0., 0., 0.], [x, 0., 0.], [x, y, 0.], [0., y, 0.]],
    );
    quad(
        "wall_south",
        "grey",
        [[0., 0., z], [0., y, z], [x, y, z], [x, 0., z]],
    );
    let (l0, l1, lz0, lz1, ly) = (1.5, 2.5, 1.0, 2.0, y - p);
    quad(
        "lamp",
        "lamp",
        [[l0, ly, lz0], [l1, ly, lz0], [l1, ly, lz1], [l0, ly, lz1]],
    );
    obj
}

/// The cabinet's footprint: x from the wall (plus `gap`) to 0.5 m, z from
/// 1.13 to 2.13 m; 1.2 m tall.
const CABINET_X: f64 = 0.5;
const CABINET_Z: [f64; 2] = [1.13, 2.13];
const CABINET_HEIGHT: f64 = 1.2;

/// A cabinet standing on the floor against the west wall, `gap` off it,
/// its faces facing out and its base left out (it stands on the floor);
/// `back` writes its face against the wall, as a closed model would.
fn cabinet_obj(gap: f64, back: bool) -> String {
    let (x0, x1, y1) = (gap, CABINET_X, CABINET_HEIGHT);
    let [z0, z1] = CABINET_Z;
    let mut faces = vec![
        (
            "top",
            [[x0, y1, z0], [x0, y1, z1], [x1, y1, z1], [x1, y1, z0]],
        ),
        (
            "front",
            [[x1, 0., z0], [x1, y1, z0], [x1, y1, z1], [x1, 0., z1]],
        ),
        (
            "north",
            [[x0, 0., z0], [x0, y1, z0], [x1, y1, z0], [x1, 0., z0]],
        ),
        (
            "south",
            [[x1, 0., z1], [x1, y1, z1], [x0, y1, z1], [x0, 0., z1]],
        ),
    ];
    if back {
        faces.push((
            "back",
            [[x0, 0., z1], [x0, y1, z1], [x0, y1, z0], [x0, 0., z0]],
        ));
    }
    let mut obj = String::new();
    for (name, corners) in faces {
        obj.push_str(&format!("o cabinet_{name}\nusemtl grey\n"));
        for [a, b, c] in corners {
            obj.push_str(&format!("v {a} {b} {c}\n"));
        }
        obj.push_str("f -4 -3 -2 -1\n");
    }
    obj
}

fn office_folder(gap: f64, back: bool) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| std::fs::write(dir.path().join(name), text).unwrap();
    write("scene.obj", &(office_obj() + &cabinet_obj(gap, back)));
    write(
        "scene.mtl",
        "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 10 10 10\n",
    );
    write("scene.toml", "obj = \"scene.obj\"\n");
    dir
}

/// One CSV row: the point, its illuminance (None when left out) and status.
struct Row {
    x: f64,
    y: f64,
    z: f64,
    lux: Option<f64>,
    status: String,
}

/// What `isorad grid` wrote: the rows and the `# name = value` lines.
struct GridRun {
    rows: Vec<Row>,
    header: Vec<(String, String)>,
    stdout: String,
}

impl GridRun {
    fn value(&self, name: &str) -> f64 {
        let (_, value) = self.header.iter().find(|(n, _)| n == name).unwrap();
        // `U0 = Emin/Eavg = 0.5`: the value after the last `=`.
        let value = value.rsplit(" = ").next().unwrap();
        value.split_whitespace().next().unwrap().parse().unwrap()
    }

    /// Eavg and U₀ recomputed from the rows counted (status `kept…`).
    fn kept_statistics(&self) -> (f64, f64) {
        let kept: Vec<f64> = (self.rows.iter())
            .filter(|r| r.status.starts_with("kept"))
            .map(|r| r.lux.unwrap())
            .collect();
        let average = kept.iter().sum::<f64>() / kept.len() as f64;
        let minimum = kept.iter().copied().fold(f64::INFINITY, f64::min);
        (average, minimum / average)
    }
}

fn run_grid(dir: &Path, surface: &str, extra: &[&str]) -> GridRun {
    let mut args = vec!["grid", "scene.toml", "-q", "--surface", surface];
    args.extend_from_slice(&["--spacing", "0.25", "--csv", "grid.csv"]);
    args.extend_from_slice(extra);
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_isorad"))
        .current_dir(dir)
        .args(&args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.join("grid.csv")).unwrap();
    let header = (csv.lines())
        .filter_map(|l| l.strip_prefix("# "))
        .filter_map(|l| l.split_once(" = "))
        .map(|(n, v)| (n.to_owned(), v.to_owned()))
        .collect();
    let mut lines = csv.lines().skip_while(|l| l.starts_with('#'));
    assert_eq!(lines.next(), Some("x,y,z,illuminance_lux,status"));
    let rows = lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            Row {
                x: f[0].parse().unwrap(),
                y: f[1].parse().unwrap(),
                z: f[2].parse().unwrap(),
                lux: (!f[3].is_empty()).then(|| f[3].parse().unwrap()),
                status: f[4].to_owned(),
            }
        })
        .collect();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    GridRun {
        rows,
        header,
        stdout,
    }
}

/// Whether plan point (x, z) lies over the cabinet's footprint.
fn over_cabinet(x: f64, z: f64) -> bool {
    x < CABINET_X && (CABINET_Z[0]..CABINET_Z[1]).contains(&z)
}

/// The case: with the cabinet flush against the wall (closed, or
/// without its back as modellers write it), the work-plane points inside
/// it are left out, and Eavg and U₀ are those of the same grid with the
/// cabinet 1 mm off the wall. The points 5 mm in front of the cabinet are
/// left out as near a surface. Kept, the points inside make U₀ about 0.
#[test]
fn a_cabinet_flush_against_a_wall_leaves_its_points_out_as_one_a_millimetre_off() {
    let cases = [(0.001, true), (0.0, true), (0.0, false)];
    let mut statistics = Vec::new();
    for (gap, back) in cases {
        let dir = office_folder(gap, back);
        let run = run_grid(dir.path(), "floor", &["--height", "0.8"]);
        for row in &run.rows {
            let expected = if over_cabinet(row.x, row.z) {
                "left_out_inside_object"
            } else if row.x < CABINET_X && (row.z - CABINET_Z[0]).abs() < 0.01 {
                "left_out_near_surface"
            } else {
                "kept"
            };
            let at = (row.x, row.y, row.z);
            assert_eq!(row.status, expected, "gap {gap}, back {back}, at {at:?}");
            assert_eq!(row.lux.is_some(), expected == "kept", "at {at:?}");
        }
        assert_eq!(run.value("left_out_inside_object"), 8.0);
        assert_eq!(run.value("left_out_near_surface"), 2.0);
        assert_eq!(run.value("points"), 182.0);
        assert!(run.stdout.contains("left_out_inside_object = 8"));
        // The summary's statistics are those of the kept rows.
        let (average, uniformity) = run.kept_statistics();
        assert!((run.value("Eavg") - average).abs() < 1e-5 * average);
        assert!((run.value("U0") - uniformity).abs() < 1e-5);
        eprintln!("gap {gap} m, back {back}: Eavg {average:.3} lx, U0 {uniformity:.4}");
        statistics.push((average, uniformity));
    }
    let (reference_average, reference_uniformity) = statistics[0];
    for &(average, uniformity) in &statistics[1..] {
        assert!((average / reference_average - 1.0).abs() < 0.005);
        assert!((uniformity / reference_uniformity - 1.0).abs() < 0.01);
    }
    // Kept, the points inside the flush cabinet read about nothing.
    let dir = office_folder(0.0, true);
    let run = run_grid(
        dir.path(),
        "floor",
        &["--height", "0.8", "--keep-obstructed-points"],
    );
    assert_eq!(run.value("kept_inside_object"), 8.0);
    assert_eq!(run.value("points"), 192.0);
    let (average, uniformity) = run.kept_statistics();
    eprintln!("kept: Eavg {average:.3} lx, U0 {uniformity:.6}");
    assert!(uniformity < 0.01, "U0 {uniformity}");
    assert!(average < 0.99 * reference_average);
    assert!((run.rows.iter()).any(|r| r.status == "kept_near_surface"));
}

/// On the wall the cabinet stands against, the points behind it are left
/// out, flush (with or without its back) or 1 mm off (there, in the gap,
/// as near a surface), and so are those 5 mm beside it. With no clearance,
/// the points in the 1 mm gap are kept.
#[test]
fn wall_points_behind_a_cabinet_are_left_out() {
    let left_out = |row: &Row| {
        let beside = (row.z - CABINET_Z[0]).abs() < 0.01;
        row.y < CABINET_HEIGHT && (beside || (CABINET_Z[0]..CABINET_Z[1]).contains(&row.z))
    };
    for (gap, back) in [(0.0, true), (0.0, false), (0.001, true)] {
        let dir = office_folder(gap, back);
        let run = run_grid(dir.path(), "wall_west", &[]);
        for row in &run.rows {
            let at = (row.x, row.y, row.z);
            assert_eq!(
                row.status.starts_with("left_out"),
                left_out(row),
                "gap {gap}, back {back}, at {at:?}: {}",
                row.status
            );
        }
        let (inside, near) = (
            run.value("left_out_inside_object"),
            run.value("left_out_near_surface"),
        );
        eprintln!("wall, gap {gap} m, back {back}: {inside} inside, {near} near");
        assert_eq!(inside + near, 25.0);
        let (_, uniformity) = run.kept_statistics();
        assert!(uniformity > 0.2, "gap {gap}, back {back}: U0 {uniformity}");
        if gap > 0.0 {
            let run = run_grid(dir.path(), "wall_west", &["--clearance", "0"]);
            let kept = (run.rows.iter()).filter(|r| r.status == "kept").count();
            assert_eq!(kept, run.rows.len());
        }
    }
}
