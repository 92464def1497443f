//! Shadow boundaries on a receiver: where an occluder's silhouette, seen
//! from an area light's corner, falls on the receiver's plane.
//!
//! Direct light changes its form across these lines: from a polygonal
//! area light, the outer and inner edges of every penumbra are pieces of the
//! shadows that the occluders cast from the area light's corners (the
//! vertex–edge events of discontinuity meshing). An element that straddles
//! one blurs the shadow over its whole width; with element edges along them,
//! the linear interpolation between vertices follows the penumbra instead.
//!
//! For each area light corner v in front of the receiver (a photometric
//! luminaire's centre counts as one corner) and each occluder
//! polygon in the shaft between them, every silhouette edge ab of the
//! occluder seen from v (an edge whose neighbour across it faces v the other
//! way, or that has none) is cut to the part in front of the receiver, below
//! v and in front of the area light, and projected centrally from v:
//! p ↦ v + (p − v) h_v / (h_v − h_p), with h the height over the receiver's
//! plane. The projected segment is clipped to the receiver's outline, and
//! to the parts of it where the event is real: where the receiver point
//! sees the edge point and the edge point sees v (shadow rays at
//! `EVENT_SAMPLES` + 1 points along the edge). An edge whose shadow falls
//! inside another occluder's umbra, or that v sees only through other
//! objects, bounds no penumbra there: a desk top's underside edges, a
//! chair's legs beneath its seat: the check keeps the boundaries to those
//! that bound a penumbra.
//!
//! # References
//! P. Heckbert, "Discontinuity meshing for radiosity", Eurographics Workshop
//! on Rendering 1992; D. Lischinski, F. Tampieri, D. P. Greenberg,
//! "Discontinuity meshing for accurate radiosity", IEEE CG&A 12(6) 1992.

mod cast;
mod edges;
mod merge;
#[cfg(test)]
mod tests;

use glam::{DVec2, DVec3};

use super::AreaLight;
use super::sample_stream::SampleStream;
use super::stratified::stratified_points;
use crate::scene::{Scene, ShadowCache, SurfaceId, Visibility, distance_to_boundary};
use cast::{Source, area_light_corners, horizon};
pub use edges::EdgeNeighbours;
use merge::merge_boundaries;

/// Heights within this fraction of the scene's diagonal count as on a plane.
const HEIGHT_TOLERANCE: f64 = 1e-3;

/// The surfaces that may shade a receiver within a box (its corners, min
/// and max): found by their bounding boxes (`SurfaceBoxes`), and only
/// those of the receiver's own closed room.
pub type OccludersIn<'a> = &'a (dyn Fn(DVec3, DVec3) -> Vec<SurfaceId> + Sync);

/// The boundaries a receiver keeps and what they may cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryLimits {
    /// Boundaries closer than this, and shorter ones, are merged or dropped:
    /// a feature the mesh cannot resolve. Scene units.
    pub min_feature: f64,
    /// The most boundaries one receiver keeps, longest first.
    pub max_per_receiver: usize,
}

/// A receiver of shadow boundaries, with what may shade it.
#[derive(Clone, Copy)]
pub struct ShadowReceiver<'a> {
    /// The surface the boundaries fall on.
    pub surface: SurfaceId,
    /// The surfaces that may shade it within a box.
    pub occluders: OccludersIn<'a>,
}

/// The shadow boundaries that `area_lights` and the point sources at
/// `points` (photometric luminaires' centres, or their luminous openings'
/// corners) cast on `receiver` through the surfaces its `occluders` finds
/// in the box around the receiver and each light's corners (the shaft
/// between them lies inside it: a silhouette point whose shadow falls on
/// the receiver lies on a segment from a corner to the receiver), in the
/// receiver's plane coordinates: merged
/// where closer than `limits.min_feature`, the longest
/// `limits.max_per_receiver` kept. Segments running along the receiver's
/// outline are left out (its edges are element edges already).
#[must_use]
pub fn shadow_boundaries(
    scene: &Scene,
    visibility: &Visibility,
    neighbours: &EdgeNeighbours,
    receiver: ShadowReceiver<'_>,
    area_lights: &[AreaLight],
    points: &[DVec3],
    limits: BoundaryLimits,
) -> Vec<[DVec2; 2]> {
    let target = scene.surface(receiver.surface);
    let frame = target.frame();
    let outline = target.plane_vertices();
    // The BVH keeps the scene's diagonal: `Scene::diagonal` visits every
    // vertex of the scene, once per receiver of a building.
    let tolerance = HEIGHT_TOLERANCE * visibility.diagonal();
    let mut found = Vec::new();
    for area_light in area_lights {
        if area_light.surfaces.contains(&receiver.surface) {
            continue;
        }
        // The receiver must have some part in front of the area light.
        let lit = target
            .vertices()
            .iter()
            .any(|&p| (p - area_light.centre).dot(area_light.normal) > tolerance);
        if !lit {
            continue;
        }
        // The horizon only matters where the area light lights the receiver.
        let corners = area_light_corners(scene, area_light);
        let lights_front = corners.iter().any(|&v| frame.height(v) > tolerance);
        if let Some(horizon) = horizon(frame, &outline, area_light).filter(|_| lights_front) {
            found.push(horizon);
        }
        let source = Source {
            corners,
            plane: Some((area_light.centre, area_light.normal)),
            surfaces: &area_light.surfaces,
        };
        source.cast(
            scene, visibility, neighbours, receiver, tolerance, &mut found,
        );
    }
    for &point in points {
        let source = Source {
            corners: vec![point],
            plane: None,
            surfaces: &[],
        };
        source.cast(
            scene, visibility, neighbours, receiver, tolerance, &mut found,
        );
    }
    found.retain(|&[a, b]| {
        let along_outline = [a, b, a.lerp(b, 0.5)]
            .iter()
            .all(|&p| distance_to_boundary(&outline, p) <= limits.min_feature);
        a.distance(b) >= limits.min_feature && !along_outline
    });
    merge_boundaries(found, limits)
}

/// Receiver points [`light_reaches`] tries: a 4 × 4 stratification.
const REACH_POINTS: usize = 16;

/// Whether any of the points `from` (an area light's centre and corners)
/// sees some part of `receiver`: a shadow ray from one of 16 stratified
/// points of the receiver (lifted a surface offset off it) to one of them
/// (stopped that far short, so the area light's own surface `lamp` does not
/// count) is unblocked. A receiver in another closed room, or wholly in
/// the umbra, sees none, and casting shadow boundaries on it would only
/// add vertices where no direct light falls. A receiver lit only through a
/// gap narrower than the samples can be missed: its shadows are then
/// meshed as if there were no boundaries.
#[must_use]
pub fn light_reaches(
    scene: &Scene,
    visibility: &Visibility,
    receiver: SurfaceId,
    from: &[DVec3],
    lamp: SurfaceId,
) -> bool {
    let surface = scene.surface(receiver);
    let (frame, n) = (surface.frame(), surface.normal());
    let offset = visibility.surface_offset();
    let mut random = SampleStream::new(u64::from(receiver), 0x5EE5_11A7);
    let points = stratified_points(&surface.plane_vertices(), REACH_POINTS, 0.01, &mut random);
    let mut cache = ShadowCache::default();
    points.iter().any(|&(p, _)| {
        let x = frame.to_world(p) + n * offset;
        from.iter().any(|&y| {
            let d = y - x;
            n.dot(d) > 0.0 && {
                let end = y - d.normalize_or_zero() * offset;
                visibility.is_unblocked_cached(x, end, [receiver, lamp], &mut cache)
            }
        })
    })
}
