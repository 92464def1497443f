//! Coplanar merging: triangulated exports load as the polygons they came
//! from, and only faces that really form one simple planar polygon merge.

use glam::DVec3;
use isorad::scene::{
    LoadSettings, MergeReport, Surface, load_obj, load_scene_with, merge_coplanar_faces,
};
use tempfile::TempDir;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// A triangle on the floor (y = 0) facing up, from (x, z) corners given
/// counter-clockwise seen from above (+y).
fn floor_triangle(material: usize, corners: [(f64, f64); 3]) -> Surface {
    // Seen from +y, counter-clockwise in (x, z) is clockwise in (x, −z):
    // reverse so that the normal is +y.
    let points = corners.iter().rev().map(|&(x, z)| v(x, 0.0, z)).collect();
    let surface = Surface::new("floor", material, points).expect("a triangle");
    assert!(surface.normal().y > 0.99);
    surface
}

/// The unit square at (i, j) split into two triangles, along either diagonal.
fn split_square(material: usize, i: f64, j: f64, flip: bool) -> [Surface; 2] {
    let (a, b, c, d) = ((i, j), (i + 1.0, j), (i + 1.0, j + 1.0), (i, j + 1.0));
    if flip {
        [
            floor_triangle(material, [a, b, d]),
            floor_triangle(material, [b, c, d]),
        ]
    } else {
        [
            floor_triangle(material, [a, b, c]),
            floor_triangle(material, [a, c, d]),
        ]
    }
}

fn merge(surfaces: Vec<Surface>) -> (Vec<Surface>, MergeReport) {
    merge_coplanar_faces(surfaces, 10.0)
}

fn total_area(surfaces: &[Surface]) -> f64 {
    surfaces.iter().map(Surface::area).sum()
}

/// The area covered by a surface's own triangulation (what meshing and
/// visibility use).
fn triangulated_area(surface: &Surface) -> f64 {
    let p = surface.vertices();
    surface
        .triangles()
        .iter()
        .map(|&[a, b, c]| 0.5 * (p[b] - p[a]).cross(p[c] - p[a]).dot(surface.normal()))
        .sum()
}

#[test]
fn merging_a_triangulated_quad_gives_back_one_polygon() {
    let dir = TempDir::new().unwrap();
    std::fs::write(
        dir.path().join("m.mtl"),
        "newmtl white\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 1 1 1\n",
    )
    .unwrap();
    // A 2 m × 3 m floor as two triangles, as CAD exporters write it, and a lamp.
    let obj = "mtllib m.mtl\no floor\nusemtl white\nv 0 0 0\nv 0 0 3\nv 2 0 3\nv 2 0 0\n\
               f 1 2 3\nf 1 3 4\no lamp\nusemtl lamp\nv 0 2 0\nv 1 2 0\nv 1 2 1\nv 0 2 1\nf 5 6 7 8\n";
    let path = dir.path().join("floor.obj");
    std::fs::write(&path, obj).unwrap();
    let scene = load_obj(&path).unwrap();
    let floor: Vec<&Surface> = scene
        .surfaces
        .iter()
        .filter(|s| s.name == "floor")
        .collect();
    assert_eq!(floor.len(), 1);
    assert_eq!(floor[0].vertices().len(), 4);
    assert!((floor[0].area() - 6.0).abs() < 1e-9);
    assert!(floor[0].normal().y > 0.999);
    let summary = &scene.warnings.last().unwrap().message;
    assert!(
        summary.contains("merged 2 coplanar faces into 1 polygon"),
        "{summary}"
    );

    // Switched off by the caller, or by the scene file.
    let mut settings = LoadSettings::default();
    settings.merge_coplanar = false;
    let kept = load_scene_with(path.to_str().unwrap(), &settings)
        .unwrap()
        .scene;
    assert_eq!(
        kept.surfaces.iter().filter(|s| s.name == "floor").count(),
        2
    );
    std::fs::write(
        dir.path().join("s.toml"),
        "obj = \"floor.obj\"\nmerge_coplanar = false\n",
    )
    .unwrap();
    let toml = dir.path().join("s.toml");
    let kept = load_scene_with(toml.to_str().unwrap(), &LoadSettings::default())
        .unwrap()
        .scene;
    assert_eq!(kept.surfaces.len(), 3);
    assert!(kept.warnings.is_empty(), "{:?}", kept.warnings);
}

