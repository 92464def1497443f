//! Scene loading: OBJ/MTL, scene files and the built-in Cornell box, with
//! every kind of bad input a user can write.

use std::path::{Path, PathBuf};

use glam::DVec3;
use isorad::{
    Error, Length, MeshKind, Rgb, Scene, Settings,
    internals::newell_normal,
    load_scene,
    scene::load_obj,
    solver::{FormFactorKernel, ShootFrom},
};
use tempfile::TempDir;

const MTL: &str = "newmtl white\nKd 0.5 0.5 0.5\n\nnewmtl lamp\nKd 0 0 0\nKe 1 2 3\n";

/// A small lamp quad, so that scenes have an emitter.
const LAMP: &str = "o lamp\nusemtl lamp\nv 0 2 0\nv 0 2 1\nv 1 2 1\nv 1 2 0\nf -4 -3 -2 -1\n";

fn write(dir: &TempDir, name: &str, text: &str) -> PathBuf {
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// An OBJ using `m.mtl` (written with `mtl`), the lamp, then `body`.
fn obj_scene(mtl: &str, body: &str) -> (TempDir, PathBuf, String) {
    let dir = TempDir::new().unwrap();
    write(&dir, "m.mtl", mtl);
    let text = format!("mtllib m.mtl\n{LAMP}{body}");
    let path = write(&dir, "scene.obj", &text);
    (dir, path, text)
}

/// 1-based number of the first line of `text` that contains `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).unwrap() + 1
}

/// Loads and expects an error whose message contains every one of `parts`.
fn expect_error(path: &Path, parts: &[&str]) -> Error {
    let error = match path.extension().and_then(|e| e.to_str()) {
        Some("obj") => load_obj(path).map(|_| ()).unwrap_err(),
        _ => load_scene(path.to_str().unwrap()).map(|_| ()).unwrap_err(),
    };
    let message = error.to_string();
    for part in parts {
        assert!(message.contains(part), "`{message}` lacks `{part}`");
    }
    error
}

fn white_quad(name: &str) -> String {
    format!("o {name}\nusemtl white\nv 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf -4 -3 -2 -1\n")
}

// ---- Bad OBJ and MTL input -------------------------------------------------

#[test]
fn malformed_obj_line_is_named() {
    let body = "o box\nusemtl white\nv 0 0 0\nv 1 0 x\nv 1 1 0\nf -3 -2 -1\n";
    let (_dir, path, text) = obj_scene(MTL, body);
    let line = line_of(&text, "v 1 0 x");
    let e = expect_error(&path, &[&format!("scene.obj:{line}")]);
    assert!(matches!(e, Error::ObjParse { .. }));
}

#[test]
fn face_index_out_of_range_is_named() {
    let body = "o box\nusemtl white\nv 0 0 0\nf -1 -2 99\n";
    let (_dir, path, text) = obj_scene(MTL, body);
    let line = line_of(&text, "f -1 -2 99");
    expect_error(&path, &[&format!("scene.obj:{line}"), "99"]);
}

#[test]
fn nan_and_inf_vertices_are_named() {
    for bad in ["nan", "inf", "-infinity", "1e39"] {
        let body = format!("o bad_box\nusemtl white\nv 0 0 0\nv 1 {bad} 0\nv 1 1 0\nf -3 -2 -1\n");
        let (_dir, path, text) = obj_scene(MTL, &body);
        let line = line_of(&text, &format!("v 1 {bad} 0"));
        let e = expect_error(
            &path,
            &[&format!("scene.obj:{line}"), "bad_box", "non-finite"],
        );
        assert!(matches!(e, Error::NonFiniteCoordinate { .. }), "{bad}");
    }
}

#[test]
fn reflectance_of_one_or_below_zero_is_refused() {
    for kd in ["1.0 0.5 0.5", "0.5 -0.1 0.5", "0.5 0.5 nan"] {
        let mtl = format!("newmtl white\nKd {kd}\n\nnewmtl lamp\nKe 1 1 1\n");
        let (_dir, path, _) = obj_scene(&mtl, &white_quad("floor"));
        let e = expect_error(&path, &["m.mtl:2", "`white`", "Kd"]);
        assert!(matches!(e, Error::InvalidMaterial { .. }), "{kd}");
    }
}

