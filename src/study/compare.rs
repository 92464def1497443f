//! One receiver meshed every way a comparison lists, each mesh measured
//! against the exact direct light on it.

use std::time::Instant;

use glam::DVec2;

use super::records::Built;
use super::{CompareSettings, MeshSpec, ReceiverComparison};
use crate::lighting::{DirectField, area_lights};
use crate::mesh::{
    ContourSettings, ErrorGrid, GreedySettings, PlaneTriangulation, SampledField,
    SquareMeshSettings, greedy_insertion, is_enclosed, mesh_square,
};
use crate::meshing::{
    ResolvedMeshSettings, field_layout, receiver_shadow_boundaries, total_field_layout,
};
use crate::scene::{Scene, SurfaceId, Visibility};

/// Shadow rays per light polygon where the first `shadow_rays` find a
/// penumbra: stratified 32 × 32, they put the visible fraction's own error
/// near 0.1 %.
const PENUMBRA_SHADOW_RAYS: usize = 1024;

/// Meshes one receiver every way `settings` lists and measures each mesh
/// against the exact direct light of `fields` on it, with visibility: the
/// light of one area or photometric luminaire
/// ([`crate::lighting::dominant_field`]), for which the radial contour
/// meshes are built, or of several (only level lines and square meshes).
/// The exact field sums each light's unoccluded field times its visible
/// fraction, from `shadow_rays` rays per light polygon, or 1024 where
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
    let light = ExactLight {
        scene,
        visibility,
        receiver,
        fields,
        shadow_rays: settings.shadow_rays,
    };
    let surface = scene.surface(receiver);
    let outline = surface.plane_vertices();
    let grid = ErrorGrid::new(&outline, settings.grid.max(200), &|p| light.measured(p));
    let mut bench = Bench {
        light,
        grid,
        comparison: ReceiverComparison {
            receiver: surface.name.clone(),
            surface: receiver,
            outline: outline.clone(),
            records: Vec::new(),
        },
    };
    // The square N × N meshes.
    for &n in &settings.square_sizes {
        let start = Instant::now();
        let triangulation = square_triangulation(scene, receiver, n, &|p| bench.light.exact(p));
        let seconds = start.elapsed().as_secs_f64();
        let built = Built {
            spec: MeshSpec::Square { n },
            newton_iterations: 0,
            shadow_points: 0,
            seconds,
        };
        bench.add(built, triangulation);
    }
    // The shadow boundaries the renderer's meshes would follow.
    let mesh_settings = settings.mesh.resolve(scene);
    let boundaries = if settings.shadow_boundaries {
        let lights = area_lights(scene);
        receiver_shadow_boundaries(scene, visibility, &lights, &mesh_settings, receiver)
    } else {
        Vec::new()
    };
    // The radial contour meshes, of a single light.
    if let [field] = fields {
        add_radial_meshes(&mut bench, field, settings, &mesh_settings, &boundaries);
    }
    // The level lines of the total field.
    add_level_line_meshes(&mut bench, settings, &mesh_settings, &boundaries);
    // Greedy insertion on the field sampled on its own lattice.
    if !settings.greedy_vertices.is_empty() {
        add_greedy_meshes(&mut bench, settings);
    }
    bench.comparison
}

/// The exact direct light of `fields` on a receiver, with visibility.
struct ExactLight<'a> {
    scene: &'a Scene,
    visibility: &'a Visibility,
    receiver: SurfaceId,
    fields: &'a [DirectField],
    /// Shadow rays per light polygon, before a penumbra's 1024.
    shadow_rays: usize,
}

impl ExactLight<'_> {
    /// The light at `p`: each field's value times its visible fraction.
    fn exact(&self, p: DVec2) -> f64 {
        self.fields
            .iter()
            .map(|field| {
                let value = field.value(p);
                if value <= 0.0 {
                    return 0.0;
                }
                let coarse = field.visible_fraction(self.visibility, p, self.shadow_rays);
                let visible = if coarse > 0.0 && coarse < 1.0 {
                    field.visible_fraction(self.visibility, p, PENUMBRA_SHADOW_RAYS)
                } else {
                    coarse
                };
                value * visible
            })
            .sum::<f64>()
    }

    /// [`ExactLight::exact`], or NaN at a point inside an object standing
    /// on the receiver: left out, as the renderer's mesh leaves out the
    /// elements there.
    fn measured(&self, p: DVec2) -> f64 {
        let frame = self.scene.surface(self.receiver).frame();
        if is_enclosed(
            self.scene,
            self.visibility,
            self.receiver,
            frame.to_world(p),
        ) {
            f64::NAN
        } else {
            self.exact(p)
        }
    }
}

