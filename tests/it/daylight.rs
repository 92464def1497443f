//! Daylight against references computed here, independently of isorad's
//! own sky, glazing and portal code (CIE 171:2006 cases 5.9–5.12 are of
//! this kind):
//!
//! - the sky component at floor points of a black room under an unglazed
//!   opening in the roof and in the façade, under the CIE overcast and
//!   clear skies: within 0.5 % of ∫ L(ω) cos θ dω over the opening, by a
//!   400 × 400 midpoint rule over its area (cos θ_p cos θ_o / r² dA);
//! - a glazed façade opening: the same integral with each direction's pane
//!   transmittance, Fresnel's equations for a clear pane of index 1.52
//!   written out here;
//! - the unobstructed horizontal plane under every sky: within 0.5 % of
//!   the illuminance the file asks for;
//! - the daylight factor grid and the scene file's errors.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use glam::DVec3;
use isorad::scene::ProbePoint;
use isorad::{Ambient, ProbeMode, Settings, Solver, load_scene, phase::silent};

/// The room: 4 m wide (x), 3 m high (y), 4 m deep (z), faces inwards.
const ROOM: [f64; 3] = [4.0, 3.0, 4.0];
/// Zenith luminance of the test skies, cd/m².
const ZENITH: f64 = 5000.0;

/// A rectangle as an OBJ face, counter-clockwise seen from its front.
fn face(out: &mut String, name: &str, material: &str, corners: [[f64; 3]; 4]) {
    out.push_str(&format!("o {name}\nusemtl {material}\n"));
    for [x, y, z] in corners {
        out.push_str(&format!("v {x} {y} {z}\n"));
    }
    out.push_str("f -4 -3 -2 -1\n");
}

/// Where the room's opening is.
#[derive(Clone, Copy)]
enum Opening {
    /// x and z from 1.5 to 2.5 in the ceiling.
    Roof,
    /// x from 1 to 3, y from 0.9 to 2.1 in the wall z = 4 (south, +z).
    Facade { glazed: bool },
}

/// The black room's OBJ and MTL: walls with a hole written as the four
/// pieces around it, as exporters write them.
fn room(opening: Opening) -> (String, String) {
    let [w, h, d] = ROOM;
    let mut obj = String::from("mtllib room.mtl\n");
    face(
        &mut obj,
        "floor",
        "black",
        [[0.0, 0.0, 0.0], [0.0, 0.0, d], [w, 0.0, d], [w, 0.0, 0.0]],
    );
    face(
        &mut obj,
        "north",
        "black",
        [[0.0, 0.0, 0.0], [w, 0.0, 0.0], [w, h, 0.0], [0.0, h, 0.0]],
    );
    face(
        &mut obj,
        "west",
        "black",
        [[0.0, 0.0, 0.0], [0.0, h, 0.0], [0.0, h, d], [0.0, 0.0, d]],
    );
    face(
        &mut obj,
        "east",
        "black",
        [[w, 0.0, 0.0], [w, 0.0, d], [w, h, d], [w, h, 0.0]],
    );
    let ceiling = |obj: &mut String, name: &str, x: [f64; 2], z: [f64; 2]| {
        face(
            obj,
            name,
            "black",
            [
                [x[0], h, z[0]],
                [x[1], h, z[0]],
                [x[1], h, z[1]],
                [x[0], h, z[1]],
            ],
        );
    };
    let south = |obj: &mut String, name: &str, x: [f64; 2], y: [f64; 2], material: &str| {
        face(
            obj,
            name,
            material,
            [
                [x[0], y[0], d],
                [x[0], y[1], d],
                [x[1], y[1], d],
                [x[1], y[0], d],
            ],
        );
    };
    match opening {
        Opening::Roof => {
            ceiling(&mut obj, "c1", [0.0, w], [0.0, 1.5]);
            ceiling(&mut obj, "c2", [0.0, w], [2.5, d]);
            ceiling(&mut obj, "c3", [0.0, 1.5], [1.5, 2.5]);
            ceiling(&mut obj, "c4", [2.5, w], [1.5, 2.5]);
            south(&mut obj, "south", [0.0, w], [0.0, h], "black");
        }
        Opening::Facade { glazed } => {
            ceiling(&mut obj, "ceiling", [0.0, w], [0.0, d]);
            south(&mut obj, "s1", [0.0, w], [0.0, 0.9], "black");
            south(&mut obj, "s2", [0.0, w], [2.1, h], "black");
            south(&mut obj, "s3", [0.0, 1.0], [0.9, 2.1], "black");
            south(&mut obj, "s4", [3.0, w], [0.9, 2.1], "black");
            if glazed {
                south(&mut obj, "pane", [1.0, 3.0], [0.9, 2.1], "glass");
            }
        }
    }
    let mtl = "newmtl black\nKd 0 0 0\nnewmtl glass\nKd 0 0 0\nTf 0.8 0.8 0.8\n".to_owned();
    (obj, mtl)
}

