//! The library as a program embeds it: scenes built in code, a solver driven
//! step by step, stopped and cancelled, its solution queried and rendered,
//! and nothing printed.

use std::fmt::Write as _;
use std::path::Path;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use glam::DVec3;
use isorad::{
    Ambient, Camera, Error, Length, Material, MeshKind, Phase, PhaseProgress, ProbeMode,
    RenderSettings, Rgb, Scene, Settings, Solver, StopReason, ToneMap, Until, load_scene,
    phase::silent, scene::ProbePoint, write_exr, write_png,
};

/// A room built in code, in coordinates and colours that f32 holds exactly
/// (as an OBJ file does): a 4 × 3 × 4 box open at the front, a light just
/// below the ceiling, a block on the floor. Each entry: object, material,
/// vertices counter-clockwise seen from the front.
fn room_polygons() -> Vec<(&'static str, usize, Vec<DVec3>)> {
    let v = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    let (white, red, light) = (0, 1, 2);
    let mut polygons = vec![
        (
            "floor",
            white,
            vec![v(0., 0., 0.), v(0., 0., 4.), v(4., 0., 4.), v(4., 0., 0.)],
        ),
        (
            "ceiling",
            white,
            vec![v(0., 3., 0.), v(4., 3., 0.), v(4., 3., 4.), v(0., 3., 4.)],
        ),
        (
            "back",
            white,
            vec![v(0., 0., 4.), v(0., 3., 4.), v(4., 3., 4.), v(4., 0., 4.)],
        ),
        (
            "left",
            red,
            vec![v(0., 0., 0.), v(0., 3., 0.), v(0., 3., 4.), v(0., 0., 4.)],
        ),
        (
            "right",
            white,
            vec![v(4., 0., 0.), v(4., 0., 4.), v(4., 3., 4.), v(4., 3., 0.)],
        ),
        (
            "light",
            light,
            vec![
                v(1.5, 2.75, 1.5),
                v(2.5, 2.75, 1.5),
                v(2.5, 2.75, 2.5),
                v(1.5, 2.75, 2.5),
            ],
        ),
    ];
    // A block's top and four sides, facing out, 1 m high, at x, z in
    // [1, 2] × [2.25, 3.25].
    let (x0, x1, z0, z1, h) = (1.0, 2.0, 2.25, 3.25, 1.0);
    let block = [
        (
            "block",
            white,
            vec![v(x0, h, z0), v(x1, h, z0), v(x1, h, z1), v(x0, h, z1)],
        ),
        (
            "block",
            white,
            vec![v(x0, 0., z0), v(x1, 0., z0), v(x1, h, z0), v(x0, h, z0)],
        ),
        (
            "block",
            white,
            vec![v(x1, 0., z0), v(x1, 0., z1), v(x1, h, z1), v(x1, h, z0)],
        ),
        (
            "block",
            white,
            vec![v(x1, 0., z1), v(x0, 0., z1), v(x0, h, z1), v(x1, h, z1)],
        ),
        (
            "block",
            white,
            vec![v(x0, 0., z1), v(x0, 0., z0), v(x0, h, z0), v(x0, h, z1)],
        ),
    ];
    for (name, material, mut vertices) in block {
        vertices.reverse();
        polygons.push((name, material, vertices));
    }
    polygons
}

fn room_materials() -> Vec<Material> {
    vec![
        Material::diffuse("white", Rgb::splat(0.75)),
        Material::diffuse("red", Rgb::new(0.625, 0.125, 0.125)),
        Material::emitter("lamp", Rgb::splat(8.0)).with_reflectance(Rgb::splat(0.5)),
    ]
}

fn room_in_code() -> Scene {
    let mut scene = Scene::new();
    for material in room_materials() {
        scene.add_material(material).unwrap();
    }
    for (name, material, vertices) in room_polygons() {
        assert_eq!(
            scene.add_polygon(name, material, &vertices).unwrap().len(),
            1
        );
    }
    scene.set_camera(Camera::look_at(
        DVec3::new(2.0, 1.5, -5.0),
        DVec3::new(2.0, 1.5, 2.0),
        DVec3::Y,
        40.0,
    ));
    scene
}