#[test]
fn negative_emission_is_refused() {
    let mtl = "newmtl white\nKd 0.5 0.5 0.5\nnewmtl lamp\nKe 1 -1 1\n";
    let (_dir, path, _) = obj_scene(mtl, "");
    expect_error(&path, &["m.mtl:4", "`lamp`", "negative"]);
}

#[test]
fn short_colour_is_an_error_not_a_panic() {
    let mtl = "newmtl white\nKd 0.5 0.5\nnewmtl lamp\nKe 1 1 1\n";
    let (_dir, path, _) = obj_scene(mtl, &white_quad("floor"));
    expect_error(&path, &["m.mtl:2", "three numbers"]);
}

#[test]
fn missing_mtl_file_is_named() {
    let dir = TempDir::new().unwrap();
    let path = write(&dir, "scene.obj", &format!("mtllib nothere.mtl\n{LAMP}"));
    let e = expect_error(&path, &["scene.obj", "nothere.mtl"]);
    assert!(matches!(e, Error::MissingMtl { .. }));
}

#[test]
fn second_missing_mtl_file_is_named_too() {
    // tobj keeps going when one of two libraries loads; isorad does not.
    let (dir, _, _) = obj_scene(MTL, "");
    let path = write(
        &dir,
        "two.obj",
        &format!("mtllib m.mtl\nmtllib gone.mtl\n{LAMP}"),
    );
    expect_error(&path, &["two.obj", "gone.mtl"]);
}

#[test]
fn unknown_material_is_named() {
    let body = "o box\nusemtl purple\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n";
    let (_dir, path, text) = obj_scene(MTL, body);
    let line = line_of(&text, "usemtl purple");
    let e = expect_error(&path, &[&format!("scene.obj:{line}"), "`box`", "`purple`"]);
    assert!(matches!(e, Error::MissingMaterial { .. }));
}

#[test]
fn face_without_material_is_named() {
    let dir = TempDir::new().unwrap();
    write(&dir, "m.mtl", MTL);
    let text = format!("mtllib m.mtl\no naked\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n{LAMP}");
    let path = write(&dir, "scene.obj", &text);
    let e = expect_error(&path, &["scene.obj:6", "`naked`", "without a material"]);
    assert!(matches!(e, Error::MissingMaterial { .. }));
}

#[test]
fn empty_file_is_an_empty_scene() {
    let dir = TempDir::new().unwrap();
    let path = write(&dir, "empty.obj", "");
    let e = expect_error(&path, &["empty.obj", "no usable faces"]);
    assert!(matches!(e, Error::EmptyScene { .. }));
}

#[test]
fn scene_without_emitter_is_refused() {
    let dir = TempDir::new().unwrap();
    write(&dir, "m.mtl", MTL);
    let text = format!("mtllib m.mtl\n{}", white_quad("floor"));
    let path = write(&dir, "dark.obj", &text);
    let e = expect_error(&path, &["dark.obj", "no emitter"]);
    assert!(matches!(e, Error::EmptyScene { .. }));
}

// ---- Bad scene files -------------------------------------------------------

fn toml_scene(toml: &str) -> (TempDir, PathBuf) {
    let (dir, _, _) = obj_scene(MTL, &white_quad("floor"));
    let path = write(&dir, "scene.toml", toml);
    (dir, path)
}

#[test]
fn toml_unknown_key_is_named() {
    let (_dir, path) = toml_scene(
        "obj = \"scene.obj\"\n[camera]\nposition = [0, 0, -5]\nlook_at = [0, 0, 0]\nvfov = 30\n",
    );
    expect_error(&path, &["scene.toml", "line 5", "vfov"]);
}

#[test]
fn toml_missing_obj_is_named() {
    let (_dir, path) = toml_scene("[solver]\ntolerance = 0.01\n");
    let e = expect_error(&path, &["scene.toml", "obj"]);
    assert!(matches!(e, Error::SceneFile { .. }));
}

