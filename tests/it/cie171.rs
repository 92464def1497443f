//! The analytic test cases of CIE 171:2006, "Test cases to assess the
//! accuracy of lighting computer programs", each with its exact value
//! computed here, independently of isorad's own kernels:
//!
//! - 5.2, a point source: E = I(C, γ) cos θ / r² on the floor and the walls
//!   of a black room, for an asymmetric luminaire given as IES LM-63 and as
//!   EULUMDAT (wrapped value lines, multipliers, a tilted aim), within 1 %
//!   at every probe;
//! - 5.3, an area source: a Lambertian rectangle on the ceiling, E = L ∫
//!   cos θ cos θ' / r² dA by Gauss–Legendre quadrature, within 1 %;
//! - 5.8, inter-reflections in a closed room of reflectance ρ: the mean
//!   illuminance over its faces is Φ / S / (1 − ρ), within 2 %, for ρ from
//!   0.2 to 0.95.

use std::f64::consts::PI;
use std::path::Path;

use glam::DVec3;
use isorad::calculation::{CalculationGrid, IlluminanceStatistics, illuminance_lux};
use isorad::scene::ProbePoint;
use isorad::{Ambient, ProbeMode, Settings, Solver, StopReason, load_scene, phase::silent};

/// The room: 4 m × 4 m, 3 m high, one quad per face, facing inwards.
const ROOM: [f64; 3] = [4.0, 3.0, 4.0];

/// The candela multiplier written in the IES file and the scene's
/// `multiplier`.
const FILE_MULTIPLIER: f64 = 2.0;
const SCENE_MULTIPLIER: f64 = 0.75;

/// The asymmetric test luminaire, candela before the scene's multiplier
/// (the files store it divided by their own multipliers):
/// I(C, γ) = 300 + 700 max(cos γ, 0) (1 + 0.5 cos C + 0.3 sin C), smooth
/// enough that the web's bilinear interpolation (10° in C, 2.5° in γ) is
/// within 0.2 %; the sin C term makes it asymmetric about every plane, so a
/// C90 turned the wrong way shows.
fn intensity(c: f64, gamma: f64) -> f64 {
    let c = c.to_radians();
    300.0 + 700.0 * gamma.to_radians().cos().max(0.0) * (1.0 + 0.5 * c.cos() + 0.3 * c.sin())
}

/// Its flux, lm, before the scene's multiplier: ∫ I dΩ = 1200 π + 700 π
/// (the cos C and sin C terms integrate to zero).
const FLUX: f64 = 1900.0 * PI;

fn gammas() -> Vec<f64> {
    (0..=72).map(|k| 2.5 * k as f64).collect()
}

/// Numbers written `per_line` to a line, as photometric files wrap them.
fn wrapped(values: impl IntoIterator<Item = f64>, per_line: usize) -> String {
    let values: Vec<String> = values.into_iter().map(|v| format!("{v:.4}")).collect();
    values
        .chunks(per_line)
        .map(|chunk| chunk.join(" "))
        .collect::<Vec<_>>()
        .join("\n")
}

/// LM-63-2002, type C, no symmetry (C 0–360 every 10°), absolute
/// photometry, intensities divided by the candela multiplier, values
/// wrapped seven to a line.
fn ies_file() -> String {
    let cs: Vec<f64> = (0..=36).map(|k| 10.0 * k as f64).collect();
    let gammas = gammas();
    let mut text = format!(
        "IESNA:LM-63-2002\n[TEST] CIE 171 asymmetric\n[MANUFAC] isorad tests\nTILT=NONE\n\
         1 -1 {FILE_MULTIPLIER} {} {} 1 2 0 0 0\n1.0 1.0 30\n{}\n{}\n",
        gammas.len(),
        cs.len(),
        wrapped(gammas.iter().copied(), 7),
        wrapped(cs.iter().copied(), 7),
    );
    for &c in &cs {
        let plane = gammas.iter().map(|&g| intensity(c, g) / FILE_MULTIPLIER);
        text.push_str(&wrapped(plane, 7));
        text.push('\n');
    }
    text
}