/// The same room as OBJ + MTL files in `dir`; returns the OBJ's path.
fn write_room_obj(dir: &Path) -> std::path::PathBuf {
    let mut mtl = String::new();
    for m in room_materials() {
        let (kd, ke) = (m.reflectance, m.emitted_radiance);
        writeln!(mtl, "newmtl {}", m.name).unwrap();
        writeln!(mtl, "Kd {} {} {}", kd.r, kd.g, kd.b).unwrap();
        writeln!(mtl, "Ke {} {} {}", ke.r, ke.g, ke.b).unwrap();
    }
    let names: Vec<String> = room_materials().into_iter().map(|m| m.name).collect();
    let mut obj = String::from("mtllib room.mtl\n");
    let mut next_vertex = 1;
    for (index, (name, material, vertices)) in room_polygons().into_iter().enumerate() {
        writeln!(
            obj,
            "o {name}\ng {name}_{index}\nusemtl {}",
            names[material]
        )
        .unwrap();
        for p in &vertices {
            writeln!(obj, "v {} {} {}", p.x, p.y, p.z).unwrap();
        }
        let face: Vec<String> = (next_vertex..next_vertex + vertices.len())
            .map(|i| i.to_string())
            .collect();
        writeln!(obj, "f {}", face.join(" ")).unwrap();
        next_vertex += vertices.len();
    }
    std::fs::write(dir.join("room.mtl"), mtl).unwrap();
    std::fs::write(dir.join("room.obj"), obj).unwrap();
    dir.join("room.obj")
}

fn preview() -> Settings {
    let mut settings = Settings::preview();
    settings.mesh.max_edge = Length::Absolute(0.25);
    settings.solver.tolerance = 0.02;
    settings
}

#[test]
fn a_scene_built_in_code_and_loaded_from_obj_solve_identically() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write_room_obj(dir.path());
    let loaded = load_scene(obj.to_str().unwrap()).unwrap().scene;
    let built = room_in_code();
    assert!(built.warnings.is_empty() && loaded.warnings.is_empty());
    assert_eq!(built.materials, loaded.materials);
    let geometry = |s: &Scene| -> Vec<Vec<DVec3>> {
        s.surfaces.iter().map(|s| s.vertices().to_vec()).collect()
    };
    assert_eq!(geometry(&built), geometry(&loaded));

    let mut solvers = [built, loaded].map(|scene| Solver::new(scene, preview()).unwrap());
    for solver in &mut solvers {
        assert_eq!(solver.run(), StopReason::Converged);
    }
    let [a, b] = &solvers;
    assert_eq!(a.stats().shots, b.stats().shots);
    assert_eq!(a.radiosity().len(), b.radiosity().len());
    let worst = a
        .radiosity()
        .iter()
        .zip(b.radiosity())
        .map(|(x, y)| (*x - y).abs().max_element())
        .fold(0.0, f64::max);
    assert!(worst <= 1e-12, "largest radiosity difference {worst}");
}

