//! How much of the sky a ray reaches: 1 through open air, τ(θ) through
//! each glazing pane it crosses, 0 when anything opaque is in the way.

use glam::DVec3;

use crate::daylight::pane_transmittance;
use crate::scene::{Scene, SurfaceId, Visibility};

/// The most panes a ray crosses before it is taken as blocked.
const MAX_PANES: usize = 8;

/// The transmittance from `origin` along unit `direction` to the sky: the
/// product of τ(θ) over the glazing panes crossed (θ the angle to each
/// pane's normal, [`pane_transmittance`]), or 0 when an opaque surface
/// blocks the ray. `ignore` is the surface the ray leaves.
#[must_use]
pub fn sky_transmittance(
    scene: &Scene,
    visibility: &Visibility,
    origin: DVec3,
    direction: DVec3,
    ignore: SurfaceId,
) -> f64 {
    let reach = 4.0 * visibility.diagonal();
    let mut transmittance = 1.0;
    let (mut from, mut ignore) = (origin, ignore);
    for _ in 0..MAX_PANES {
        let Some((surface, distance)) = visibility.closest_hit(from, direction, reach, ignore)
        else {
            return transmittance;
        };
        let hit = scene.surface(surface);
        let material = scene.material_of(hit);
        if !material.is_glazing() {
            return 0.0;
        }
        let cos_theta = hit.normal().dot(direction).abs();
        transmittance *= pane_transmittance(material.transmittance, cos_theta);
        if transmittance <= 0.0 {
            return 0.0;
        }
        from += direction * distance;
        ignore = surface;
    }
    0.0
}