/// EULUMDAT, Isym 0 (36 planes), cd/klm of a 2000 lm lamp set with a
/// conversion factor of 2 (the same candela as the IES file).
fn ldt_file() -> String {
    let lamp_flux = 2000.0;
    let conversion = FILE_MULTIPLIER;
    let gammas = gammas();
    let mut lines: Vec<String> = [
        "isorad tests",
        "1",
        "0",
        "36",
        "10",
        "73",
        "2.5",
        "CIE 171",
        "asymmetric",
        "A-1",
        "asymmetric.ldt",
        "2026-12-02",
        "100",
        "100",
        "50",
        "0",
        "0",
        "0",
        "0",
        "0",
        "0",
        "80",
        "100",
    ]
    .iter()
    .map(|s| (*s).to_owned())
    .collect();
    lines.push(format!("{conversion}"));
    lines.extend(["0", "1", "1", "LED"].map(String::from));
    lines.push(format!("{lamp_flux}"));
    lines.extend(["3000", "80", "30"].map(String::from));
    lines.extend((0..10).map(|_| "0.5".to_owned()));
    lines.extend((0..36).map(|k| format!("{}", 10 * k)));
    lines.extend(gammas.iter().map(|g| format!("{g}")));
    for k in 0..36 {
        let c = 10.0 * f64::from(k);
        for &g in &gammas {
            let candela = intensity(c, g) / conversion;
            lines.push(format!("{:.5}", candela * 1000.0 / lamp_flux));
        }
    }
    lines.join("\r\n") + "\r\n"
}

/// The six faces of the room as OBJ quads facing inwards, material `wall`.
fn room_obj() -> String {
    let [x, y, z] = ROOM;
    let v = [
        [0.0, 0.0, 0.0],
        [x, 0.0, 0.0],
        [x, 0.0, z],
        [0.0, 0.0, z],
        [0.0, y, 0.0],
        [x, y, 0.0],
        [x, y, z],
        [0.0, y, z],
    ];
    let mut obj = String::from("mtllib scene.mtl\n");
    for p in v {
        obj.push_str(&format!("v {} {} {}\n", p[0], p[1], p[2]));
    }
    let faces = [
        ("floor", [1, 4, 3, 2]),
        ("ceiling", [5, 6, 7, 8]),
        ("wall_z0", [1, 2, 6, 5]),
        ("wall_z4", [4, 8, 7, 3]),
        ("wall_x0", [1, 5, 8, 4]),
        ("wall_x4", [2, 3, 7, 6]),
    ];
    for (name, f) in faces {
        obj.push_str(&format!(
            "o {name}\nusemtl wall\nf {} {} {} {}\n",
            f[0], f[1], f[2], f[3]
        ));
    }
    obj
}

/// Where the luminaire hangs and points: off-centre, tilted, C0 not quite
/// perpendicular to the aim (the loader makes it so).
const POSITION: DVec3 = DVec3::new(1.6, 2.7, 2.3);
const AIM: DVec3 = DVec3::new(0.25, -1.0, 0.15);
const C0: DVec3 = DVec3::new(1.0, 0.1, 0.0);

/// Writes the room (reflectance `rho`), both photometric files and a
/// scene file lighting it with `lighting` (a `[[luminaire]]` table or
/// nothing), plus `extra_obj` faces.
fn room_folder(rho: f64, luminaire_file: Option<&str>, extra_obj: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| std::fs::write(dir.path().join(name), text).unwrap();
    write("scene.obj", &(room_obj() + extra_obj));
    write(
        "scene.mtl",
        &format!("newmtl wall\nKd {rho} {rho} {rho}\nnewmtl panel\nKd 0 0 0\nKe 10 10 10\n"),
    );
    write("asymmetric.ies", &ies_file());
    write("asymmetric.ldt", &ldt_file());
    let mut toml = "obj = \"scene.obj\"\n".to_owned();
    if let Some(file) = luminaire_file {
        toml.push_str(&format!(
            "\n[[luminaire]]\nies = \"{file}\"\nposition = [{}, {}, {}]\naim = [{}, {}, {}]\n\
             c0 = [{}, {}, {}]\nmultiplier = {SCENE_MULTIPLIER}\n",
            POSITION.x, POSITION.y, POSITION.z, AIM.x, AIM.y, AIM.z, C0.x, C0.y, C0.z
        ));
    }
    write("scene.toml", &toml);
    dir
}