#[test]
fn the_phases_outside_the_shots_report_their_progress_in_order() {
    let reports = Mutex::new(Vec::new());
    let record = |p: PhaseProgress| reports.lock().unwrap().push(p);
    let mut solver = Solver::new_with_progress(room_in_code(), preview(), &record).unwrap();
    let prepared = reports.lock().unwrap().len();
    solver.run();
    assert_eq!(
        reports.lock().unwrap().len(),
        prepared,
        "shots report elsewhere"
    );
    let solution = solver.solution(Ambient::Everywhere, &record);
    let reports = reports.into_inner().unwrap();

    // Each phase once, in the order it runs, from 0 to its total.
    let mut order: Vec<Phase> = reports.iter().map(|p| p.phase).collect();
    order.dedup();
    let expected = [
        Phase::ClosedRooms,
        Phase::ShadowBoundaries,
        Phase::Meshing,
        Phase::AmbientTerm,
    ];
    assert_eq!(order, expected);
    let surfaces = solver.scene().surfaces.len();
    let vertices = solver.mesh().vertices.len();
    let totals = [1, surfaces, surfaces + 1, vertices];
    for (phase, total) in expected.into_iter().zip(totals) {
        let seen: Vec<&PhaseProgress> = reports.iter().filter(|p| p.phase == phase).collect();
        assert!(seen.iter().all(|p| p.total == total), "{phase:?}: {seen:?}");
        assert_eq!(seen.first().unwrap().done, 0, "{phase:?} starts at 0");
        assert_eq!(seen.last().unwrap().done, total, "{phase:?} ends done");
    }
    // The reporter changes nothing: the same ambient term without one.
    assert_eq!(
        solution.radiosity(),
        solver.solution(Ambient::Everywhere, &silent).radiosity()
    );

    // The contour mesher lays out its receivers between the two.
    let mut contour = preview();
    contour.mesh.kind = MeshKind::Contour;
    let reports = Mutex::new(Vec::new());
    let record = |p: PhaseProgress| reports.lock().unwrap().push(p.phase);
    Solver::new_with_progress(room_in_code(), contour, &record).unwrap();
    let mut order = reports.into_inner().unwrap();
    order.dedup();
    let expected = [
        Phase::ClosedRooms,
        Phase::ShadowBoundaries,
        Phase::ContourLayouts,
        Phase::Meshing,
    ];
    assert_eq!(order, expected);
}

#[test]
fn cancelling_half_way_leaves_a_balanced_solution_that_can_resume() {
    let mut solver = Solver::new(room_in_code(), preview()).unwrap();
    let cancel = AtomicBool::new(false);
    let until = Until::default().tolerance(1e-4).cancelled_by(&cancel);
    let mut seen = Vec::new();
    let stop = solver.run_until(&until, |progress| {
        seen.push(progress.shots);
        if progress.shots == 25 {
            cancel.store(true, Ordering::Relaxed);
        }
    });
    assert_eq!(stop, StopReason::Cancelled);
    assert_eq!(solver.stats().shots, 25);
    assert_eq!(seen, (1..=25).collect::<Vec<_>>());
    let unshot = solver.unshot_fraction();
    assert!(unshot > 0.02, "stopped half-way: unshot {unshot}");
    let e = solver.energy_balance();
    let imbalance = (e.absorbed + e.unshot + e.escaped - e.emitted)
        .abs()
        .max_element();
    assert!(imbalance < 1e-9 * e.emitted.max_element(), "{e:?}");
    // The ambient term stands in for the unshot light: the ambient solution
    // is brighter everywhere, by the same vertex count.
    let (plain, ambient) = (
        solver.solution(Ambient::Omitted, &silent),
        solver.solution(Ambient::Everywhere, &silent),
    );
    assert_eq!(plain.radiosity().len(), ambient.radiosity().len());
    assert!(
        plain
            .radiosity()
            .iter()
            .zip(&ambient.radiosity())
            .all(|(p, a)| a.r >= p.r && a.g >= p.g && a.b >= p.b)
    );
    // The flag still set, nothing more is shot; cleared, the solve resumes.
    assert_eq!(solver.run_until(&until, |_| {}), StopReason::Cancelled);
    cancel.store(false, Ordering::Relaxed);
    assert_eq!(solver.run(), StopReason::Converged);
    assert!(solver.stats().shots > 25 && solver.convergence_fraction() <= 0.02);
    // Converged, it shot what was left patch to patch; cancelled, it did not.
    assert!(solver.patch_shot_summary().is_some());
}

#[test]
fn run_until_stops_on_shots_time_and_nothing_left() {
    let mut solver = Solver::new(room_in_code(), preview()).unwrap();
    let stop = solver.run_until(&Until::default().time_budget(Duration::ZERO), |_| {});
    assert_eq!((stop, solver.stats().shots), (StopReason::TimeBudget, 0));
    let stop = solver.run_until(&Until::default().total_shots(7), |_| {});
    assert_eq!((stop, solver.stats().shots), (StopReason::ShotLimit, 7));
    assert!(solver.step());
    assert_eq!(solver.stats().shots, 8);
    // A tolerance of zero runs until no patch holds any unshot power; a
    // shot limit stands in for that here.
    let stop = solver.run_until(&Until::default().tolerance(0.0).total_shots(30), |_| {});
    assert_eq!((stop, solver.stats().shots), (StopReason::ShotLimit, 30));
}

