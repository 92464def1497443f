//! The element hierarchy of adaptive meshing: splitting keeps the mesh valid,
//! and the rendered triangulation through hanging vertices is conforming and
//! crack-free.

use crate::support::{Rng, SceneBuilder};
use glam::DVec3;
use isorad::{
    Camera, RenderSettings, Rgb, SurfaceId,
    mesh::{ElementHierarchy, Mesh, SquareMeshSettings, mesh_square},
    render::{ShadedTriangle, rasterize},
};
use std::collections::HashMap;

/// A 1 × 1 square facing +z, and a triangle facing +z beside it, meshed coarsely.
fn plane_scene() -> isorad::Scene {
    let mut b = SceneBuilder::default();
    let m = b.material("white", 0.5, 0.0);
    b.polygon(
        "square",
        m,
        vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ],
    );
    b.polygon(
        "triangle",
        m,
        vec![
            DVec3::new(1.5, 0.0, 0.0),
            DVec3::new(2.5, 0.0, 0.0),
            DVec3::new(1.5, 1.0, 0.0),
        ],
    );
    b.scene
}

fn coarse_mesh(scene: &isorad::Scene) -> Mesh {
    let mut settings = SquareMeshSettings::for_scene(scene);
    settings.elements_per_side = Some(4);
    mesh_square(scene, &settings)
}

/// Splits random elements, several rounds, validating after each.
fn refine_randomly(scene: &isorad::Scene, rounds: usize, seed: u64) -> (Mesh, ElementHierarchy) {
    let mut mesh = coarse_mesh(scene);
    let mut hierarchy = ElementHierarchy::new(&mesh);
    let areas: Vec<f64> = scene.surfaces.iter().map(|s| s.area()).collect();
    let mut rng = Rng(seed);
    for round in 0..rounds {
        let chosen: Vec<usize> = (0..mesh.elements.len())
            .filter(|_| rng.next_f64() < 0.3)
            .collect();
        let before = mesh.vertices.len();
        let added = hierarchy.split(&mut mesh, &chosen);
        assert_eq!(added.len(), mesh.vertices.len() - before);
        hierarchy
            .validate(&mesh, &areas)
            .unwrap_or_else(|e| panic!("round {round}: {e}"));
    }
    (mesh, hierarchy)
}

/// Rendered triangles of every element, through hanging vertices.
fn rendered_triangles(mesh: &Mesh) -> Vec<[u32; 3]> {
    let mut all = Vec::new();
    let mut split = Vec::new();
    for element in &mesh.elements {
        mesh.element_triangles(element, |_, _| 0.0, &mut split);
        all.extend_from_slice(&split);
    }
    all
}

#[test]
fn validate_holds_after_refinement() {
    let scene = plane_scene();
    for seed in 1..=5 {
        let (mesh, hierarchy) = refine_randomly(&scene, 4, seed);
        assert!(hierarchy.len() > mesh.elements.len());
        // Every hanging vertex splits an edge of some leaf element into two.
        assert!(!mesh.edge_midpoints.is_empty());
    }
}

#[test]
fn rendered_triangles_tile_the_surfaces_and_are_conforming() {
    let scene = plane_scene();
    let (mesh, _) = refine_randomly(&scene, 4, 7);
    let triangles = rendered_triangles(&mesh);
    let position = |v: u32| mesh.vertices[v as usize].position;
    // Areas sum to the surfaces', every triangle counter-clockwise (+z).
    let mut area = 0.0;
    for &[a, b, c] in &triangles {
        let cross = (position(b) - position(a)).cross(position(c) - position(a));
        assert!(cross.z > 0.0, "triangle {a} {b} {c} is flat or flipped");
        area += 0.5 * cross.z;
    }
    let expected: f64 = scene.surfaces.iter().map(|s| s.area()).sum();
    assert!((area - expected).abs() < 1e-9, "{area} vs {expected}");
    // Conforming: every directed edge inside a surface is matched by its
    // reverse; the unmatched ones lie on the surfaces' outlines.
    let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
    for &[a, b, c] in &triangles {
        for (p, q) in [(a, b), (b, c), (c, a)] {
            *edges.entry((p, q)).or_default() += 1;
        }
    }
    let mut boundary_length = 0.0;
    for (&(p, q), &count) in &edges {
        assert_eq!(count, 1, "edge ({p}, {q}) used twice the same way");
        if !edges.contains_key(&(q, p)) {
            boundary_length += position(p).distance(position(q));
        }
    }
    let perimeter = 4.0 + 2.0 + 2f64.sqrt();
    assert!(
        (boundary_length - perimeter).abs() < 1e-9,
        "unmatched edges total {boundary_length}, the outlines {perimeter}: a T-junction"
    );
}

#[test]
fn a_refined_plane_renders_without_cracks() {
    let scene = plane_scene();
    let (mesh, _) = refine_randomly(&scene, 5, 11);
    let triangles: Vec<ShadedTriangle> = rendered_triangles(&mesh)
        .iter()
        .filter(|t| mesh.vertices[t[0] as usize].surface == SurfaceId::new(0))
        .map(|t| ShadedTriangle {
            positions: t.map(|v| mesh.vertices[v as usize].position),
            radiance: [Rgb::ONE; 3],
        })
        .collect();
    // Looking straight down at the unit square, which overfills the image.
    let camera = Camera {
        position: DVec3::new(0.5, 0.5, 1.0),
        look_at: DVec3::new(0.5, 0.5, 0.0),
        up: DVec3::Y,
        vfov_deg: 40.0,
        width: 257,
        height: 257,
    };
    let mut settings = RenderSettings::default();
    settings.supersampling = 1;
    let image = rasterize(&triangles, &camera, &settings);
    let holes = image.pixels().iter().filter(|p| p[0] < 0.999).count();
    assert_eq!(
        holes, 0,
        "{holes} background pixels show through the refined plane"
    );
}

#[test]
fn hanging_vertices_lie_on_their_neighbours_outlines() {
    let scene = plane_scene();
    let (mesh, _) = refine_randomly(&scene, 3, 3);
    let mut hanging = 0;
    for element in &mesh.elements {
        let outline = mesh.element_outline(element);
        hanging += outline.len() - element.corners().len();
        // Every outline vertex after a corner lies on the segment between corners.
        assert!(outline.len() <= 2 * element.corners().len() + 4);
    }
    assert!(hanging > 0, "random refinement left no hanging vertex");
}