/// Solves the scene in `dir` at its default settings; the solve must
/// converge (unshot power under the tolerance), not stop at a limit.
fn solve(dir: &Path) -> Solver {
    let loaded = load_scene(dir.join("scene.toml").to_str().unwrap()).unwrap();
    let settings = Settings::from_scene_options(&loaded.options).unwrap();
    let mut solver = Solver::new(loaded.scene, settings).unwrap();
    let stop = solver.run();
    assert!(
        matches!(stop, StopReason::Converged | StopReason::NothingToShoot),
        "the solve stopped: {stop:?}"
    );
    solver
}

/// The exact illuminance of the test luminaire at `x` on a surface of unit
/// normal `n`, lx: I(C, γ) cos θ / r², with γ from the aim
/// and C from C0 (made perpendicular to the aim) towards (−aim) × C0,
/// times the scene's multiplier.
fn point_source_lux(x: DVec3, n: DVec3) -> f64 {
    let aim = AIM.normalize();
    let c0 = (C0 - aim * C0.dot(aim)).normalize();
    let c90 = (-aim).cross(c0);
    let d = x - POSITION;
    let r2 = d.length_squared();
    let d = d / r2.sqrt();
    let cos = (-d).dot(n);
    if cos <= 0.0 {
        return 0.0;
    }
    let gamma = d.dot(aim).clamp(-1.0, 1.0).acos().to_degrees();
    let c = d.dot(c90).atan2(d.dot(c0)).to_degrees().rem_euclid(360.0);
    intensity(c, gamma) * SCENE_MULTIPLIER * cos / r2
}

/// Probe points on the floor and on two walls, with their normals.
fn probe_points() -> Vec<(DVec3, DVec3)> {
    let mut points = Vec::new();
    for i in 0..5 {
        for k in 0..5 {
            let (a, b) = (0.3 + 0.85 * f64::from(i), 0.3 + 0.85 * f64::from(k));
            points.push((DVec3::new(a, 0.0, b), DVec3::Y));
            points.push((DVec3::new(a, 0.25 + 0.5 * f64::from(k), 0.0), DVec3::Z));
            points.push((DVec3::new(4.0, 0.25 + 0.5 * f64::from(k), b), -DVec3::X));
        }
    }
    points
}

fn probe_lux(solver: &Solver, x: DVec3, n: DVec3) -> f64 {
    let point = ProbePoint {
        position: x,
        normal: Some(n),
        line: 0,
    };
    let probe = solver
        .solution(Ambient::Everywhere, &silent)
        .probe(&point, ProbeMode::Gather)
        .unwrap();
    illuminance_lux(probe.irradiance)
}

#[test]
fn case_5_2_point_source_from_ies_and_eulumdat() {
    for file in ["asymmetric.ies", "asymmetric.ldt"] {
        let dir = room_folder(0.0, Some(file), "");
        let solver = solve(dir.path());
        let mut worst: f64 = 0.0;
        for (x, n) in probe_points() {
            let exact = point_source_lux(x, n);
            let got = probe_lux(&solver, x, n);
            let error = (got - exact).abs() / exact;
            assert!(
                error < 0.01,
                "{file}: at {x} (normal {n}): {got} lx, exact {exact} lx"
            );
            worst = worst.max(error);
        }
        eprintln!("5.2 {file}: worst probe error {:.3} %", 100.0 * worst);
    }
}

