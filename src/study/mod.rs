//! Studies of the meshers: contour meshes against square meshes on the
//! receivers lit by a dominant small emitter (vertices and interpolation
//! error), and the pictures that show them: log–log plots
//! ([`write_loglog_plot`]) and meshes side by side ([`write_mesh_panels`]),
//! which take plain data and draw text with the bundled DejaVu Sans
//! (`assets/fonts`). Nothing else in isorad imports this module.
//!
//! For each receiver, every mesh gets the exact direct radiosity of the
//! dominant luminaire at its vertices (visibility included), and its
//! piecewise-linear interpolation is compared with the exact value on a
//! dense grid of points inside the receiver (DESIGN.md, "How the error of a
//! mesh is measured"). The vertex values are exact, so the error is the
//! mesh's alone.

mod mesh_panels;
mod plot;
mod records;

pub use mesh_panels::{MeshPanel, write_mesh_panels};
pub use plot::{Series, write_loglog_plot};
pub use records::{MeshRecord, MeshSpec, ReceiverComparison, write_json};

use records::Built;

use glam::DVec2;
use std::time::Instant;

use crate::lighting::DirectField;
use crate::lighting::luminaires;
use crate::mesh::{
    ContourSettings, ErrorGrid, GreedySettings, PlaneTriangulation, SampledField,
    SquareMeshSettings, greedy_insertion, is_enclosed, mesh_square,
};
use crate::meshing::{MeshSettings, field_layout, receiver_shadow_boundaries, total_field_layout};
use crate::scene::{Scene, SurfaceId, Visibility};

/// What a comparison meshes and how finely it measures.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct CompareSettings {
    /// N of the square N × N meshes.
    pub square_sizes: Vec<usize>,
    /// (D, K) of the fixed contour meshes.
    pub contour_sizes: Vec<(usize, usize)>,
    /// Relative errors, in thousandths, that contour meshes are refined to
    /// (`ContourSettings::max_relative_error`).
    pub contour_errors_per_mille: Vec<u32>,
    /// The error is measured on a `grid` × `grid` lattice over the receiver.
    pub grid: usize,
    /// Shadow rays per luminaire polygon for the exact field's visibility.
    pub shadow_rays: usize,
    /// The contour meshes refined to an error (radial and level lines)
    /// follow the receiver's shadow boundaries, as the renderer's meshes do,
    /// and the fixed D × K layouts are measured a second time with them
    /// ([`MeshSpec::ShadowContour`]) where the receiver has any (true); the
    /// fixed layouts themselves are the seed's, without them.
    pub shadow_boundaries: bool,
    /// Vertex budgets of the greedy-insertion meshes
    /// ([`MeshSpec::Greedy`]), on the field sampled with visibility.
    pub greedy_vertices: Vec<usize>,
    /// Lattice cells along the receiver's longer side on which the
    /// greedy-insertion meshes sample the field (a lattice apart from the
    /// error grid's).
    pub greedy_lattice: usize,
    /// The mesh settings the renderer would use (a scene file's `[mesh]`):
    /// the element spacing the level lines fill gaps to and the shadow
    /// boundaries are merged at.
    pub mesh: MeshSettings,
}

impl Default for CompareSettings {
    /// Square 5…40; contour the seed's sizes (10×3 … 80×12), the
    /// balanced D = 2K sizes that do best per vertex, and contour meshes
    /// refined to 8, 4, 2, 1 and 0.5 %; a 400² grid.
    fn default() -> Self {
        CompareSettings {
            square_sizes: vec![5, 10, 20, 30, 40],
            contour_sizes: vec![
                (10, 3),
                (20, 5),
                (40, 8),
                (80, 12),
                (8, 4),
                (12, 6),
                (16, 8),
                (24, 12),
                (32, 16),
            ],
            contour_errors_per_mille: vec![80, 40, 20, 10, 5],
            grid: 400,
            shadow_rays: 16,
            shadow_boundaries: true,
            greedy_vertices: vec![50, 100, 200, 300, 500, 800],
            greedy_lattice: 192,
            mesh: MeshSettings::default(),
        }
    }
}

/// Shadow rays per luminaire polygon where the first `shadow_rays` find a
/// penumbra: stratified 32 × 32, they put the visible fraction's own error
/// near 0.1 %.
const PENUMBRA_SHADOW_RAYS: usize = 1024;

