//! Portals: where daylight comes into a model, sampled as sources. The
//! openings found in its geometry and its glazing panes.
//!
//! The portals split the directions a point sees the sky in: a ray that
//! reaches the sky counts for the first portal it crosses, and for no
//! portal when it crosses none ([`Portals::first_crossed`]). So a
//! direction counts once however the portals overlap as seen from the
//! point.

use glam::DVec3;

use crate::scene::{Scene, SurfaceId};

use super::openings::find_openings;

/// What a portal is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PortalKind {
    /// A hole in the model.
    Opening,
    /// A glazing surface.
    Glazing(SurfaceId),
}

/// One portal: a planar polygon as triangles.
#[derive(Clone, Debug, PartialEq)]
pub struct Portal {
    /// What it is.
    pub kind: PortalKind,
    /// Its triangles.
    pub triangles: Vec<[DVec3; 3]>,
    /// Its plane's unit normal (either side).
    pub normal: DVec3,
}

/// A scene's portals.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Portals {
    /// Openings first, then panes, in the scene's order.
    pub portals: Vec<Portal>,
}

impl Portals {
    /// The openings `find_openings` finds and every glazing surface.
    #[must_use]
    pub fn of_scene(scene: &Scene) -> Portals {
        let mut portals: Vec<Portal> = find_openings(scene)
            .into_iter()
            .map(|opening| {
                let c = opening.corners;
                Portal {
                    kind: PortalKind::Opening,
                    triangles: vec![[c[0], c[1], c[2]], [c[0], c[2], c[3]]],
                    normal: opening.normal,
                }
            })
            .collect();
        for (id, surface) in scene.surfaces_with_ids() {
            if !scene.material_of(surface).is_glazing() {
                continue;
            }
            let vertices = surface.vertices();
            let triangles = surface
                .triangles()
                .into_iter()
                .map(|[a, b, c]| [vertices[a], vertices[b], vertices[c]])
                .collect();
            portals.push(Portal {
                kind: PortalKind::Glazing(id),
                triangles,
                normal: surface.normal(),
            });
        }
        Portals { portals }
    }

    /// The index of the first portal the ray from `origin` along unit
    /// `direction` crosses, with the distance to it.
    #[must_use]
    pub fn first_crossed(&self, origin: DVec3, direction: DVec3) -> Option<(usize, f64)> {
        let mut first: Option<(usize, f64)> = None;
        for (index, portal) in self.portals.iter().enumerate() {
            for triangle in &portal.triangles {
                if let Some(t) = ray_triangle(origin, direction, triangle)
                    && first.is_none_or(|(_, best)| t < best)
                {
                    first = Some((index, t));
                }
            }
        }
        first
    }
}

/// The distance along the ray (origin, unit direction) to triangle `t`,
/// if it crosses it ahead (Möller–Trumbore, either side).
fn ray_triangle(origin: DVec3, direction: DVec3, t: &[DVec3; 3]) -> Option<f64> {
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let p = direction.cross(e2);
    let det = e1.dot(p);
    if det.abs() <= 1e-14 * e1.length_squared().max(e2.length_squared()) {
        return None;
    }
    let s = origin - t[0];
    let u = s.dot(p) / det;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = direction.dot(q) / det;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let distance = e2.dot(q) / det;
    (distance > 0.0).then_some(distance)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ray_crosses_the_nearer_portal_first() {
        let square = |z: f64| Portal {
            kind: PortalKind::Opening,
            triangles: vec![
                [
                    DVec3::new(-1.0, -1.0, z),
                    DVec3::new(1.0, -1.0, z),
                    DVec3::new(1.0, 1.0, z),
                ],
                [
                    DVec3::new(-1.0, -1.0, z),
                    DVec3::new(1.0, 1.0, z),
                    DVec3::new(-1.0, 1.0, z),
                ],
            ],
            normal: DVec3::Z,
        };
        let portals = Portals {
            portals: vec![square(3.0), square(2.0)],
        };
        let (index, t) = portals.first_crossed(DVec3::ZERO, DVec3::Z).unwrap();
        assert_eq!(index, 1);
        assert!((t - 2.0).abs() < 1e-12);
        assert!(portals.first_crossed(DVec3::ZERO, DVec3::NEG_Z).is_none());
        assert!(
            portals
                .first_crossed(DVec3::ZERO, DVec3::new(0.9, 0.0, 0.1).normalize())
                .is_none()
        );
    }
}