/// A run that stops gives back its shot buffers; resumed, it makes them
/// again and shoots exactly the light one run would.
#[test]
fn a_run_stopped_and_resumed_shoots_the_light_of_one_run() {
    let until = |shots: usize| Until::default().tolerance(0.0).total_shots(shots);
    let mut resumed = Solver::new(room_in_code(), preview()).unwrap();
    resumed.run_until(&until(3), |_| {});
    resumed.run_until(&until(12), |_| {});
    let mut whole = Solver::new(room_in_code(), preview()).unwrap();
    whole.run_until(&until(12), |_| {});
    assert_eq!(resumed.stats().shots, whole.stats().shots);
    for (a, b) in resumed.radiosity().iter().zip(whole.radiosity()) {
        assert!(
            (*a - b).abs().max_element() <= 1e-12 * b.max_element().max(1.0),
            "{a:?} {b:?}"
        );
    }
}

/// The absorbed power the surface totals of `solution` show, Σ (1 − ρ) ×
/// received power.
fn absorbed_in_totals(solution: &isorad::Solution<'_>, scene: &isorad::Scene) -> Rgb {
    solution
        .surface_totals()
        .iter()
        .zip(&scene.surfaces)
        .map(|(t, s)| (Rgb::ONE - scene.material_of(s).reflectance) * t.received_power)
        .sum()
}

/// After patch shots the ledger counts what they gave the patches, which
/// the image's ambient term gathers at the vertices: the totals of the
/// solution with the term show the ledger's absorbed power, the light
/// shot at the vertices alone less.
#[test]
fn surface_totals_with_the_ambient_term_close_the_ledger_after_patch_shots() {
    let mut solver = Solver::new(room_in_code(), preview()).unwrap();
    solver.run();
    let summary = solver.patch_shot_summary().expect("patch shots");
    assert!(summary.unshot_after <= 0.01 && summary.unshot_before > 0.01);
    let scene = solver.scene();
    let ledger = solver.energy_balance().absorbed;
    let gathered = absorbed_in_totals(&solver.solution(Ambient::Everywhere, &silent), scene);
    let shot = absorbed_in_totals(&solver.solution(Ambient::Omitted, &silent), scene);
    println!("absorbed: ledger {ledger}, with the term {gathered}, vertex shots {shot}");
    assert!(
        (gathered - ledger).abs().max_element() < 0.01 * ledger.max_element(),
        "{gathered} vs {ledger}"
    );
    assert!((shot - ledger).abs().max_element() > 0.01 * ledger.max_element());
}

#[test]
fn surface_totals_close_the_energy_ledger() {
    // The vertices' shots alone, which the totals of the mesh show.
    let mut settings = preview();
    settings.solver.patch_tolerance = 1.0;
    let mut solver = Solver::new(room_in_code(), settings).unwrap();
    solver.run();
    let solution = solver.solution(Ambient::Omitted, &silent);
    let totals = solution.surface_totals();
    let scene = solver.scene();
    assert_eq!(totals.len(), scene.surfaces.len());
    // Absorbed power: Σ (1 − ρ) × received power over surfaces. The totals
    // integrate the shaded mesh (the corners' means); the ledger counts the
    // emitters' light with its curvature (`solver/element_power.rs`), which
    // the corners' means miss: they differ by that discretisation error,
    // 0.2 % in this room.
    let absorbed: Rgb = totals
        .iter()
        .zip(&scene.surfaces)
        .map(|(t, s)| (Rgb::ONE - scene.material_of(s).reflectance) * t.received_power)
        .sum();
    let ledger = solver.energy_balance().absorbed;
    assert!(
        (absorbed - ledger).abs().max_element() < 0.01 * ledger.max_element(),
        "{absorbed} vs {ledger}"
    );
    // Per surface: B = E + ρ H holds for the means too.
    for (t, s) in totals.iter().zip(&scene.surfaces) {
        let m = scene.material_of(s);
        let expected = m.emitted_radiosity() + m.reflectance * t.mean_irradiance;
        assert!(
            (t.mean_radiosity - expected).abs().max_element()
                < 1e-9 * expected.max_element().max(1.0)
        );
        assert!(t.area > 0.0 && t.area <= s.area() * (1.0 + 1e-9));
    }
    // The floor loses the block's footprint (1 × 1) to the contact cut-out.
    assert!(
        (totals[0].area - 15.0).abs() < 1e-9,
        "floor area {}",
        totals[0].area
    );
}

