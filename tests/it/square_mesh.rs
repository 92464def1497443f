//! The square mesher: conforming, covering, and N × N on quads.

use crate::support::SceneBuilder;
use glam::DVec3;
use isorad::{
    Scene,
    mesh::{Mesh, SquareMeshSettings, mesh_square},
};
use std::collections::HashMap;

fn single(vertices: Vec<DVec3>) -> Scene {
    let mut b = SceneBuilder::default();
    let m = b.material("m", 0.5, 1.0);
    b.polygon("face", m, vertices);
    b.scene
}

fn xy(points: &[(f64, f64)]) -> Vec<DVec3> {
    points.iter().map(|&(x, y)| DVec3::new(x, y, 0.0)).collect()
}

/// Total length of the edges used by exactly one element.
fn boundary_length(mesh: &Mesh) -> f64 {
    let mut uses: HashMap<(u32, u32), u32> = HashMap::new();
    for e in &mesh.elements {
        let c = e.corners();
        for k in 0..c.len() {
            let (a, b) = (c[k], c[(k + 1) % c.len()]);
            *uses.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    uses.iter()
        .filter(|(_, n)| **n == 1)
        .map(|((a, b), _)| {
            mesh.vertices[*a as usize]
                .position
                .distance(mesh.vertices[*b as usize].position)
        })
        .sum()
}

#[test]
fn meshes_conform_and_cover_their_polygons() {
    let shapes = [
        xy(&[(0.0, 0.0), (3.0, 0.0), (3.5, 2.0), (0.2, 1.7)]),
        xy(&[(0.0, 0.0), (2.0, 0.3), (0.7, 1.9)]),
        xy(&[(0.0, 0.0), (2.0, 0.0), (2.6, 1.2), (1.0, 2.2), (-0.6, 1.2)]),
        xy(&[
            (0.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
        ]),
        xy(&[(0.0, 0.0), (2.0, 0.0), (0.5, 0.5), (0.0, 2.0)]),
    ];
    for shape in shapes {
        let scene = single(shape.clone());
        let mut settings = SquareMeshSettings::for_scene(&scene);
        settings.max_edge = 0.13;
        settings.patch_max_edge = 0.5;
        let mesh = mesh_square(&scene, &settings);
        let area = scene.surfaces[0].area();
        mesh.validate(&[area]).unwrap();
        let covered: f64 = mesh.elements.iter().map(|e| e.area).sum();
        assert!(
            (covered - area).abs() < 1e-9 * area,
            "{shape:?}: {covered} vs {area}"
        );
        // A T-junction would leave an edge used once inside the polygon.
        let perimeter: f64 = (0..shape.len())
            .map(|k| shape[k].distance(shape[(k + 1) % shape.len()]))
            .sum();
        let boundary = boundary_length(&mesh);
        assert!(
            (boundary - perimeter).abs() < 1e-9 * perimeter,
            "{shape:?}: boundary {boundary} vs perimeter {perimeter}"
        );
        let longest = mesh
            .elements
            .iter()
            .flat_map(|e| {
                let c = e.corners().to_vec();
                (0..c.len()).map(move |k| (c[k], c[(k + 1) % c.len()]))
            })
            .map(|(a, b)| {
                mesh.vertices[a as usize]
                    .position
                    .distance(mesh.vertices[b as usize].position)
            })
            .fold(0.0, f64::max);
        assert!(
            longest <= 0.13 * 1.5,
            "{shape:?}: an element edge of {longest}"
        );
    }
}

#[test]
fn a_quad_gets_n_by_n_elements() {
    let scene = single(xy(&[(0.0, 0.0), (3.0, 0.0), (3.0, 2.0), (0.0, 2.0)]));
    let mut settings = SquareMeshSettings::for_scene(&scene);
    settings.elements_per_side = Some(7);
    let mesh = mesh_square(&scene, &settings);
    assert_eq!(mesh.elements.len(), 49);
    assert_eq!(mesh.vertices.len(), 64);
    assert!(
        mesh.elements
            .iter()
            .all(|e| !e.is_triangle() && (e.area - 6.0 / 49.0).abs() < 1e-12)
    );
}

/// Found by the meshers fuzz target: a face whose outline runs out to a
/// spike and straight back (`a b a c d`) encloses 25 m², but its
/// triangulation covered 37.5 m². The spike is removed when the face is
/// cleaned, and the mesh covers the face exactly.
#[test]
fn a_face_with_a_spike_is_meshed_to_its_own_area() {
    let mut scene = Scene::new();
    let m = scene
        .add_material(isorad::Material::diffuse("m", isorad::Rgb::splat(0.5)))
        .unwrap();
    let outline = xy(&[(0.0, 0.0), (5.0, 0.0), (0.0, 0.0), (10.0, 5.0), (0.0, 5.0)]);
    let surfaces = scene.add_polygon("spiky", m, &outline).unwrap();
    assert_eq!(surfaces.len(), 1);
    let area = scene.surfaces[0].area();
    assert!((area - 25.0).abs() < 1e-9, "surface area {area}");
    assert_eq!(scene.surfaces[0].vertices().len(), 3);
    let mut settings = SquareMeshSettings::for_scene(&scene);
    settings.max_edge = 1.0;
    let mesh = mesh_square(&scene, &settings);
    let covered: f64 = mesh.elements.iter().map(|e| e.area).sum();
    assert!((covered - 25.0).abs() < 1e-9, "elements cover {covered}");
    mesh.validate(&[area]).unwrap();
}