/// A receiver under comparison: its exact light, the grid its meshes'
/// errors are measured on, and the records so far.
struct Bench<'a> {
    light: ExactLight<'a>,
    grid: ErrorGrid,
    comparison: ReceiverComparison,
}

impl Bench<'_> {
    /// Measures `triangulation` with exact vertex values and records it.
    fn add(&mut self, built: Built, triangulation: PlaneTriangulation) {
        let light = &self.light;
        let exact = |p: DVec2| light.exact(p);
        self.comparison
            .add(built, triangulation, &exact, &self.grid);
    }
}

/// The radial contour meshes of `field`: the fixed D × K layouts, again
/// with the shadow boundaries where there are any, and the layouts refined
/// to an error, which follow the boundaries as the renderer's do.
fn add_radial_meshes(
    bench: &mut Bench,
    field: &DirectField,
    settings: &CompareSettings,
    mesh_settings: &ResolvedMeshSettings,
    boundaries: &[[DVec2; 2]],
) {
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
    let radial: Vec<(MeshSpec, ContourSettings)> =
        fixed.chain(shadow_aware).chain(refined).collect();
    let spacing = mesh_settings.square.max_edge;
    let (scene, visibility, receiver) = (
        bench.light.scene,
        bench.light.visibility,
        bench.light.receiver,
    );
    let outline = scene.surface(receiver).plane_vertices();
    for (spec, contour) in radial {
        let start = Instant::now();
        let Some(mut layout) = field_layout(scene, visibility, receiver, field.clone(), &contour)
        else {
            continue;
        };
        match spec {
            // At the element spacing, as the renderer's meshes have them.
            MeshSpec::ContourToError { .. } => layout.add_boundaries(boundaries, spacing),
            // Only their ends: the triangulation puts a vertex wherever
            // they cross a contour piece.
            MeshSpec::ShadowContour { .. } => layout.add_boundaries(boundaries, f64::INFINITY),
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
        bench.add(built, triangulation);
    }
}

/// The level-line meshes of the total direct field, refined to each
/// error, along the shadow boundaries at the element spacing.
fn add_level_line_meshes(
    bench: &mut Bench,
    settings: &CompareSettings,
    mesh_settings: &ResolvedMeshSettings,
    boundaries: &[[DVec2; 2]],
) {
    let (scene, receiver, fields) = (bench.light.scene, bench.light.receiver, bench.light.fields);
    let outline = scene.surface(receiver).plane_vertices();
    let square = &mesh_settings.square;
    for &per_mille in &settings.contour_errors_per_mille {
        let start = Instant::now();
        let contour = ContourSettings {
            max_relative_error: f64::from(per_mille) / 1000.0,
            ..ContourSettings::default()
        };
        let Some(mut layout) = total_field_layout(scene, receiver, fields, &contour, square) else {
            continue;
        };
        layout.add_boundaries(boundaries, square.max_edge);
        let triangulation = layout.triangulate(&outline);
        let built = Built {
            spec: MeshSpec::LevelLines { per_mille },
            newton_iterations: layout.newton_iterations,
            shadow_points: layout.shadow_points,
            seconds: start.elapsed().as_secs_f64(),
        };
        bench.add(built, triangulation);
    }
}

/// The greedy-insertion meshes, to each vertex budget, on the measured
/// field sampled on their own lattice (the sampling's time counted in
/// each).
fn add_greedy_meshes(bench: &mut Bench, settings: &CompareSettings) {
    let outline = bench.comparison.outline.clone();
    let start = Instant::now();
    let measured = |p: DVec2| bench.light.measured(p);
    let sampled = SampledField::sample(&outline, settings.greedy_lattice, &measured);
    let sampling = start.elapsed().as_secs_f64();
    for &vertices in &settings.greedy_vertices {
        let start = Instant::now();
        let greedy = GreedySettings {
            max_vertices: vertices,
            rms_rel_error: 0.0,
        };
        let exact = |p: DVec2| bench.light.exact(p);
        let (triangulation, _) = greedy_insertion(&outline, &sampled, &exact, &[], &greedy);
        let built = Built {
            spec: MeshSpec::Greedy { vertices },
            newton_iterations: 0,
            shadow_points: 0,
            seconds: sampling + start.elapsed().as_secs_f64(),
        };
        bench.add(built, triangulation);
    }
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