/// The scene written to a folder: room.obj, room.mtl and room.toml with
/// `tables` (the `[sky]` and `[sun]`).
fn write_scene(dir: &Path, obj: &str, mtl: &str, tables: &str) -> PathBuf {
    std::fs::write(dir.join("room.obj"), obj).unwrap();
    std::fs::write(dir.join("room.mtl"), mtl).unwrap();
    let path = dir.join("room.toml");
    std::fs::write(&path, format!("obj = \"room.obj\"\n{tables}")).unwrap();
    path
}

/// Illuminance (lux) probed by final gather at `points` on the floor.
fn floor_lux(path: &Path, points: &[DVec3]) -> Vec<f64> {
    let loaded = load_scene(path.to_str().unwrap()).unwrap();
    let settings = Settings::from_scene_options(&loaded.options).unwrap();
    let mut solver = Solver::new(loaded.scene, settings).unwrap();
    solver.run();
    let solution = solver.solution(Ambient::Everywhere, &silent);
    points
        .iter()
        .map(|&position| {
            let point = ProbePoint {
                position,
                normal: Some(DVec3::Y),
                line: 0,
            };
            let probe = solution.probe(&point, ProbeMode::Gather).unwrap();
            probe.irradiance.luminance() * 179.0
        })
        .collect()
}

/// The CIE overcast sky: L = L_z (1 + 2 sin γ) / 3 (Moon & Spencer).
fn overcast(direction: DVec3) -> f64 {
    ZENITH * (1.0 + 2.0 * direction.y) / 3.0
}

/// The CIE clear sky of 1973 (ISO 15469 type 12) for the sun at
/// (altitude 40°, azimuth 160° from north = −z, clockwise through east =
/// +x): L = L_z f(χ) φ(Z) / (f(Z_s) φ(0)), with
/// f(χ) = 0.91 + 10 e^(−3χ) + 0.45 cos² χ, φ(Z) = 1 − e^(−0.32 / cos Z).
fn clear(direction: DVec3) -> f64 {
    let (altitude, azimuth) = (40_f64.to_radians(), 160_f64.to_radians());
    let sun = DVec3::new(
        altitude.cos() * azimuth.sin(),
        altitude.sin(),
        -altitude.cos() * azimuth.cos(),
    );
    let chi = direction.dot(sun).clamp(-1.0, 1.0).acos();
    let zenith_sun = PI / 2.0 - altitude;
    let f = |x: f64| 0.91 + 10.0 * (-3.0 * x).exp() + 0.45 * x.cos().powi(2);
    let phi = |cos_z: f64| 1.0 - (-0.32 / cos_z).exp();
    ZENITH * f(chi) * phi(direction.y) / (f(zenith_sun) * phi(1.0))
}