#[test]
fn toml_pointing_to_missing_obj_is_named() {
    let (_dir, path) = toml_scene("obj = \"gone.obj\"\n");
    let e = expect_error(&path, &["scene.toml", "gone.obj"]);
    assert!(matches!(e, Error::SceneFile { .. }));
}

#[test]
fn toml_bad_camera_is_named() {
    let (_dir, path) =
        toml_scene("obj = \"scene.obj\"\n[camera]\nposition = [1, 2, 3]\nlook_at = [1, 2, 3]\n");
    expect_error(&path, &["scene.toml", "camera", "look_at"]);
}

/// The settings a scene file's `[mesh]` and `[solver]` tables give.
fn file_settings(toml: &str) -> Result<Settings, Error> {
    let (_dir, path) = toml_scene(toml);
    let loaded = load_scene(path.to_str().unwrap()).unwrap();
    Settings::from_scene_options(&loaded.options)
}

/// A bad setting names the file, the line and the field path.
fn expect_setting_error(toml: &str, line: usize, name: &str, words: &[&str]) {
    let e = file_settings(toml).unwrap_err();
    let message = e.to_string();
    match &e {
        Error::SceneSetting {
            path,
            line: l,
            name: n,
            ..
        } => {
            assert!(path.ends_with("scene.toml"), "{message}");
            assert_eq!((*l, n.as_str()), (Some(line), name), "{message}");
        }
        other => panic!("expected a scene setting error, got {other:?}"),
    }
    let prefix = format!("scene.toml: line {line}: invalid setting `{name}`");
    assert!(message.contains(&prefix), "{message}");
    for word in words {
        assert!(message.contains(word), "{message} lacks {word}");
    }
}

#[test]
fn toml_bad_settings_are_named_with_line_and_field() {
    let obj = "obj = \"scene.obj\"\n";
    // Type errors: an unknown variant, a string for a number, unknown keys.
    expect_setting_error(
        &format!("{obj}[mesh]\nkind = \"hexagonal\"\n"),
        3,
        "mesh.kind",
        &["hexagonal", "square"],
    );
    expect_setting_error(
        &format!("{obj}[solver]\nmax_shots = 10\ntolerance = \"low\"\n"),
        4,
        "solver.tolerance",
        &["string \"low\""],
    );
    expect_setting_error(
        &format!("{obj}[mesh]\nmax_egde = 1.0\nkind = \"square\"\n"),
        3,
        "mesh.max_egde",
        &["unknown field"],
    );
    expect_setting_error(
        &format!("{obj}[mesh.refinement]\nthreshold = 1.0\nlevels = 2\n"),
        4,
        "mesh.refinement.levels",
        &["unknown field", "max_levels"],
    );
    expect_setting_error(
        &format!("{obj}[mesh]\nmax_edge = {{ of_diameter = 0.1 }}\n"),
        3,
        "mesh.max_edge",
        &["of_diagonal"],
    );
    // Range errors found by validation.
    expect_setting_error(
        &format!("{obj}[solver]\ntolerance = 2.0\n"),
        3,
        "solver.tolerance",
        &["2 is not in (0, 1)"],
    );
    expect_setting_error(
        &format!("{obj}[solver]\nzone_affinity = 0\n"),
        3,
        "solver.zone_affinity",
        &["0 is not in (0, 1]"],
    );
    expect_setting_error(
        &format!("{obj}[solver]\nclosed_zone_weight = 1.5\n"),
        3,
        "solver.closed_zone_weight",
        &["1.5 is not in (0, 1]"],
    );
    expect_setting_error(
        &format!("{obj}[solver]\npatch_tolerance = 0\n"),
        3,
        "solver.patch_tolerance",
        &["0 is not in (0, 1]"],
    );
    expect_setting_error(
        &format!("{obj}[solver]\nambient_sweeps = 65\n"),
        3,
        "solver.ambient_sweeps",
        &["65 is more than 64"],
    );
    expect_setting_error(
        &format!("{obj}[solver]\nsmooth_ambient = 1\n"),
        3,
        "solver.smooth_ambient",
        &["bool"],
    );
    expect_setting_error(
        &format!("{obj}[mesh]\nkind = \"adaptive\"\nrefinement.threshold = 0\n"),
        4,
        "mesh.refinement.threshold",
        &["positive"],
    );
    expect_setting_error(
        &format!("{obj}[mesh]\nelements_per_side = 0\n"),
        3,
        "mesh.elements_per_side",
        &["0 is not in 1..=1000"],
    );
    expect_setting_error(
        &format!("{obj}[mesh]\nmax_shadow_boundaries = 0\n"),
        3,
        "mesh.max_shadow_boundaries",
        &["0 is not in 1..=1000000"],
    );
    // A table where a table belongs is checked when loading.
    let (_dir, path) = toml_scene(&format!("{obj}mesh = 3\n"));
    expect_error(&path, &["scene.toml", "line 2", "invalid type"]);
}