/// Gauss–Legendre nodes and weights on [0, 1], 16 points (Golub–Welsch
/// would do; these are the tabulated ones, mapped from [−1, 1]).
fn gauss_legendre_16() -> Vec<(f64, f64)> {
    const HALF: [(f64, f64); 8] = [
        (0.095_012_509_837_637_44, 0.189_450_610_455_068_5),
        (0.281_603_550_779_258_9, 0.182_603_415_044_923_6),
        (0.458_016_777_657_227_4, 0.169_156_519_395_002_5),
        (0.617_876_244_402_643_7, 0.149_595_988_816_576_7),
        (0.755_404_408_355_003, 0.124_628_971_255_533_9),
        (0.865_631_202_387_831_7, 0.095_158_511_682_492_78),
        (0.944_575_023_073_232_6, 0.062_253_523_938_647_89),
        (0.989_400_934_991_649_9, 0.027_152_459_411_754_09),
    ];
    HALF.iter()
        .flat_map(|&(x, w)| [(0.5 - 0.5 * x, 0.5 * w), (0.5 + 0.5 * x, 0.5 * w)])
        .collect()
}

/// The panel: 1.2 m × 0.6 m on the ceiling, emitting downwards.
const PANEL: [f64; 4] = [1.0, 2.2, 1.5, 2.1];
/// Its radiance, W/(m²·sr) per channel (MTL Ke).
const PANEL_RADIANCE: f64 = 10.0;

/// The exact illuminance of the panel at `x` (unit normal `n`), lx:
/// L ∫ cos θ cos θ' / r² dA, the panel cut into 8 × 8 tiles of 16 × 16
/// Gauss–Legendre points each (the integrand is smooth: every probe is at
/// least 0.25 m from the panel's plane).
fn area_source_lux(x: DVec3, n: DVec3) -> f64 {
    let [x0, x1, z0, z1] = PANEL;
    let nodes = gauss_legendre_16();
    let tiles = 8;
    let (dx, dz) = ((x1 - x0) / f64::from(tiles), (z1 - z0) / f64::from(tiles));
    let mut integral = 0.0;
    for i in 0..tiles {
        for k in 0..tiles {
            for &(s, ws) in &nodes {
                for &(t, wt) in &nodes {
                    let y = DVec3::new(
                        x0 + (f64::from(i) + s) * dx,
                        ROOM[1],
                        z0 + (f64::from(k) + t) * dz,
                    );
                    let d = y - x;
                    let r2 = d.length_squared();
                    let cos_r = n.dot(d).max(0.0) / r2.sqrt();
                    let cos_s = d.y / r2.sqrt();
                    integral += ws * wt * cos_r * cos_s / r2;
                }
            }
        }
    }
    PANEL_RADIANCE * integral * dx * dz * isorad::photometry::LUMENS_PER_WATT
}

#[test]
fn case_5_3_area_source() {
    let [x0, x1, z0, z1] = PANEL;
    let y = ROOM[1] - 1e-4;
    let panel = format!(
        "o panel\nusemtl panel\nv {x0} {y} {z0}\nv {x1} {y} {z0}\nv {x1} {y} {z1}\nv {x0} {y} {z1}\n\
         f -4 -3 -2 -1\n"
    );
    let dir = room_folder(0.0, None, &panel);
    let solver = solve(dir.path());
    let mut worst: f64 = 0.0;
    for (x, n) in probe_points() {
        let exact = area_source_lux(x, n);
        let got = probe_lux(&solver, x, n);
        let error = (got - exact).abs() / exact;
        assert!(
            error < 0.01,
            "at {x} (normal {n}): {got} lx, exact {exact} lx"
        );
        worst = worst.max(error);
    }
    eprintln!("5.3: worst probe error {:.3} %", 100.0 * worst);
}