#[test]
fn a_split_quad_merges_into_four_vertices_with_the_same_area() {
    let (merged, report) = merge(split_square(0, 0.0, 0.0, false).into());
    assert_eq!(merged.len(), 1);
    assert_eq!(merged[0].vertices().len(), 4);
    assert!((merged[0].area() - 1.0).abs() < 1e-12);
    assert_eq!(
        report,
        MergeReport {
            faces_merged: 2,
            polygons: 1,
            regions_kept: 0,
            faces_kept: 0
        }
    );
}

#[test]
fn an_l_shape_of_triangles_merges_into_one_hexagon() {
    // Three unit squares, (0,0), (1,0) and (0,1): six triangles.
    let mut faces = Vec::new();
    for (i, j) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)] {
        faces.extend(split_square(0, i, j, i > 0.0));
    }
    let (merged, _) = merge(faces);
    assert_eq!(merged.len(), 1);
    let l = &merged[0];
    // Collinear vertices (1, 0) and (0, 1) are dropped: the six corners remain.
    assert_eq!(l.vertices().len(), 6, "{:?}", l.vertices());
    assert!((l.area() - 3.0).abs() < 1e-12);
    // Its triangulation covers the L, not the square around it.
    assert!((triangulated_area(l) - 3.0).abs() < 1e-12);
}

#[test]
fn a_grid_of_split_quads_merges_into_one_rectangle() {
    let mut faces = Vec::new();
    for i in 0..10 {
        for j in 0..10 {
            faces.extend(split_square(
                0,
                f64::from(i),
                f64::from(j),
                (i + j) % 2 == 1,
            ));
        }
    }
    assert_eq!(faces.len(), 200);
    let (merged, report) = merge(faces);
    assert_eq!(merged.len(), 1);
    assert_eq!(merged[0].vertices().len(), 4);
    assert!((merged[0].area() - 100.0).abs() < 1e-9);
    assert_eq!(
        report.summary().unwrap(),
        "merged 200 coplanar faces into 1 polygon"
    );
}

#[test]
fn different_materials_and_objects_do_not_merge() {
    let [a, _] = split_square(0, 0.0, 0.0, false);
    let [_, b] = split_square(1, 0.0, 0.0, false);
    let (merged, report) = merge(vec![a, b]);
    assert_eq!(merged.len(), 2);
    assert_eq!(report, MergeReport::default());
    assert!(report.summary().is_none());

    let [a, mut b] = split_square(0, 0.0, 0.0, false);
    b.name = "rug".into();
    assert_eq!(merge(vec![a, b]).0.len(), 2);
}

#[test]
fn a_slight_crease_does_not_merge() {
    // Two triangles over the unit square, the far corner lifted: folded by
    // about 1° along the diagonal.
    let lift = (1.0_f64).to_radians().tan() / std::f64::consts::SQRT_2;
    let creased = |lift: f64| {
        let a = Surface::new(
            "floor",
            0,
            vec![v(0., 0., 0.), v(1., 0., 1.), v(1., 0., 0.)],
        )
        .unwrap();
        let b = Surface::new(
            "floor",
            0,
            vec![v(0., 0., 0.), v(0., lift, 1.), v(1., 0., 1.)],
        )
        .unwrap();
        merge(vec![a, b]).0.len()
    };
    assert_eq!(creased(lift), 2);
    // A rounding-sized fold is no crease.
    assert_eq!(creased(1e-9), 1);
}

#[test]
fn a_ring_keeps_its_faces() {
    // A 3 × 3 block of squares without the middle one: a region with a hole.
    let mut faces = Vec::new();
    for i in 0..3 {
        for j in 0..3 {
            if (i, j) != (1, 1) {
                faces.extend(split_square(0, f64::from(i), f64::from(j), false));
            }
        }
    }
    let (merged, report) = merge(faces);
    assert_eq!(merged.len(), 16);
    assert!((total_area(&merged) - 8.0).abs() < 1e-12);
    assert_eq!(
        report,
        MergeReport {
            faces_merged: 0,
            polygons: 0,
            regions_kept: 1,
            faces_kept: 16
        }
    );
    assert!(
        report
            .summary()
            .unwrap()
            .contains("1 coplanar region with a hole")
    );
}

#[test]
fn squares_touching_at_a_corner_stay_apart() {
    // Two split squares sharing only the vertex (1, 1): two regions, each
    // merged on its own, never one pinched polygon.
    let mut faces = Vec::from(split_square(0, 0.0, 0.0, false));
    faces.extend(split_square(0, 1.0, 1.0, false));
    let (merged, report) = merge(faces);
    assert_eq!(merged.len(), 2);
    assert!(merged.iter().all(|s| s.vertices().len() == 4));
    assert_eq!(report.polygons, 2);
}