#[test]
fn toml_settings_reach_every_field() {
    let toml = "obj = \"scene.obj\"\n[solver]\nkernel = \"exact\"\nmax_samples = 32\n\
                shoot_from = \"patch_mean\"\n\
                [mesh]\nkind = \"adaptive\"\nmax_edge = 2\n\
                patch_max_edge = { of_diagonal = 0.5 }\nrefinement.threshold = 0.25\n\
                [mesh.contour]\nlevels = 5\n[mesh.dominance]\nmin_share = 0.7\n";
    let settings = file_settings(toml).unwrap();
    assert_eq!(settings.solver.kernel, FormFactorKernel::Exact);
    assert_eq!(settings.solver.max_samples, 32);
    assert_eq!(settings.solver.shoot_from, ShootFrom::PatchMean);
    assert_eq!(settings.mesh.kind, MeshKind::Adaptive);
    assert_eq!(settings.mesh.max_edge, Length::Absolute(2.0));
    assert_eq!(settings.mesh.patch_max_edge, Length::OfDiagonal(0.5));
    assert_eq!(settings.mesh.refinement.threshold, 0.25);
    assert_eq!(settings.mesh.contour.levels, 5);
    assert_eq!(settings.mesh.dominance.min_share, 0.7);
    // Everything else keeps its default.
    let mut expected = Settings::default();
    expected.solver.kernel = FormFactorKernel::Exact;
    expected.solver.max_samples = 32;
    expected.solver.shoot_from = ShootFrom::PatchMean;
    expected.mesh.kind = MeshKind::Adaptive;
    expected.mesh.max_edge = Length::Absolute(2.0);
    expected.mesh.patch_max_edge = Length::OfDiagonal(0.5);
    expected.mesh.refinement.threshold = 0.25;
    expected.mesh.contour.levels = 5;
    expected.mesh.dominance.min_share = 0.7;
    assert_eq!(settings, expected);
}

#[test]
fn settings_round_trip_through_toml() {
    let mut settings = Settings::final_quality();
    settings.mesh.kind = MeshKind::Contour;
    settings.mesh.max_edge = Length::Absolute(0.5);
    settings.mesh.elements_per_side = Some(4);
    settings.solver.kernel = FormFactorKernel::Wallace;
    let text = toml::to_string(&settings).unwrap();
    let back: Settings = toml::from_str(&text).unwrap();
    assert_eq!(back, settings, "{text}");
}

#[test]
fn toml_settings_and_camera_defaults() {
    let toml = "obj = \"scene.obj\"\n[camera]\nposition = [0.5, 1, -3]\nlook_at = [0.5, 1, 0]\n\
                [solver]\ntolerance = 0.02\n[mesh]\nkind = \"contour\"\nmax_edge = 0.1\n\
                elements_per_side = 7\n";
    let (_dir, path) = toml_scene(toml);
    let loaded = load_scene(path.to_str().unwrap()).unwrap();
    let camera = loaded.scene.camera.unwrap();
    assert_eq!(
        (camera.width, camera.height, camera.vfov_deg),
        (512, 512, 40.0)
    );
    assert_eq!(camera.up, DVec3::Y);
    let settings = Settings::from_scene_options(&loaded.options).unwrap();
    assert_eq!(settings.solver.tolerance, 0.02);
    assert_eq!(settings.mesh.kind, MeshKind::Contour);
    assert_eq!(settings.mesh.max_edge, Length::Absolute(0.1));
    assert_eq!(settings.mesh.elements_per_side, Some(7));
    assert_eq!(loaded.source, path.to_str().unwrap());
}