#[test]
fn case_5_8_inter_reflections_in_a_closed_room() {
    let [x, y, z] = ROOM;
    let area = 2.0 * (x * y + y * z + z * x);
    let flux = FLUX * SCENE_MULTIPLIER;
    for rho in [0.2, 0.5, 0.8, 0.95] {
        let dir = room_folder(rho, Some("asymmetric.ies"), "");
        let solver = solve(dir.path());
        let exact = flux / area / (1.0 - rho);
        // The mesh's mean over every face, weighted by area.
        let solution = solver.solution(Ambient::Everywhere, &silent);
        let totals = solution.surface_totals();
        let received: f64 = totals
            .iter()
            .map(|t| illuminance_lux(t.received_power))
            .sum();
        let mesh_mean = received / area;
        // And the gather's, read on each face's calculation grid.
        let mut grid_received = 0.0;
        for face in [
            "floor", "ceiling", "wall_z0", "wall_z4", "wall_x0", "wall_x4",
        ] {
            let grid = CalculationGrid::on_surface(solution.scene, face, 0.0, Some(0.5)).unwrap();
            let stats = IlluminanceStatistics::of(&grid.illuminance(&solution)).unwrap();
            let face_area: f64 = solution
                .scene
                .surfaces
                .iter()
                .filter(|s| s.name == face)
                .map(|s| s.area())
                .sum();
            grid_received += stats.average * face_area;
        }
        let grid_mean = grid_received / area;
        eprintln!(
            "5.8 ρ = {rho}: exact {exact:.2} lx, mesh {mesh_mean:.2} lx ({:+.2} %), \
             grid {grid_mean:.2} lx ({:+.2} %), {} shots",
            100.0 * (mesh_mean / exact - 1.0),
            100.0 * (grid_mean / exact - 1.0),
            solver.stats().shots
        );
        assert!(
            (mesh_mean / exact - 1.0).abs() < 0.02,
            "ρ = {rho}: mesh mean {mesh_mean}, exact {exact}"
        );
        assert!(
            (grid_mean / exact - 1.0).abs() < 0.02,
            "ρ = {rho}: grid mean {grid_mean}, exact {exact}"
        );
    }
}

/// Runs `isorad` in `dir`.
fn isorad(dir: &Path, args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_isorad"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn a_work_plane_grid_lists_the_exact_illuminance_and_draws_it() {
    for file in ["asymmetric.ies", "asymmetric.ldt"] {
        let dir = room_folder(0.0, Some(file), "");
        let out = isorad(
            dir.path(),
            &[
                "grid",
                "scene.toml",
                "-q",
                "--surface",
                "floor",
                "--height",
                "0.8",
                "--csv",
                "grid.csv",
                "--isolux",
                "isolux.png",
                "--falsecolor",
                "falsecolor.png",
            ],
        );
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let csv = std::fs::read_to_string(dir.path().join("grid.csv")).unwrap();
        let mut lines = csv.lines().skip_while(|l| l.starts_with('#'));
        assert_eq!(lines.next(), Some("x,y,z,illuminance_lux,status"));
        let rows: Vec<Vec<f64>> = lines
            .map(|l| {
                let (values, status) = l.rsplit_once(',').unwrap();
                assert_eq!(status, "kept");
                values.split(',').map(|v| v.parse().unwrap()).collect()
            })
            .collect();
        // A 4 m room: EN 12464-1's p = 0.2 · 5^log10(4) ≈ 0.53 m, so 8 × 8 points.
        assert_eq!(rows.len(), 64);
        let mut total_error = 0.0;
        let mut values = Vec::new();
        for row in &rows {
            let x = DVec3::new(row[0], row[1], row[2]);
            assert!((x.y - 0.8).abs() < 1e-12);
            let exact = point_source_lux(x, DVec3::Y);
            total_error += (row[3] - exact).abs() / exact;
            values.push(row[3]);
        }
        let mean_error = total_error / rows.len() as f64;
        eprintln!("grid {file}: mean error {:.3} %", 100.0 * mean_error);
        assert!(mean_error < 0.01, "{file}: mean error {mean_error}");
        // The statistics in the header and on stdout.
        let stats = IlluminanceStatistics::of(&values).unwrap();
        for (name, value) in [
            ("Emin", stats.minimum),
            ("Eavg", stats.average),
            ("Emax", stats.maximum),
        ] {
            let line = format!("{name} = {value:.6} lx");
            assert!(csv.contains(&format!("# {line}")), "{csv}");
            assert!(stdout.contains(&line), "{stdout}");
        }
        assert!(csv.contains(&format!("# U0 = Emin/Eavg = {:.6}", stats.uniformity())));
        assert!(csv.contains(&format!("# Emin/Emax = {:.6}", stats.diversity())));
        for picture in ["isolux.png", "falsecolor.png"] {
            let image = ::image::open(dir.path().join(picture)).unwrap();
            assert!(image.width() > 400, "{picture}");
        }
    }
}