#[test]
fn a_solution_renders_to_an_image_the_caller_owns() {
    let mut solver = Solver::new(room_in_code(), preview()).unwrap();
    solver.run();
    let solution = solver.solution(Ambient::Everywhere, &silent);
    let triangles = solution.triangles();
    let mesh = solver.mesh();
    assert!(triangles.len() >= mesh.elements.len());
    let mut camera = solver.scene().camera_or_default();
    (camera.width, camera.height) = (64, 48);
    let image = solution.render(&camera, &RenderSettings::default());
    assert_eq!((image.width(), image.height()), (64, 48));
    // The centre pixel looks at the lit back wall: its radiance is the
    // mesh's value there, B/π, within Gouraud's interpolation.
    let probe = solution
        .probe(
            &ProbePoint {
                position: DVec3::new(2.0, 1.5, 4.0),
                normal: None,
                line: 1,
            },
            ProbeMode::Mesh,
        )
        .unwrap();
    let [r, g, b] = image.pixel(32, 24);
    let pixel = Rgb::new(f64::from(r), f64::from(g), f64::from(b));
    let expected = probe.radiosity / std::f64::consts::PI;
    assert!(
        (pixel - expected).abs().max_element() < 0.05 * expected.max_element(),
        "{pixel} vs {expected}"
    );
}

#[test]
fn scenes_built_in_code_get_the_loaders_errors_and_warnings() {
    let mut scene = Scene::new();
    let bright = Material::diffuse("too bright", Rgb::new(1.0, 0.5, 0.5));
    let Err(Error::InvalidMaterial {
        material, message, ..
    }) = scene.add_material(bright)
    else {
        panic!("reflectance 1 accepted");
    };
    assert_eq!(material, "too bright");
    assert!(message.contains("below 1"), "{message}");
    let negative = Material::emitter("lamp", Rgb::new(1.0, -1.0, 1.0));
    assert!(matches!(
        scene.add_material(negative),
        Err(Error::InvalidMaterial { .. })
    ));
    let white = scene
        .add_material(Material::diffuse("white", Rgb::splat(0.5)))
        .unwrap();
    let square = |z: f64| {
        vec![
            DVec3::new(0.0, 0.0, z),
            DVec3::new(1.0, 0.0, z),
            DVec3::new(1.0, 1.0, z),
            DVec3::new(0.0, 1.0, z),
        ]
    };
    let mut nan = square(0.0);
    nan[2].y = f64::NAN;
    let Err(Error::NonFiniteCoordinate { object, .. }) = scene.add_polygon("wall", white, &nan)
    else {
        panic!("NaN accepted");
    };
    assert_eq!(object, "wall");
    assert!(matches!(
        scene.add_polygon("wall", 7, &square(0.0)),
        Err(Error::MissingMaterial { .. })
    ));
    // Degenerate: skipped with a warning; clearly non-planar: split in two.
    let line = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
    assert!(
        scene
            .add_polygon("sliver", white, &line)
            .unwrap()
            .is_empty()
    );
    let mut bent = square(0.0);
    bent[2].z = 0.5;
    assert_eq!(scene.add_polygon("bent", white, &bent).unwrap().len(), 2);
    assert_eq!(scene.warnings.len(), 2, "{:?}", scene.warnings);
    assert!(scene.warnings[0].message.contains("sliver"));
    // Nothing emits: the solver refuses, as the loader would.
    let Err(error) = Solver::new(scene, Settings::default()) else {
        panic!("a scene without an emitter solved");
    };
    assert!(matches!(error, Error::EmptyScene { .. }), "{error}");
    assert!(error.to_string().contains("no emitter"), "{error}");
}