/// Meshes one receiver every way `settings` lists and measures each mesh
/// against the exact direct light of `fields` on it, with visibility: the
/// light of one area or photometric luminaire
/// ([`crate::lighting::dominant_field`]), for which the radial contour
/// meshes are built, or of several (only level lines and square meshes).
/// The exact field sums each light's unoccluded field times its visible
/// fraction, from `shadow_rays` rays per luminaire polygon, or 1024 where
/// those find a penumbra; points inside an object standing on the receiver
/// (a block's footprint, [`is_enclosed`]) are left out, as the renderer's
/// mesh leaves out its elements there. The greedy-insertion meshes see the
/// same field only at the samples of their own lattice
/// (`greedy_lattice`), not at the error grid's points.
#[must_use]
pub fn compare_receiver(
    scene: &Scene,
    visibility: &Visibility,
    receiver: SurfaceId,
    fields: &[DirectField],
    settings: &CompareSettings,
) -> ReceiverComparison {
    let surface = scene.surface(receiver);
    let outline = surface.plane_vertices();
    let frame = surface.frame();
    let exact = |p: DVec2| {
        fields
            .iter()
            .map(|field| {
                let value = field.value(p);
                if value <= 0.0 {
                    return 0.0;
                }
                let coarse = field.visible_fraction(visibility, p, settings.shadow_rays);
                let visible = if coarse > 0.0 && coarse < 1.0 {
                    field.visible_fraction(visibility, p, PENUMBRA_SHADOW_RAYS)
                } else {
                    coarse
                };
                value * visible
            })
            .sum::<f64>()
    };
    // Points inside an object standing on the receiver are left out, as the
    // renderer's mesh leaves out the elements there.
    let measured = |p: DVec2| {
        if is_enclosed(scene, visibility, receiver, frame.to_world(p)) {
            f64::NAN
        } else {
            exact(p)
        }
    };
    let grid = ErrorGrid::new(&outline, settings.grid.max(200), &measured);
    let mut comparison = ReceiverComparison {
        receiver: surface.name.clone(),
        surface: receiver,
        outline: outline.clone(),
        records: Vec::new(),
    };
    for &n in &settings.square_sizes {
        let start = Instant::now();
        let triangulation = square_triangulation(scene, receiver, n, &exact);
        let seconds = start.elapsed().as_secs_f64();
        let built = Built {
            spec: MeshSpec::Square { n },
            newton_iterations: 0,
            shadow_points: 0,
            seconds,
        };
        comparison.add(built, triangulation, &exact, &grid);
    }
    let fixed = settings.contour_sizes.iter().map(|&(directions, levels)| {
        let contour = ContourSettings {
            directions,
            levels,
            max_relative_error: 0.0,
            ..ContourSettings::default()
        };
        (MeshSpec::Contour { directions, levels }, contour)
    });
    let refined = settings.contour_errors_per_mille.iter().map(|&per_mille| {
        let contour = ContourSettings {
            max_relative_error: f64::from(per_mille) / 1000.0,
            ..ContourSettings::default()
        };
        (MeshSpec::ContourToError { per_mille }, contour)
    });
    let mesh_settings = &settings.mesh;
    let square_settings = mesh_settings.square_for(scene);
    let boundaries = if settings.shadow_boundaries {
        let lights = luminaires(scene);
        receiver_shadow_boundaries(scene, visibility, &lights, mesh_settings, receiver)
    } else {
        Vec::new()
    };
    // The seed's layouts again with the shadow boundaries, where there are
    // any.
    let shadow_aware: Vec<(MeshSpec, ContourSettings)> = if boundaries.is_empty() {
        Vec::new()
    } else {
        fixed
            .clone()
            .filter_map(|(spec, contour)| match spec {
                MeshSpec::Contour { directions, levels } => {
                    Some((MeshSpec::ShadowContour { directions, levels }, contour))
                }
                _ => None,
            })
            .collect()
    };
    let radial: Vec<(MeshSpec, ContourSettings)> = match fields {
        [_] => fixed.chain(shadow_aware).chain(refined).collect(),
        _ => Vec::new(),
    };
    let spacing = square_settings.max_edge;
    for (spec, contour) in radial {
        let start = Instant::now();
        let Some(mut layout) =
            field_layout(scene, visibility, receiver, fields[0].clone(), &contour)
        else {
            continue;
        };
        match spec {
            // At the element spacing, as the renderer's meshes have them.
            MeshSpec::ContourToError { .. } => layout.add_boundaries(&boundaries, spacing),
            // Only their ends: the triangulation puts a vertex wherever
            // they cross a contour piece.
            MeshSpec::ShadowContour { .. } => layout.add_boundaries(&boundaries, f64::INFINITY),
            _ => {}
        }
        let triangulation = layout.triangulate(&outline);
        let seconds = start.elapsed().as_secs_f64();
        let built = Built {
            spec,
            newton_iterations: layout.newton_iterations,
            shadow_points: layout.shadow_points,
            seconds,
        };
        comparison.add(built, triangulation, &exact, &grid);
    }
    for &per_mille in &settings.contour_errors_per_mille {
        let start = Instant::now();
        let contour = ContourSettings {
            max_relative_error: f64::from(per_mille) / 1000.0,
            ..ContourSettings::default()
        };
        let Some(mut layout) =
            total_field_layout(scene, receiver, fields, &contour, &square_settings)
        else {
            continue;
        };
        layout.add_boundaries(&boundaries, spacing);
        let triangulation = layout.triangulate(&outline);
        let built = Built {
            spec: MeshSpec::LevelLines { per_mille },
            newton_iterations: layout.newton_iterations,
            shadow_points: layout.shadow_points,
            seconds: start.elapsed().as_secs_f64(),
        };
        comparison.add(built, triangulation, &exact, &grid);
    }
    if !settings.greedy_vertices.is_empty() {
        let start = Instant::now();
        let sampled = SampledField::sample(&outline, settings.greedy_lattice, &measured);
        let sampling = start.elapsed().as_secs_f64();
        for &vertices in &settings.greedy_vertices {
            let start = Instant::now();
            let greedy = GreedySettings {
                max_vertices: vertices,
                rms_rel_error: 0.0,
            };
            let (triangulation, _) = greedy_insertion(&outline, &sampled, &exact, &[], &greedy);
            let built = Built {
                spec: MeshSpec::Greedy { vertices },
                newton_iterations: 0,
                shadow_points: 0,
                seconds: sampling + start.elapsed().as_secs_f64(),
            };
            comparison.add(built, triangulation, &exact, &grid);
        }
    }
    comparison
}