#[test]
fn a_grid_on_an_unknown_surface_or_with_a_bad_spacing_is_refused_before_solving() {
    let dir = room_folder(0.0, Some("asymmetric.ies"), "");
    let cases: [(&[&str], &str); 6] = [
        (
            &["--surface", "flor"],
            "--surface: no surface is named `flor`; the scene has ceiling, floor",
        ),
        (
            &["--surface", "floor", "--spacing", "0"],
            "--spacing: 0 must be > 0",
        ),
        (
            &["--surface", "floor", "--height", "-1"],
            "--height: -1 must be ≥ 0",
        ),
        (
            &["--surface", "floor", "--clearance", "-1"],
            "--clearance: -1 must be ≥ 0",
        ),
        (
            &["--surface", "floor", "--height", "0.8", "--clearance", "10"],
            "all 64 grid points on `floor` lie inside objects or within --clearance 10",
        ),
        (
            &["--surface", "floor", "--isolux", "plot.jpg"],
            "--isolux plot.jpg: the plot is written as .png or .svg",
        ),
    ];
    for (flags, message) in cases {
        let mut args = vec!["grid", "scene.toml", "-q", "--csv", "grid.csv"];
        args.extend_from_slice(flags);
        let out = isorad(dir.path(), &args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success());
        assert!(stderr.contains(message), "{flags:?}: {stderr}");
        assert!(!dir.path().join("grid.csv").exists());
    }
}

/// Both kinds of light in one scene: an emitting face (MTL `Ke`) and a
/// photometric luminaire add, each exactly, and the ledger closes.
#[test]
fn an_emitting_face_and_a_photometric_luminaire_light_one_room_together() {
    let [x0, x1, z0, z1] = PANEL;
    let y = ROOM[1] - 1e-4;
    let panel = format!(
        "o panel\nusemtl panel\nv {x0} {y} {z0}\nv {x1} {y} {z0}\nv {x1} {y} {z1}\nv {x0} {y} {z1}\n\
         f -4 -3 -2 -1\n"
    );
    let dir = room_folder(0.0, Some("asymmetric.ldt"), &panel);
    let solver = solve(dir.path());
    let balance = solver.energy_balance();
    let total = balance.absorbed + balance.unshot + balance.escaped;
    let imbalance = ((total - balance.emitted).abs() / balance.emitted).max_element();
    assert!(imbalance < 1e-9, "ledger imbalance {imbalance}");
    for (x, n) in probe_points() {
        // The luminaire hangs below the panel's plane: the panel never hides it.
        let exact = point_source_lux(x, n) + area_source_lux(x, n);
        let got = probe_lux(&solver, x, n);
        assert!(
            (got - exact).abs() < 0.01 * exact,
            "at {x} (normal {n}): {got} lx, exact {exact} lx"
        );
    }
}