#[test]
fn unknown_scene_name() {
    let e = load_scene("no-such-scene").unwrap_err();
    assert!(matches!(e, Error::UnknownScene { .. }));
    let message = e.to_string();
    assert!(message.contains("no-such-scene") && message.contains("cornell"));
    assert!(isorad::scene::builtin_names().contains(&"cornell"));
}

// ---- Geometry clean-up -----------------------------------------------------

#[test]
fn quads_and_pentagons_stay_whole() {
    let body = "o slab\nusemtl white\nv 0 0 0\nv 2 0 0\nv 2 0 2\nv 0 0 2\nf -4 -3 -2 -1\n\
                o house\nusemtl white\nv 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nf -5 -4 -3 -2 -1\n";
    let (_dir, path, _) = obj_scene(MTL, body);
    let scene = load_scene(path.to_str().unwrap()).unwrap().scene;
    let count = |name: &str| scene.surfaces.iter().filter(|s| s.name == name).count();
    assert_eq!((count("slab"), count("house"), count("lamp")), (1, 1, 1));
    let house = scene.surfaces.iter().find(|s| s.name == "house").unwrap();
    assert_eq!(house.vertices().len(), 5);
    assert!((house.area() - 3.0).abs() < 1e-6);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

#[test]
fn all_triangle_obj_loads() {
    // tobj leaves face_arities empty when every face is a triangle.
    let dir = TempDir::new().unwrap();
    write(&dir, "m.mtl", MTL);
    let text = "mtllib m.mtl\no lamp\nusemtl lamp\nv 0 1 0\nv 1 1 0\nv 0 1 1\nv 1 1 1\n\
                f 1 3 2\nf 2 3 4\no tri\nusemtl white\nv 0 0 0\nv 1 0 0\nv 0 0 1\nf 5 7 6\n";
    let path = write(&dir, "tris.obj", text);
    let scene = load_obj(&path).unwrap();
    // The lamp's two coplanar triangles merge back into its quad.
    assert_eq!(scene.surfaces.len(), 2);
    assert_eq!(scene.surfaces[0].vertices().len(), 4);
    assert_eq!(scene.surfaces[1].vertices().len(), 3);
    assert_eq!(scene.surfaces[1].name, "tri");
    assert!((scene.surfaces[0].area() - 1.0).abs() < 1e-6);
}

#[test]
fn non_planar_quad_is_split_with_a_warning() {
    // One corner lifted by 30 % of the quad's side.
    let body = "o bent\nusemtl white\nv 0 0 0\nv 1 0 0\nv 1 0.3 1\nv 0 0 1\nf -4 -3 -2 -1\n";
    let (_dir, path, text) = obj_scene(MTL, body);
    let scene = load_obj(&path).unwrap();
    let bent: Vec<_> = scene.surfaces.iter().filter(|s| s.name == "bent").collect();
    assert_eq!(bent.len(), 2);
    assert!(
        bent.iter()
            .all(|s| s.vertices().len() == 3 && s.normal().y < -0.8)
    );
    let line = text.lines().count(); // the last statement: bent's face
    assert_eq!(scene.warnings.len(), 1);
    let warning = &scene.warnings[0].message;
    assert!(
        warning.contains("`bent`") && warning.contains("not planar"),
        "{warning}"
    );
    assert!(warning.contains(&format!("scene.obj:{line}")), "{warning}");
}

#[test]
fn degenerate_faces_are_skipped_with_a_warning() {
    let body = "o sliver\nusemtl white\nv 0 0 0\nv 1 0 0\nv 2 0 0\nf -3 -2 -1\nf -3 -3 -2\n";
    let (_dir, path, _) = obj_scene(MTL, body);
    let scene = load_obj(&path).unwrap();
    assert!(scene.surfaces.iter().all(|s| s.name != "sliver"));
    assert_eq!(scene.warnings.len(), 2);
    assert!(
        scene
            .warnings
            .iter()
            .all(|w| w.message.contains("`sliver`"))
    );
}

#[test]
fn polylines_are_ignored_with_a_warning() {
    let body = "o wire\nusemtl white\nv 0 0 0\nv 1 0 0\nv 2 1 0\nl -3 -2 -1\n";
    let (_dir, path, _) = obj_scene(MTL, body);
    let scene = load_obj(&path).unwrap();
    assert_eq!(scene.surfaces.len(), 1);
    assert!(scene.warnings[0].message.contains("polyline"));
}

// ---- The Cornell box -------------------------------------------------------

fn cornell_file_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell/cornell.toml")
}

