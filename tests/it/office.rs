//! The generated office (scenes/office): a CAD-style export of thousands of
//! faces that coplanar merging brings back to a mesh of sensible size.

use std::path::{Path, PathBuf};

use isorad::{
    mesh::{SquareMeshSettings, mesh_square},
    scene::{LoadSettings, Surface, load_scene_with},
};

fn office_toml() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/office/office.toml")
}

fn load(merge: bool) -> isorad::Scene {
    let mut settings = LoadSettings::default();
    settings.merge_coplanar = merge;
    load_scene_with(office_toml().to_str().unwrap(), &settings)
        .unwrap()
        .scene
}

fn named<'a>(scene: &'a isorad::Scene, name: &str) -> Vec<&'a Surface> {
    scene.surfaces.iter().filter(|s| s.name == name).collect()
}

#[test]
fn the_office_loads_with_its_triangulated_shell_merged() {
    let faces = load(false);
    let merged = load(true);
    assert!(
        faces.surfaces.len() >= 5000,
        "{} faces",
        faces.surfaces.len()
    );
    assert_eq!(named(&faces, "floor").len(), 48 * 32 * 2);
    // Carpet, ceiling and the four walls come back as single rectangles of
    // the same area; nothing else merges (boxes' faces are not coplanar).
    for (name, area) in [
        ("floor", 96.0),
        ("ceiling", 96.0),
        ("wall_south", 36.0),
        ("wall_north", 36.0),
        ("wall_west", 24.0),
        ("wall_east", 24.0),
    ] {
        let before: f64 = named(&faces, name).iter().map(|s| s.area()).sum();
        let after = named(&merged, name);
        assert_eq!(after.len(), 1, "{name}");
        assert_eq!(after[0].vertices().len(), 4, "{name}");
        assert!(
            (after[0].area() - area).abs() < 1e-4 && (before - area).abs() < 1e-4,
            "{name}"
        );
    }
    let shell = 48 * 32 * 2 + 24 * 16 * 2 + 2 * 12 * 3 * 2 + 2 * 8 * 3 * 2;
    assert_eq!(merged.surfaces.len(), faces.surfaces.len() - shell + 6);
    let summary = &merged.warnings.last().unwrap().message;
    assert!(
        summary.contains("merged 4,080 coplanar faces into 6 polygons"),
        "{summary}"
    );
    assert_eq!(named(&merged, "luminaire").len(), 8);
}

#[test]
fn the_office_meshes_with_its_contacts() {
    let scene = load(true);
    let mesh = mesh_square(&scene, &SquareMeshSettings::for_scene(&scene));
    let areas: Vec<f64> = scene.surfaces.iter().map(Surface::area).collect();
    mesh.validate(&areas).unwrap();
    // The carpet loses the footprints of what stands on it: pedestals,
    // chair bases, desk legs and bookcases, to within 2e-3 m² (less than one
    // desk leg's octagon, 2.5e-3 m²; measured 1.4e-3 over 48 legs).
    let floor = scene.surface_named("floor").unwrap();
    let covered: f64 = mesh
        .elements
        .iter()
        .filter(|e| e.surface == floor)
        .map(|e| e.area)
        .sum();
    let pedestals = 16.0 * 0.4 * 0.6;
    let chairs = 16.0 * 0.5 * 0.5;
    let legs = 4.0 * 2.0 * 6.0 * 8.0 * 0.5 * 0.03_f64.powi(2) * (std::f64::consts::PI / 4.0).sin();
    let bookcases = 5.0 * 2.0 * 0.02 * 0.35 + 5.0 * 0.96 * 0.02;
    let footprints = pedestals + chairs + legs + bookcases;
    assert!(
        (96.0 - covered - footprints).abs() < 2e-3,
        "floor elements cover {covered} m², expected {}",
        96.0 - footprints
    );
}

/// A 16-sided plate on a floor with an octagonal column standing on it:
/// the contact mesher's constrained triangulation once panicked inside
/// spade 2.15 ("Failed to locate position"), before crossings of contact
/// lines became vertices of isorad's own.
#[test]
fn contact_mesher_survives_an_octagonal_column_on_a_16_gon() {
    let dir = tempfile::tempdir().unwrap();
    let ring = |sides: usize, radius: f64, y: f64| -> Vec<[f64; 3]> {
        (0..sides)
            .map(|k| {
                let a = 2.0 * std::f64::consts::PI * k as f64 / sides as f64;
                [2.1 + radius * a.cos(), y, 3.12 + radius * a.sin()]
            })
            .collect()
    };
    let mut obj = String::from(
        "mtllib m.mtl\no floor\nusemtl white\nv 0 0 0\nv 0 0 8\nv 12 0 8\nv 12 0 0\nf -4 -3 -2 -1\n",
    );
    let mut polygon = |name: &str, points: &[[f64; 3]]| {
        obj.push_str(&format!("o {name}\nusemtl white\n"));
        for p in points {
            obj.push_str(&format!("v {:.6} {:.6} {:.6}\n", p[0], p[1], p[2]));
        }
        let n = points.len();
        let indices: Vec<String> = (0..n).map(|k| format!("-{}", n - k)).collect();
        obj.push_str(&format!("f {}\n", indices.join(" ")));
    };
    // The plate: sides and a top facing up (counter-clockwise from above).
    let (bottom, top) = (ring(16, 0.25, 0.0), ring(16, 0.25, 0.05));
    for k in 0..16 {
        let j = (k + 1) % 16;
        polygon("plate", &[bottom[j], bottom[k], top[k], top[j]]);
    }
    polygon("plate", &top.iter().rev().copied().collect::<Vec<_>>());
    let (bottom, top) = (ring(8, 0.03, 0.05), ring(8, 0.03, 0.42));
    for k in 0..8 {
        let j = (k + 1) % 8;
        polygon("column", &[bottom[j], bottom[k], top[k], top[j]]);
    }
    obj.push_str(
        "o lamp\nusemtl lamp\nv 1.8 2 2.8\nv 2.2 2 2.8\nv 2.2 2 3.2\nv 1.8 2 3.2\nf -4 -3 -2 -1\n",
    );
    std::fs::write(
        dir.path().join("m.mtl"),
        "newmtl white\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 10 10 10\n",
    )
    .unwrap();
    let path = dir.path().join("plate.obj");
    std::fs::write(&path, obj).unwrap();
    let scene = isorad::scene::load_obj(&path).unwrap();
    let mut settings = SquareMeshSettings::for_scene(&scene);
    settings.max_edge = 0.367;
    let _ = mesh_square(&scene, &settings);
}