#[test]
fn settings_presets_are_valid_and_ordered() {
    let (preview, default, last) = (
        Settings::preview(),
        Settings::default(),
        Settings::final_quality(),
    );
    for s in [&preview, &default, &last] {
        s.validate().unwrap();
    }
    assert!(preview.solver.tolerance > default.solver.tolerance);
    assert!(default.solver.tolerance > last.solver.tolerance);
    let edge = |s: &Settings| s.mesh.max_edge.resolve(1.0);
    assert!(edge(&preview) > edge(&default) && edge(&default) > edge(&last));
    let mut bad = Settings::default();
    bad.mesh.max_edge = Length::Absolute(-1.0);
    assert!(matches!(bad.validate(), Err(Error::InvalidSetting { .. })));
}

/// Set in the child process that [`the_library_prints_nothing`] starts.
const QUIET_CHILD: &str = "ISORAD_QUIET_CHILD";
const BEGIN: &str = "<<library work begins>>";
const END: &str = "<<library work ends>>";

/// Everything a program might call, warnings included, between markers on
/// stdout and stderr; run in a child process whose output is checked.
fn library_work(dir: &Path) {
    use std::io::Write;
    let mark = |text: &str| {
        std::io::stdout()
            .write_all(format!("{text}\n").as_bytes())
            .unwrap();
        std::io::stderr()
            .write_all(format!("{text}\n").as_bytes())
            .unwrap();
    };
    mark(BEGIN);
    // A file whose face is not planar (split, with a warning).
    let obj = write_room_obj(dir);
    let text = std::fs::read_to_string(&obj).unwrap();
    std::fs::write(&obj, text.replacen("v 4 3 4", "v 4 3.75 4", 1)).unwrap();
    let scene = load_scene(obj.to_str().unwrap()).unwrap().scene;
    assert!(!scene.warnings.is_empty());
    let mut settings = preview();
    settings.mesh.kind = isorad::MeshKind::Contour;
    let mut solver = Solver::new(scene, settings).unwrap();
    solver.run_until(&Until::default(), |_| {});
    let solution = solver.solution(Ambient::Everywhere, &silent);
    let _ = solution.surface_totals();
    let point = ProbePoint {
        position: DVec3::new(2.0, 0.0, 1.0),
        normal: None,
        line: 1,
    };
    solution.probe(&point, ProbeMode::Gather).unwrap();
    let mut camera = solver.scene().camera_or_default();
    (camera.width, camera.height) = (32, 32);
    let image = solution.render(&camera, &RenderSettings::default());
    write_exr(&image, &dir.join("out.exr")).unwrap();
    write_png(&image, &ToneMap { exposure: 0.0 }, &dir.join("out.png")).unwrap();
    assert!(load_scene("no such scene").is_err());
    mark(END);
}

#[test]
fn the_library_prints_nothing() {
    if std::env::var_os(QUIET_CHILD).is_some() {
        let dir = tempfile::tempdir().unwrap();
        library_work(dir.path());
        // Leave before the test harness prints its summary.
        std::process::exit(0);
    }
    // The test's name as the harness lists it: its path below the crate.
    let name = format!(
        "{}::the_library_prints_nothing",
        module_path!()
            .split_once("::")
            .map_or("", |(_, module)| module)
    );
    let out = std::process::Command::new(std::env::current_exe().unwrap())
        .args([name.as_str(), "--exact", "--nocapture"])
        .args(["--test-threads", "1"])
        .env(QUIET_CHILD, "1")
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    for (stream, bytes) in [("stdout", &out.stdout), ("stderr", &out.stderr)] {
        let text = String::from_utf8_lossy(bytes);
        let inside = text
            .split_once(BEGIN)
            .and_then(|(_, rest)| rest.split_once(END))
            .map(|(inside, _)| inside.trim().to_owned());
        assert_eq!(inside.as_deref(), Some(""), "{stream}: {text}");
    }
}