/// The square N × N mesh of a receiver (a lattice of N divisions if it is
/// not a quad), split into triangles along the diagonals the renderer picks.
fn square_triangulation(
    scene: &Scene,
    receiver: SurfaceId,
    n: usize,
    exact: &dyn Fn(DVec2) -> f64,
) -> PlaneTriangulation {
    let surface = scene.surface(receiver);
    let alone = Scene {
        surfaces: vec![surface.clone()],
        materials: scene.materials.clone(),
        ..Scene::default()
    };
    let mut settings = SquareMeshSettings::for_scene(&alone);
    settings.elements_per_side = Some(n);
    let mesh = mesh_square(&alone, &settings);
    let frame = surface.frame();
    let points: Vec<DVec2> = mesh
        .vertices
        .iter()
        .map(|v| frame.to_plane(v.position))
        .collect();
    let values: Vec<f64> = points.iter().map(|&p| exact(p)).collect();
    let gap = |a: u32, b: u32| (values[a as usize] - values[b as usize]).abs();
    let mut triangles = Vec::new();
    for element in &mesh.elements {
        let (split, count) = element.triangles(gap);
        triangles.extend(split[..count].iter().map(|t| t.map(|v| v as usize)));
    }
    PlaneTriangulation { points, triangles }
}

/// The seed paper's Figure 5 trio and the meshes isorad renders with,
/// where measured: square 10×10 | contour 20×5 (the seed's) |
/// shadow-aware contour 20×5 | contour refined to 1 % | level lines to
/// 1 % | greedy insertion to 300 vertices | square 30×30, with their exact
/// vertex values.
#[must_use]
pub fn panels_for_figure(comparison: &ReceiverComparison) -> Vec<MeshPanel> {
    [
        MeshSpec::Square { n: 10 },
        MeshSpec::Contour {
            directions: 20,
            levels: 5,
        },
        MeshSpec::ShadowContour {
            directions: 20,
            levels: 5,
        },
        MeshSpec::ContourToError { per_mille: 10 },
        MeshSpec::LevelLines { per_mille: 10 },
        MeshSpec::Greedy { vertices: 300 },
        MeshSpec::Square { n: 30 },
    ]
    .into_iter()
    .filter_map(|spec| comparison.record(spec))
    .map(|record| MeshPanel {
        title: record.spec.to_string(),
        points: record.triangulation.points.clone(),
        values: record.values.clone(),
        triangles: record.triangulation.triangles.clone(),
        outline: comparison.outline.clone(),
    })
    .collect()
}
