//! Area lights: emitting surfaces grouped into the lamps they model.
//!
//! OBJ exports often split one lamp into several polygons (a quad into two
//! triangles, a panel into strips). For the dominant-emitter analysis and the
//! contour mesher a lamp is one emitter, so coplanar, touching emitting
//! surfaces of one material are joined into one [`AreaLight`].

use crate::scene::Box3;
use glam::DVec3;

use crate::rgb::Rgb;
use crate::scene::{Scene, Surface, SurfaceId};
use crate::union_find::root;

/// Normals of one area light's surfaces differ by at most this (unit vectors).
const NORMAL_TOLERANCE: f64 = 1e-6;

/// Distances (off the plane, between touching boundaries) below this
/// fraction of the scene's diagonal count as zero: the scale of
/// [`crate::scene::Visibility::surface_offset`].
const DISTANCE_TOLERANCE: f64 = 1e-5;

/// One lamp: coplanar emitting surfaces of one material that share an edge
/// or a vertex.
#[derive(Clone, Debug, PartialEq)]
pub struct AreaLight {
    /// Its surfaces, ascending.
    pub surfaces: Vec<SurfaceId>,
    /// Unit normal of its emitting side.
    pub normal: DVec3,
    /// Centroid of its area, c = Σ A_i c_i / Σ A_i over its surfaces.
    pub centre: DVec3,
    /// Total area, in the square of the scene's length unit.
    pub area: f64,
    /// The largest distance from `centre` to any of its vertices.
    pub radius: f64,
    /// Exitance E = π L_e per channel, W/m².
    pub exitance: Rgb,
}