/// Transmittance of a clear pane (index 1.52) of transmittance `tn` at
/// normal incidence, at incidence cos θ: the two polarisations' Fresnel
/// reflectances r, the path's transmissivity t^(1/cos θ_t), and the
/// inter-reflections between the faces, (1 − r)² t / (1 − r² t²), averaged.
fn pane(tn: f64, cos_i: f64) -> f64 {
    let n = 1.52;
    let cos_t = (1.0 - (1.0 - cos_i * cos_i) / (n * n)).sqrt();
    let rs = ((cos_i - n * cos_t) / (cos_i + n * cos_t)).powi(2);
    let rp = ((cos_t - n * cos_i) / (cos_t + n * cos_i)).powi(2);
    // The transmissivity t_n that gives tn at normal incidence.
    let r0 = ((n - 1.0) / (n + 1.0)).powi(2);
    let through = |r: f64, t: f64| (1.0 - r).powi(2) * t / (1.0 - r * r * t * t);
    let (mut low, mut high) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (low + high);
        if through(r0, mid) < tn {
            low = mid
        } else {
            high = mid
        }
    }
    let t = low.powf(1.0 / cos_t);
    0.5 * (through(rs, t) + through(rp, t))
}

/// ∫ L(ω) τ(ω) cos θ dω at floor point `x` over the opening `corner` +
/// s·`a` + t·`b` (s, t in [0, 1]) of unit normal `normal`, lux: a 400 ×
/// 400 midpoint rule of L cos θ_p cos θ_o / r² dA.
fn sky_component(
    x: DVec3,
    corner: DVec3,
    a: DVec3,
    b: DVec3,
    normal: DVec3,
    sky: &dyn Fn(DVec3) -> f64,
    tn: Option<f64>,
) -> f64 {
    let n = 400;
    let area = a.cross(b).length() / (n * n) as f64;
    let mut sum = 0.0;
    for i in 0..n {
        for j in 0..n {
            let p = corner + a * ((i as f64 + 0.5) / n as f64) + b * ((j as f64 + 0.5) / n as f64);
            let d = p - x;
            let r2 = d.length_squared();
            let dir = d / r2.sqrt();
            let (cos_p, cos_o) = (dir.y, dir.dot(normal).abs());
            let tau = tn.map_or(1.0, |tn| pane(tn, cos_o));
            sum += sky(dir) * tau * cos_p * cos_o / r2 * area;
        }
    }
    sum
}

/// Floor points: a 5 × 5 grid over the room.
fn floor_points() -> Vec<DVec3> {
    let mut points = Vec::new();
    for i in 0..5 {
        for k in 0..5 {
            points.push(DVec3::new(0.4 + 0.8 * i as f64, 0.0, 0.4 + 0.8 * k as f64));
        }
    }
    points
}

/// The worst relative difference of `got` from `want`.
fn worst(got: &[f64], want: &[f64]) -> f64 {
    got.iter()
        .zip(want)
        .map(|(g, w)| (g / w - 1.0).abs())
        .fold(0.0, f64::max)
}

const OVERCAST: &str =
    "[sky]\nmodel = \"cie_overcast\"\nzenith_luminance = 5000.0\nground_reflectance = 0.0\n";
const CLEAR: &str = "[sky]\nmodel = \"cie_clear\"\nzenith_luminance = 5000.0\nground_reflectance = 0.0\n\
                     [sun]\naltitude_deg = 40.0\nazimuth_deg = 160.0\nnormal_illuminance = 0.0\n";

fn check_opening(opening: Opening, tables: &str, sky: &dyn Fn(DVec3) -> f64) {
    let dir = tempfile::tempdir().unwrap();
    let (obj, mtl) = room(opening);
    let path = write_scene(dir.path(), &obj, &mtl, tables);
    let points = floor_points();
    let got = floor_lux(&path, &points);
    let (corner, a, b, normal, tn) = match opening {
        Opening::Roof => (
            DVec3::new(1.5, 3.0, 1.5),
            DVec3::X,
            DVec3::Z,
            DVec3::Y,
            None,
        ),
        Opening::Facade { glazed } => (
            DVec3::new(1.0, 0.9, 4.0),
            DVec3::X * 2.0,
            DVec3::Y * 1.2,
            DVec3::Z,
            glazed.then_some(0.8),
        ),
    };
    let want: Vec<f64> = points
        .iter()
        .map(|&x| sky_component(x, corner, a, b, normal, sky, tn))
        .collect();
    let error = worst(&got, &want);
    let place = match opening {
        Opening::Roof => "roof opening",
        Opening::Facade { glazed: false } => "facade opening",
        Opening::Facade { glazed: true } => "glazed facade",
    };
    let sky = if tables.contains("cie_clear") {
        "clear"
    } else {
        "overcast"
    };
    eprintln!(
        "{place}, {sky} sky: worst {:.3} % over {} points",
        100.0 * error,
        got.len()
    );
    assert!(
        error < 0.005,
        "worst {:.3} %: got {got:?}, want {want:?}",
        100.0 * error
    );
}