/// `isorad probe` reads lux and cd/m² beside W/m².
#[test]
fn probe_lists_illuminance_in_lux_and_luminance() {
    let dir = room_folder(0.5, Some("asymmetric.ies"), "");
    std::fs::write(dir.path().join("points.csv"), "2.0,0,2.0\n0.5,0,3.5\n").unwrap();
    let out = isorad(
        dir.path(),
        &["probe", "scene.toml", "-q", "--points", "points.csv"],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    for line in lines {
        let row: Vec<f64> = line.split(',').map(|v| v.parse().unwrap()).collect();
        let y =
            |first: usize| 0.2126 * row[first] + 0.7152 * row[first + 1] + 0.0722 * row[first + 2];
        let lux = row[column("illuminance_lux")];
        let nits = row[column("luminance_cd_m2")];
        assert!((lux - 179.0 * y(column("irradiance_r"))).abs() < 1e-9 * lux);
        assert!((nits - 179.0 * y(column("radiosity_r")) / PI).abs() < 1e-9 * nits);
        // Grey walls of ρ 0.5: L = ρ E / π.
        assert!((nits - 0.5 * lux / PI).abs() < 1e-9 * lux);
    }
}

/// A work plane through a cabinet: the points inside it are left out
/// (counted in the header), the others read light.
#[test]
fn work_plane_points_inside_furniture_are_left_out() {
    // A closed 1 × 1.2 × 1 m cabinet, faces outwards, over x 2.5–3.5, z 0.5–1.5.
    let mut cabinet = String::from("o cabinet\nusemtl wall\n");
    let (x0, x1, y0, y1, z0, z1) = (2.5, 3.5, 0.0, 1.2, 0.5, 1.5);
    for (x, y, z) in [
        (x0, y0, z0),
        (x1, y0, z0),
        (x1, y0, z1),
        (x0, y0, z1),
        (x0, y1, z0),
        (x1, y1, z0),
        (x1, y1, z1),
        (x0, y1, z1),
    ] {
        cabinet.push_str(&format!("v {x} {y} {z}\n"));
    }
    // Outward: the reverse of the room's inward faces.
    for f in [
        [-8, -7, -6, -5],
        [-4, -1, -2, -3],
        [-8, -4, -3, -7],
        [-5, -6, -2, -1],
        [-8, -5, -1, -4],
        [-7, -3, -2, -6],
    ] {
        cabinet.push_str(&format!("f {} {} {} {}\n", f[0], f[1], f[2], f[3]));
    }
    let dir = room_folder(0.0, Some("asymmetric.ies"), &cabinet);
    let solver = solve(dir.path());
    let solution = solver.solution(Ambient::Everywhere, &silent);
    let grid = CalculationGrid::on_surface(solution.scene, "floor", 0.8, None).unwrap();
    let lux = grid.illuminance(&solution);
    let mut inside = 0;
    for (point, e) in grid.points.iter().zip(&lux) {
        let Some((p, _)) = point else { continue };
        let in_cabinet = (x0..x1).contains(&p.x) && (z0..z1).contains(&p.z);
        assert_eq!(e.is_nan(), in_cabinet, "at {p}: {e} lx");
        inside += usize::from(in_cabinet);
    }
    assert_eq!(inside, 4);
    let rule = isorad::calculation::ObstructionRule::default();
    let selection = grid
        .select(solution.scene, solution.visibility, &rule)
        .unwrap();
    assert!(
        grid.header_lines(&lux, &selection)
            .contains(&"left_out_inside_object = 4".to_owned())
    );
    assert_eq!(IlluminanceStatistics::of(&lux).unwrap().points, 60);
    // On the floor itself, the points under the cabinet are left out too.
    let floor = CalculationGrid::on_surface(solution.scene, "floor", 0.0, None).unwrap();
    let lux = floor.illuminance(&solution);
    for (point, e) in floor.points.iter().zip(&lux) {
        let Some((p, _)) = point else { continue };
        let under = (x0..x1).contains(&p.x) && (z0..z1).contains(&p.z);
        assert_eq!(e.is_nan(), under, "at {p}: {e} lx");
    }
}

/// The free-space gather sees the elements' light as a probe on the
/// surface does: in a grey room, a hair above the floor, both agree.
#[test]
fn a_free_space_gather_just_above_a_surface_agrees_with_its_probe() {
    let dir = room_folder(0.6, Some("asymmetric.ies"), "");
    let solver = solve(dir.path());
    let solution = solver.solution(Ambient::Everywhere, &silent);
    for (x, n) in probe_points() {
        let on_surface = probe_lux(&solver, x, n);
        let (irradiance, _) = solution.irradiance_in_space(x + n * 1e-3, n);
        let above = illuminance_lux(irradiance);
        // The luminaire's direct light and the elements' reflected light, both.
        let direct = point_source_lux(x, n);
        assert!(on_surface > 1.2 * direct, "at {x}: little reflected light");
        assert!(
            (above - on_surface).abs() < 0.01 * on_surface,
            "at {x} (normal {n}): {above} lx in space, {on_surface} lx on the surface"
        );
    }
}
