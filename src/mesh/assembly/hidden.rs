//! The hidden parts of a mesh: elements inside a closed object standing on
//! their surface, or under a parallel surface covering it, which no light
//! reaches and no viewer sees.

use glam::DVec3;
use rayon::prelude::*;

use super::contacts::{CONTACT_TOLERANCE, slot_gap};
use crate::mesh::data::topology::Mesh;
use crate::scene::{Scene, Surface, SurfaceId, Visibility};

/// Drops the elements of the given surfaces that lie inside a closed object
/// standing on them (under a block on a floor) or under a parallel surface
/// covering them (behind a ceiling panel, in the slot between two books):
/// no light reaches them and no viewer sees them. An element is hidden
/// when its centroid is ([`is_enclosed`]), each surface's slots judged
/// against its own contact tolerance (given with it).
/// `visibility` is the scene's BVH ([`Visibility::new`]).
pub(crate) fn remove_hidden_elements(
    mesh: &mut Mesh,
    scene: &Scene,
    visibility: &Visibility,
    surfaces: &[(SurfaceId, f64)],
) {
    let mut tolerance = vec![None; scene.surfaces.len()];
    for &(id, within) in surfaces {
        tolerance[id.index()] = Some(within);
    }
    let hidden: Vec<bool> = mesh
        .elements
        .par_iter()
        .map(|element| {
            tolerance[element.surface.index()].is_some_and(|within| {
                let centroid = element.corner_mean(|v| mesh.vertices[v as usize].position);
                is_enclosed_within(scene, visibility, element.surface, centroid, within)
            })
        })
        .collect();
    mesh.remove_elements(|index, _| hidden[index]);
}

/// Whether the point `x` of `surface` is hidden: at least 6 of 7 rays from
/// just above it, spread over its hemisphere, end on the back of a surface
/// (inside a closed object standing on it, whose one-sided surfaces face
/// outwards) or on a parallel surface facing it across a slot no wider
/// than `slot_gap` (between two books, where light dies within a gap's
/// width of the mouth).
#[must_use]
pub fn is_enclosed(scene: &Scene, visibility: &Visibility, surface: SurfaceId, x: DVec3) -> bool {
    let tolerance = CONTACT_TOLERANCE * visibility.diagonal();
    is_enclosed_within(scene, visibility, surface, x, tolerance)
}

/// [`is_enclosed`] with the contact `tolerance` the slots are judged
/// against ([`slot_gap`]): a thousandth of the surface's room's diagonal.
#[must_use]
pub fn is_enclosed_within(
    scene: &Scene,
    visibility: &Visibility,
    surface: SurfaceId,
    x: DVec3,
    tolerance: f64,
) -> bool {
    // Ten times the shadow rays' lift for a scene of the room's size: a
    // point lifted by the lift of a building's size would start inside
    // the slot behind an object 2 cm from a wall.
    let lift = tolerance / 10.0;
    let reach = visibility.diagonal();
    let receiver = scene.surface(surface);
    let normal = receiver.normal();
    let origin = x + normal * lift;
    // A facing surface covers the point when the hit lies no higher above
    // the receiver's plane than the slot is wide (a face tilted within the
    // parallel test's 2.5° may be near at one end and far at the other).
    let covers = |other: &Surface, height: f64| {
        other.normal().dot(normal) < -0.999 && height <= slot_gap(receiver, other, tolerance)
    };
    let is_closed = |direction: DVec3| {
        visibility
            .closest_hit(origin, direction, reach, surface)
            .is_some_and(|(hit, distance)| {
                let other = scene.surface(hit);
                let height = lift + distance * direction.dot(normal);
                other.normal().dot(direction) > 0.0 || covers(other, height)
            })
    };
    // Six of seven must be closed: the second open ray settles it, which
    // in the open (most elements) is the second ray cast.
    let mut open = 0;
    for direction in hemisphere_directions(normal) {
        if !is_closed(direction) {
            open += 1;
            if open > 1 {
                return false;
            }
        }
    }
    true
}

/// Seven directions over the hemisphere around `normal`: the normal and six
/// at 60° from it.
fn hemisphere_directions(normal: DVec3) -> [DVec3; 7] {
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    let mut directions = [normal; 7];
    for (k, direction) in directions.iter_mut().skip(1).enumerate() {
        let azimuth = std::f64::consts::TAU * k as f64 / 6.0;
        let (sin, cos) = azimuth.sin_cos();
        *direction = normal * 0.5 + (u * cos + v * sin) * 0.75f64.sqrt();
    }
    directions
}