#[test]
fn roof_opening_under_the_overcast_sky() {
    check_opening(Opening::Roof, OVERCAST, &overcast);
}

#[test]
fn roof_opening_under_the_clear_sky() {
    check_opening(Opening::Roof, CLEAR, &clear);
}

#[test]
fn facade_opening_under_the_overcast_sky() {
    check_opening(Opening::Facade { glazed: false }, OVERCAST, &overcast);
}

#[test]
fn facade_opening_under_the_clear_sky() {
    check_opening(Opening::Facade { glazed: false }, CLEAR, &clear);
}

#[test]
fn glazed_facade_under_the_overcast_sky() {
    check_opening(Opening::Facade { glazed: true }, OVERCAST, &overcast);
}

#[test]
fn glazed_facade_under_the_clear_sky() {
    check_opening(Opening::Facade { glazed: true }, CLEAR, &clear);
}

/// A lone square of side 10 m at the origin, facing `normal` (+y or +x).
fn lone_square(normal: DVec3) -> String {
    let mut obj = String::from("mtllib room.mtl\n");
    let corners = if normal == DVec3::Y {
        [
            [-5.0, 0.0, -5.0],
            [-5.0, 0.0, 5.0],
            [5.0, 0.0, 5.0],
            [5.0, 0.0, -5.0],
        ]
    } else {
        [
            [0.0, -5.0, -5.0],
            [0.0, 5.0, -5.0],
            [0.0, 5.0, 5.0],
            [0.0, -5.0, 5.0],
        ]
    };
    face(&mut obj, "plane", "grey", corners);
    obj
}

/// Illuminance (lux) at the centre of a lone square facing `normal`.
fn open_plane_lux(tables: &str, normal: DVec3) -> f64 {
    let dir = tempfile::tempdir().unwrap();
    let path = write_scene(
        dir.path(),
        &lone_square(normal),
        "newmtl grey\nKd 0.5 0.5 0.5\n",
        tables,
    );
    let loaded = load_scene(path.to_str().unwrap()).unwrap();
    let settings = Settings::from_scene_options(&loaded.options).unwrap();
    let mut solver = Solver::new(loaded.scene, settings).unwrap();
    solver.run();
    let solution = solver.solution(Ambient::Everywhere, &silent);
    let point = ProbePoint {
        position: DVec3::ZERO,
        normal: Some(normal),
        line: 0,
    };
    let probe = solution.probe(&point, ProbeMode::Gather).unwrap();
    probe.irradiance.luminance() * 179.0
}

/// Every sky gives the unobstructed horizontal plane the illuminance its
/// file asks for, within 0.5 %.
#[test]
fn every_sky_gives_the_open_plane_its_horizontal_illuminance() {
    let sun = "[sun]\naltitude_deg = 35.0\nazimuth_deg = 200.0\nnormal_illuminance = 0.0\n";
    let mut skies: Vec<String> = ["cie_overcast", "uniform"]
        .iter()
        .map(|m| format!("model = \"{m}\"\n"))
        .collect();
    for m in ["cie_clear", "cie_intermediate"] {
        skies.push(format!("model = \"{m}\"\n{sun}"));
    }
    for t in 1..=15 {
        skies.push(format!("model = \"cie_general\"\ntype = {t}\n{sun}"));
    }
    for sky in skies {
        let (model, sun) = sky
            .split_once("[sun]")
            .map_or((sky.as_str(), ""), |(m, s)| (m, s));
        let tables = format!(
            "[sky]\n{model}horizontal_illuminance = 12000.0\n{}",
            if sun.is_empty() {
                String::new()
            } else {
                format!("[sun]{sun}")
            }
        );
        let lux = open_plane_lux(&tables, DVec3::Y);
        eprintln!(
            "{}: {:+.4} %",
            model.replace('\n', " "),
            100.0 * (lux / 12_000.0 - 1.0)
        );
        assert!((lux / 12_000.0 - 1.0).abs() < 0.005, "{model}: {lux} lx");
    }
}