/// Groups the scene's emitting surfaces into area lights. Surfaces of an
/// emitting body are left out: their luminaire lights the scene
/// ([`Scene::join_emitting_bodies`]).
///
/// Two emitting surfaces i, j belong to one area light when they share a
/// material, their unit normals differ by at most 10⁻⁶ (|n_i − n_j|), each
/// one's centroid lies within ε of the other's plane, and their boundaries
/// touch: a vertex of one lies within ε of an edge (or vertex) of the other.
/// ε is 10⁻⁵ of the scene's diagonal. Area lights are the connected groups of
/// this relation, ordered by their first surface.
///
/// # References
/// R. E. Tarjan, "Efficiency of a Good But Not Linear Set Union Algorithm",
/// JACM 22 (1975) (the union–find that joins the groups).
#[must_use]
pub fn area_lights(scene: &Scene) -> Vec<AreaLight> {
    let in_body = scene.in_emitting_body();
    let emitters: Vec<SurfaceId> = scene
        .surfaces_with_ids()
        .filter(|(id, surface)| !in_body[id.index()] && is_emitting(scene, surface))
        .map(|(id, _)| id)
        .collect();
    let tolerance = DISTANCE_TOLERANCE * scene.diagonal();
    // Join every touching coplanar pair of one material. Only emitters
    // whose boxes come within the tolerance can touch: swept in order of
    // their boxes' low x, each meets only those that start before its box
    // ends, not every other (a building has thousands of lamps).
    let boxes: Vec<(DVec3, DVec3)> = emitters
        .iter()
        .map(|&id| {
            let Box3 {
                min: low,
                max: high,
            } = scene.surface(id).bounds();
            (
                low - DVec3::splat(tolerance),
                high + DVec3::splat(tolerance),
            )
        })
        .collect();
    let mut by_low_x: Vec<usize> = (0..emitters.len()).collect();
    by_low_x.sort_by(|&a, &b| boxes[a].0.x.total_cmp(&boxes[b].0.x));
    let mut parent: Vec<usize> = (0..emitters.len()).collect();
    for (n, &a) in by_low_x.iter().enumerate() {
        for &b in &by_low_x[n + 1..] {
            if boxes[b].0.x > boxes[a].1.x {
                break;
            }
            let overlap = boxes[a].0.cmple(boxes[b].1).all() && boxes[b].0.cmple(boxes[a].1).all();
            let (sa, sb) = (scene.surface(emitters[a]), scene.surface(emitters[b]));
            if overlap && same_area_light(sa, sb, tolerance) {
                let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    // Collect the groups in order of their first surface.
    let mut groups: Vec<Vec<SurfaceId>> = Vec::new();
    let mut group_of_root = vec![usize::MAX; emitters.len()];
    for (k, &surface) in emitters.iter().enumerate() {
        let r = root(&mut parent, k);
        if group_of_root[r] == usize::MAX {
            group_of_root[r] = groups.len();
            groups.push(Vec::new());
        }
        groups[group_of_root[r]].push(surface);
    }
    groups
        .into_iter()
        .map(|surfaces| area_light_of(scene, surfaces))
        .collect()
}

/// True when `surface` has a material that emits.
fn is_emitting(scene: &Scene, surface: &Surface) -> bool {
    scene
        .materials
        .get(surface.material)
        .is_some_and(|m| m.is_emitter())
}

/// Whether two emitting surfaces are parts of one lamp.
fn same_area_light(a: &Surface, b: &Surface, tolerance: f64) -> bool {
    let coplanar = a.material == b.material
        && (a.normal() - b.normal()).length() <= NORMAL_TOLERANCE
        && a.frame().height(b.frame().origin).abs() <= tolerance
        && b.frame().height(a.frame().origin).abs() <= tolerance;
    coplanar
        && (touches(a.vertices(), b.vertices(), tolerance)
            || touches(b.vertices(), a.vertices(), tolerance))
}

/// Whether a vertex of `a` lies within `tolerance` of an edge of `b`.
fn touches(a: &[DVec3], b: &[DVec3], tolerance: f64) -> bool {
    a.iter().any(|&p| {
        (0..b.len()).any(|k| distance_to_segment(p, b[k], b[(k + 1) % b.len()]) <= tolerance)
    })
}

/// Distance from `p` to the segment [a, b].
fn distance_to_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let edge = b - a;
    let t = ((p - a).dot(edge) / edge.length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
    p.distance(a + edge * t)
}

/// The area light made of the given (non-empty) surfaces.
fn area_light_of(scene: &Scene, surfaces: Vec<SurfaceId>) -> AreaLight {
    // Area-weighted normal and centroid.
    let mut area = 0.0;
    let mut weighted_normal = DVec3::ZERO;
    let mut weighted_centre = DVec3::ZERO;
    for &id in &surfaces {
        let surface = scene.surface(id);
        area += surface.area();
        weighted_normal += surface.normal() * surface.area();
        weighted_centre += area_centroid(surface) * surface.area();
    }
    let centre = weighted_centre / area;
    let radius = surfaces
        .iter()
        .flat_map(|&id| scene.surface(id).vertices())
        .map(|v| v.distance(centre))
        .fold(0.0, f64::max);
    let first = scene.surface(surfaces[0]);
    AreaLight {
        normal: weighted_normal.normalize_or(first.normal()),
        centre,
        area,
        radius,
        exitance: scene.material_of(first).emitted_radiosity(),
        surfaces,
    }
}

/// The centroid of a surface's area (not of its vertices): the
/// signed-area-weighted mean of its fan triangles' centroids.
fn area_centroid(surface: &Surface) -> DVec3 {
    let v = surface.vertices();
    let n = surface.normal();
    let mut weighted = DVec3::ZERO;
    let mut total = 0.0;
    for [a, b, c] in surface.triangles() {
        let signed = 0.5 * (v[b] - v[a]).cross(v[c] - v[a]).dot(n);
        weighted += (v[a] + v[b] + v[c]) * (signed / 3.0);
        total += signed;
    }
    if total.abs() > 0.0 && weighted.is_finite() {
        weighted / total
    } else {
        surface.frame().origin
    }
}