fn cornell() -> Scene {
    load_scene("cornell").unwrap().scene
}

fn centroid(points: &[DVec3]) -> DVec3 {
    points.iter().copied().sum::<DVec3>() / points.len() as f64
}

#[test]
fn cornell_builtin_equals_the_shipped_files() {
    let builtin = load_scene("cornell").unwrap();
    let file = load_scene(cornell_file_path().to_str().unwrap()).unwrap();
    assert_eq!(builtin.scene.surfaces, file.scene.surfaces);
    assert_eq!(builtin.scene.materials, file.scene.materials);
    assert_eq!(builtin.scene.camera, file.scene.camera);
    assert_eq!(
        Settings::from_scene_options(&builtin.options).unwrap(),
        Settings::from_scene_options(&file.options).unwrap()
    );
    assert!(builtin.scene.warnings.is_empty() && file.scene.warnings.is_empty());
    assert_eq!(builtin.source, "cornell");
    let camera = builtin.scene.camera.unwrap();
    assert_eq!(camera.position, DVec3::new(278.0, 273.0, -800.0));
    assert_eq!(camera.look_at, DVec3::new(278.0, 273.0, 0.0));
    assert_eq!(
        (camera.vfov_deg, camera.width, camera.height),
        (39.3, 512, 512)
    );
}

#[test]
fn cornell_has_the_expected_surfaces_and_materials() {
    let scene = cornell();
    assert_eq!(scene.surfaces.len(), 16);
    let names = ["white", "red", "green", "light"];
    for (m, name) in scene.materials.iter().zip(names) {
        assert_eq!(m.name, name);
    }
    let red = &scene.materials[1].reflectance;
    assert!((red.r - 0.63).abs() < 1e-6 && (red.g - 0.065).abs() < 1e-6);
}

#[test]
fn cornell_red_wall_is_one_surface_with_its_area() {
    let scene = cornell();
    let walls: Vec<_> = scene
        .surfaces
        .iter()
        .filter(|s| s.name == "red_wall")
        .collect();
    assert_eq!(walls.len(), 1);
    // The measured, slightly non-planar quad from the Cornell data.
    let original = [
        DVec3::new(552.8, 0.0, 0.0),
        DVec3::new(549.6, 0.0, 559.2),
        DVec3::new(556.0, 548.8, 559.2),
        DVec3::new(556.0, 548.8, 0.0),
    ];
    let plane = isorad::internals::best_fit_plane(&original).unwrap();
    assert!(plane.max_deviation > 0.5 && plane.max_deviation < 1.0);
    let area = 0.5 * newell_normal(&original).length();
    assert!((walls[0].area() - area).abs() < 1e-3 * area);
    assert_eq!(scene.material_of(walls[0]).name, "red");
}

#[test]
fn cornell_light_area_and_power() {
    let scene = cornell();
    let emitters: Vec<_> = scene
        .surfaces
        .iter()
        .filter(|s| scene.material_of(s).is_emitter())
        .collect();
    assert_eq!(emitters.len(), 1);
    let light = emitters[0];
    assert!((light.area() - 130.0 * 105.0).abs() < 1e-6 * 13650.0);
    assert!((light.normal() - DVec3::NEG_Y).length() < 1e-9);
    assert!(light.vertices().iter().all(|v| (v.y - 548.7).abs() < 1e-4));
    // Φ = π L_e A per channel.
    let expected = Rgb::new(17.0, 12.0, 4.0) * std::f64::consts::PI * 13650.0;
    let power = scene.emitted_power();
    assert!((power - expected).abs().max_element() < 1e-6 * expected.max_element());
}

