//! Where a solution is read: a point on a surface's front or in space
//! ([`ReadingPlace`]), the closed zones a set of places sees
//! ([`zones_read`]), and the surface a probe's point lies on
//! ([`locate_probe`]).

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::meshing::ZoneLabels;
use crate::scene::{
    ProbePoint, Scene, SurfaceId, Visibility, distance_to_boundary, polygon_contains,
};

/// Where a reading of a solution is taken, for choosing the rooms whose
/// ambient term it needs ([`crate::solver::Ambient::For`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ReadingPlace {
    /// A point on the front of a surface (a probe, a calculation grid's
    /// point on a floor): it sees what that front sees, which in a closed
    /// zone is the zone's own surfaces.
    OnSurface(SurfaceId),
    /// A point in space (a camera, a work plane's point): it sees the
    /// closed zone that encloses it, the one on whose surfaces 64 rays
    /// from it, spread over the sphere, all land, at least one on a front.
    InSpace(DVec3),
}

impl ReadingPlace {
    /// The place a probe reads: the front of the surface `point` lies on
    /// (as [`crate::Solution::probe`] finds it), or `None` on no surface.
    #[must_use]
    pub fn of_probe(scene: &Scene, point: &ProbePoint) -> Option<ReadingPlace> {
        locate_probe(scene, point).map(ReadingPlace::OnSurface)
    }

    /// The closed zone this place sees alone: its surface's, or the one
    /// that encloses the point ([`ZoneLabels::enclosing`], 64 rays);
    /// `None` in the open zone, or where a point's rays leave the scene,
    /// land in another zone, or all on backs.
    #[must_use]
    pub(crate) fn zone(
        &self,
        labels: &ZoneLabels,
        scene: &Scene,
        visibility: &Visibility,
    ) -> Option<usize> {
        match *self {
            // A surface not of this scene is in no zone.
            ReadingPlace::OnSurface(surface) if surface.index() >= scene.surfaces.len() => None,
            ReadingPlace::OnSurface(surface) => {
                let zone = labels.of(surface);
                labels.is_lossless(zone).then_some(zone)
            }
            ReadingPlace::InSpace(point) => labels.enclosing(scene, visibility, point),
        }
    }
}

/// The closed zones that readings at `places` see, ascending
/// ([`ReadingPlace::zone`], the places in parallel); `None` (they need
/// the whole solution) when any place lies in no closed zone, or when
/// no place is given.
#[must_use]
pub(crate) fn zones_read(
    labels: &ZoneLabels,
    scene: &Scene,
    visibility: &Visibility,
    places: &[ReadingPlace],
) -> Option<Vec<usize>> {
    if places.is_empty() {
        return None;
    }
    let mut zones: Vec<usize> = places
        .par_iter()
        .map(|place| place.zone(labels, scene, visibility))
        .collect::<Option<_>>()?;
    zones.sort_unstable();
    zones.dedup();
    Some(zones)
}

/// The surface a probe's point lies on: within 10⁻⁴ of the scene's diagonal of
/// its plane and inside (or on the edge of) its polygon, facing along
/// the point's normal if it has one; the nearest plane wins.
pub(crate) fn locate_probe(scene: &Scene, point: &ProbePoint) -> Option<SurfaceId> {
    let tolerance = 1e-4 * scene.diagonal();
    let mut best: Option<(SurfaceId, f64)> = None;
    for (id, surface) in scene.surfaces_with_ids() {
        if point.normal.is_some_and(|n| n.dot(surface.normal()) < 0.99) {
            continue;
        }
        let height = surface.frame().height(point.position).abs();
        if height > tolerance || best.is_some_and(|(_, h)| h <= height) {
            continue;
        }
        let plane_point = surface.frame().to_plane(point.position);
        if distance_outside_polygon(plane_point, &surface.plane_vertices()) <= tolerance {
            best = Some((id, height));
        }
    }
    best.map(|(id, _)| id)
}

/// Distance from a point outside a polygon to it (0 when inside).
fn distance_outside_polygon(p: DVec2, polygon: &[DVec2]) -> f64 {
    if polygon_contains(polygon, p) {
        0.0
    } else {
        distance_to_boundary(polygon, p)
    }
}