/// A vertical plane under the overcast sky with its ground:
/// E_v = L_z (π/6 + 4/9) from the sky (2 ∫ L(γ) cos² γ dγ) plus ρ_g E_h / 2
/// from the ground of luminance ρ_g E_h / π.
#[test]
fn the_open_vertical_plane_sees_sky_and_ground() {
    let tables =
        "[sky]\nmodel = \"cie_overcast\"\nzenith_luminance = 5000.0\nground_reflectance = 0.3\n";
    let lux = open_plane_lux(tables, DVec3::X);
    let e_h = 7.0 * PI * ZENITH / 9.0;
    let want = ZENITH * (PI / 6.0 + 4.0 / 9.0) + 0.3 * e_h / 2.0;
    assert!(
        (lux / want - 1.0).abs() < 0.005,
        "{lux} lx against {want} lx"
    );
}

/// `isorad grid --daylight-factor`: DF = 100 E / E_h under the overcast
/// sky whatever the file's sky, its statistics, and the same DF for any
/// horizontal illuminance.
#[test]
fn the_daylight_factor_grid_is_the_overcast_sky_over_its_illuminance() {
    let dir = tempfile::tempdir().unwrap();
    let (obj, mtl) = room(Opening::Roof);
    let clear = "[sky]\nmodel = \"cie_clear\"\nhorizontal_illuminance = 25000.0\nground_reflectance = 0.0\n\
                 [sun]\naltitude_deg = 40.0\nazimuth_deg = 160.0\nnormal_illuminance = 80000.0\n";
    let path = write_scene(dir.path(), &obj, &mtl, clear);
    let csv = dir.path().join("df.csv");
    let out = crate::cli::isorad(
        dir.path(),
        &[
            "grid",
            path.to_str().unwrap(),
            "--surface",
            "floor",
            "--spacing",
            "0.8",
            "--daylight-factor",
            "--csv",
            csv.to_str().unwrap(),
            "-q",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(
        text.contains("x,y,z,daylight_factor_percent,status"),
        "{text}"
    );
    for key in [
        "DFmin",
        "DFavg",
        "DFmedian",
        "DFmax",
        "U0 = DFmin/DFavg",
        "share >= 2 %",
        "sky = CIE standard overcast",
    ] {
        assert!(text.contains(key), "{key} missing: {text}");
    }
    // Under the overcast sky of the same E_h, DF is the sky component over
    // E_h = 7π L_z / 9 (the ground is black).
    let e_h = 7.0 * PI * ZENITH / 9.0;
    let scale = ZENITH / overcast(DVec3::Y);
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('x'))
    {
        let v: Vec<&str> = line.split(',').collect();
        let x = DVec3::new(v[0].parse().unwrap(), 0.0, v[2].parse().unwrap());
        let df: f64 = v[3].parse().unwrap();
        let sky = |d: DVec3| overcast(d) * scale;
        let want = 100.0
            * sky_component(
                x,
                DVec3::new(1.5, 3.0, 1.5),
                DVec3::X,
                DVec3::Z,
                DVec3::Y,
                &sky,
                None,
            )
            / e_h;
        assert!(
            (df / want - 1.0).abs() < 0.01,
            "DF {df} % against {want} % at {x}"
        );
    }
}

/// A scene file's `[sky]` and `[sun]` mistakes name the file, the line and
/// the key.
#[test]
fn sky_and_sun_mistakes_name_file_line_and_key() {
    let dir = tempfile::tempdir().unwrap();
    let (obj, mtl) = room(Opening::Roof);
    let cases = [
        ("[sky]\nmodel = \"cie_cloudy\"\n", Some(3), "model"),
        ("[sky]\nmodel = \"cie_general\"\n", None, "type"),
        (
            "[sky]\nmodel = \"cie_general\"\ntype = 16\n",
            Some(4),
            "type",
        ),
        (
            "[sky]\nmodel = \"cie_overcast\"\ntype = 3\n",
            Some(4),
            "type",
        ),
        (
            "[sky]\nmodel = \"uniform\"\nhorizontal_illuminance = 100.0\nzenith_luminance = 50.0\n",
            Some(5),
            "zenith_luminance",
        ),
        (
            "[sky]\nmodel = \"uniform\"\nhorizontal_illuminance = -1.0\n",
            Some(4),
            "horizontal_illuminance",
        ),
        (
            "[sky]\nmodel = \"uniform\"\nground_reflectance = 1.0\n",
            Some(4),
            "ground_reflectance",
        ),
        (
            "[sky]\nmodel = \"uniform\"\nnorth = [0.0, 1.0, 0.0]\n",
            Some(4),
            "north",
        ),
        ("[sky]\nmodel = \"cie_clear\"\n", Some(3), "model"),
        (
            "[sun]\naltitude_deg = 30.0\nazimuth_deg = 180.0\nnormal_illuminance = 1.0\n",
            None,
            "(table)",
        ),
        (
            "[sky]\nmodel = \"cie_clear\"\n[sun]\naltitude_deg = 30.0\nnormal_illuminance = 1.0\n",
            None,
            "altitude_deg",
        ),
        (
            "[sky]\nmodel = \"cie_clear\"\n[sun]\naltitude_deg = 30.0\nazimuth_deg = 180.0\n",
            None,
            "normal_illuminance",
        ),
        (
            "[sky]\nmodel = \"cie_clear\"\n[sun]\naltitude_deg = 95.0\nazimuth_deg = 180.0\nnormal_illuminance = 1.0\n",
            Some(5),
            "altitude_deg",
        ),
        (
            "[sky]\nmodel = \"cie_clear\"\n[sun]\nlatitude = 48.0\nlongitude = 2.0\ntime = \"2026-06-21T12:00\"\nnormal_illuminance = 1.0\n",
            Some(7),
            "time",
        ),
    ];
    for (tables, line, key) in cases {
        let path = write_scene(dir.path(), &obj, &mtl, tables);
        let error = load_scene(path.to_str().unwrap())
            .err()
            .unwrap_or_else(|| panic!("{tables} loaded"))
            .to_string();
        let place = line.map_or("room.toml:".to_owned(), |line| {
            format!("room.toml:{line}: [")
        });
        assert!(
            error.contains(&place) && error.contains(&format!("] {key} = ")),
            "{tables}: {error}"
        );
    }
    // An unknown key is refused by the TOML reader, with its line.
    let path = write_scene(
        dir.path(),
        &obj,
        &mtl,
        "[sky]\nmodel = \"uniform\"\nbrightness = 2.0\n",
    );
    let error = load_scene(path.to_str().unwrap())
        .err()
        .unwrap()
        .to_string();
    assert!(
        error.contains("line 4") && error.contains("brightness"),
        "{error}"
    );
}

/// `[glazing]` makes a material glazing by name: the glazed façade of a
/// pane whose MTL has no `Tf` reads as the one with `Tf 0.8`; a name no
/// material has, or a transmittance of 1, is refused with its line.
#[test]
fn glazing_by_name_in_the_scene_file() {
    let dir = tempfile::tempdir().unwrap();
    let (obj, _) = room(Opening::Facade { glazed: true });
    let plain = "newmtl black\nKd 0 0 0\nnewmtl glass\nKd 0.5 0.5 0.5\nd 0.2\n";
    let tables = format!("{OVERCAST}[glazing]\nglass = 0.8\n");
    let path = write_scene(dir.path(), &obj, plain, &tables);
    let points = [DVec3::new(2.0, 0.0, 2.0), DVec3::new(0.8, 0.0, 3.2)];
    let by_name = floor_lux(&path, &points);
    let (_, with_tf) = room(Opening::Facade { glazed: true });
    let path = write_scene(dir.path(), &obj, &with_tf, OVERCAST);
    let by_tf = floor_lux(&path, &points);
    assert!(
        worst(&by_name, &by_tf) < 1e-9,
        "{by_name:?} against {by_tf:?}"
    );
    for (glazing, line) in [
        ("[glazing]\nwindow = 0.8\n", 7),
        ("[glazing]\nglass = 1.0\n", 7),
    ] {
        let path = write_scene(dir.path(), &obj, plain, &format!("{OVERCAST}{glazing}"));
        let error = load_scene(path.to_str().unwrap())
            .err()
            .unwrap()
            .to_string();
        assert!(
            error.contains(&format!("room.toml:{line}: [glazing]")),
            "{error}"
        );
    }
}

/// Renders light a sun patch's edge per pixel: a plate's shadow on a
/// coarsely meshed floor (the sun in the east at 45°, the shadow's edge at
/// x = −2) is sharp, each pixel beside its edge reading what a gather at
/// its point reads.
#[test]
fn renders_draw_the_sun_patch_edge_at_each_pixel() {
    let dir = tempfile::tempdir().unwrap();
    let mut obj = String::from("mtllib room.mtl\n");
    face(
        &mut obj,
        "floor",
        "grey",
        [
            [-5.0, 0.0, -5.0],
            [-5.0, 0.0, 5.0],
            [5.0, 0.0, 5.0],
            [5.0, 0.0, -5.0],
        ],
    );
    face(
        &mut obj,
        "plate",
        "grey",
        [
            [-1.0, 1.0, -1.0],
            [1.0, 1.0, -1.0],
            [1.0, 1.0, 1.0],
            [-1.0, 1.0, 1.0],
        ],
    );
    let tables = "[camera]\nposition = [0.0, 6.0, 0.0]\nlook_at = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, -1.0]\n\
                  vfov_deg = 60.0\nwidth = 200\nheight = 200\n[mesh]\nmax_edge = 0.6\n\
                  [sky]\nmodel = \"uniform\"\nzenith_luminance = 100.0\nground_reflectance = 0.0\n\
                  [sun]\naltitude_deg = 45.0\nazimuth_deg = 90.0\nnormal_illuminance = 50000.0\n";
    let path = write_scene(dir.path(), &obj, "newmtl grey\nKd 0.5 0.5 0.5\n", tables);
    let loaded = load_scene(path.to_str().unwrap()).unwrap();
    let camera = loaded.scene.camera.clone().unwrap();
    let settings = Settings::from_scene_options(&loaded.options).unwrap();
    let mut solver = Solver::new(loaded.scene, settings).unwrap();
    solver.run();
    let solution = solver.solution(Ambient::Everywhere, &silent);
    let image = solution.render(&camera, &isorad::RenderSettings::default());
    // Column c looks at x = (c + 0.5 − 100) / 100 · 6 tan 30° on the floor's
    // centre row (z = 0.015 for row 100).
    let half = 6.0 * 30_f64.to_radians().tan();
    for column in [36, 38, 40, 44, 46, 48] {
        let x = (column as f64 + 0.5 - 100.0) / 100.0 * half;
        let z = 0.5 / 100.0 * half;
        let point = ProbePoint {
            position: DVec3::new(x, 0.0, z),
            normal: Some(DVec3::Y),
            line: 0,
        };
        let probe = solution.probe(&point, ProbeMode::Gather).unwrap();
        let want = probe.radiosity.luminance() / PI;
        let [r, g, b] = image.pixel(column, 100);
        let got = isorad::Rgb::new(r.into(), g.into(), b.into()).luminance();
        // Sunlit, the pixel is the sun's exact light; in the shadow, the
        // mesh's dim sky light, within its interpolation error.
        let tolerance = if x < -2.0 { 0.03 } else { 0.1 };
        assert!(
            (got / want - 1.0).abs() < tolerance,
            "column {column}, x = {x:.3}: pixel {got}, gather {want}"
        );
    }
}