#[test]
fn cornell_surfaces_face_into_the_room() {
    let scene = cornell();
    let room_centre = DVec3::new(278.0, 274.4, 279.6);
    for s in &scene.surfaces {
        let c = centroid(s.vertices());
        let facing = match s.name.as_str() {
            // Block faces point out of their block.
            "short_block" | "tall_block" => {
                let block: Vec<DVec3> = scene
                    .surfaces
                    .iter()
                    .filter(|t| t.name == s.name)
                    .flat_map(|t| t.vertices().iter().copied())
                    .collect();
                (c - centroid(&block)).dot(s.normal())
            }
            _ => (room_centre - c).dot(s.normal()),
        };
        assert!(facing > 0.0, "{} faces away ({:?})", s.name, s.normal());
    }
}

#[test]
fn cornell_red_wall_is_on_the_left_of_the_image() {
    let scene = cornell();
    let camera = scene.camera.clone().unwrap();
    let frame = camera.frame();
    // Pixel column of a world point: x_ndc = (d·right)/(d·forward) / (tan(fov/2)·aspect).
    let column = |p: DVec3| {
        let d = p - camera.position;
        let half = (0.5 * camera.vfov_deg.to_radians()).tan();
        let aspect = f64::from(camera.width) / f64::from(camera.height);
        let x = d.dot(frame.right) / d.dot(frame.forward) / (half * aspect);
        0.5 * (x + 1.0) * f64::from(camera.width)
    };
    let wall_centre = |name: &str| {
        let s = scene.surfaces.iter().find(|s| s.name == name).unwrap();
        centroid(s.vertices())
    };
    let red = column(wall_centre("red_wall"));
    let green = column(wall_centre("green_wall"));
    assert!(
        red < 0.5 * f64::from(camera.width),
        "red wall at column {red}"
    );
    assert!(
        green > 0.5 * f64::from(camera.width),
        "green wall at column {green}"
    );
}

/// The `[mesh]` table alone, as `isorad info` and `isorad compare` read it:
/// the same values and the same errors as the whole settings' `mesh`, and
/// the `[solver]` table, which they do not use, left unread.
#[test]
fn the_mesh_table_reads_alone_with_the_same_values_and_errors() {
    let read = |toml: &str| {
        let (_dir, path) = toml_scene(toml);
        let loaded = load_scene(path.to_str().unwrap()).unwrap();
        isorad::MeshSettings::from_scene_options(&loaded.options)
    };
    let obj = "obj = \"scene.obj\"\n";
    let file =
        format!("{obj}[mesh]\nkind = \"contour\"\nmax_edge = 0.25\n[mesh.contour]\nlevels = 7\n");
    let mesh = read(&file).unwrap();
    assert_eq!(mesh, file_settings(&file).unwrap().mesh);
    assert_eq!(mesh.contour.levels, 7);
    assert_ne!(mesh, isorad::MeshSettings::default());
    // A bad [solver] value is not the mesh's concern.
    let solver_only = format!("{obj}[solver]\ntolerance = 2.0\n");
    assert_eq!(read(&solver_only).unwrap(), isorad::MeshSettings::default());
    // Type and range errors name the file, the line and the field path.
    for (toml, line, name) in [
        (
            format!("{obj}[mesh]\nkind = \"hexagonal\"\n"),
            3,
            "mesh.kind",
        ),
        (
            format!("{obj}\n[mesh.contour]\nlevels = 0\n"),
            4,
            "mesh.contour.levels",
        ),
    ] {
        match read(&toml).unwrap_err() {
            Error::SceneSetting {
                path,
                line: l,
                name: n,
                ..
            } => {
                assert!(path.ends_with("scene.toml"));
                assert_eq!((l, n.as_str()), (Some(line), name));
            }
            other => panic!("expected a scene setting error, got {other:?}"),
        }
    }
}
