//! The planes of a scene: its surfaces grouped by the plane they lie in
//! (either facing), the large ones first: where openings are looked for.

use std::collections::HashMap;

use glam::{DVec2, DVec3};

use crate::scene::{PlaneFrame, Scene, SurfaceId};

/// The surfaces lying in one plane, whichever way they face.
#[derive(Clone, Debug)]
pub(crate) struct PlaneGroup {
    /// The plane's frame: its normal is the canonical one (largest
    /// component positive); `u` follows the longest edge in the plane, so
    /// that a wall's rectangular hole has its sides along the axes.
    pub(crate) frame: PlaneFrame,
    /// The surfaces in the plane, in increasing order.
    pub(crate) surfaces: Vec<SurfaceId>,
    /// Their area in all.
    pub(crate) area: f64,
}

impl PlaneGroup {
    /// Each surface's polygon in plane coordinates.
    pub(crate) fn polygons(&self, scene: &Scene) -> Vec<Vec<DVec2>> {
        self.surfaces
            .iter()
            .map(|&id| {
                let surface = scene.surface(id);
                surface
                    .vertices()
                    .iter()
                    .map(|&p| self.frame.to_plane(p))
                    .collect()
            })
            .collect()
    }
}

/// The normal's sign turned so that its largest component is positive: a
/// plane's two faces share it.
fn canonical(normal: DVec3) -> DVec3 {
    let a = normal.abs();
    let largest = if a.x >= a.y && a.x >= a.z {
        normal.x
    } else if a.y >= a.z {
        normal.y
    } else {
        normal.z
    };
    if largest < 0.0 { -normal } else { normal }
}

/// The scene's surfaces grouped by plane: normals equal to 10⁻⁴ (either
/// sign), offsets within `tolerance`. Groups come largest first.
pub(crate) fn plane_groups(scene: &Scene, tolerance: f64) -> Vec<PlaneGroup> {
    // Normals bucketed on a 10⁻⁴ grid; offsets clustered within a bucket.
    let mut buckets: HashMap<[i64; 3], Vec<(f64, SurfaceId)>> = HashMap::new();
    for (id, surface) in scene.surfaces_with_ids() {
        let normal = canonical(surface.normal());
        let key = (normal * 1e4).round().to_array().map(|c| c as i64);
        let offset = normal.dot(surface.vertices()[0]);
        buckets.entry(key).or_default().push((offset, id));
    }
    let mut groups = Vec::new();
    for (key, mut members) in buckets {
        let normal = DVec3::new(key[0] as f64, key[1] as f64, key[2] as f64).normalize();
        members.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut start = 0;
        for k in 1..=members.len() {
            let split = k == members.len() || members[k].0 - members[k - 1].0 > tolerance;
            if split {
                groups.push(group_of(scene, normal, &members[start..k]));
                start = k;
            }
        }
    }
    groups.sort_by(|a, b| b.area.total_cmp(&a.area).then(a.surfaces.cmp(&b.surfaces)));
    groups
}

/// One plane's group from its members (offset, surface).
fn group_of(scene: &Scene, normal: DVec3, members: &[(f64, SurfaceId)]) -> PlaneGroup {
    let offset = members.iter().map(|m| m.0).sum::<f64>() / members.len() as f64;
    let mut surfaces: Vec<SurfaceId> = members.iter().map(|m| m.1).collect();
    surfaces.sort_unstable();
    let area = surfaces.iter().map(|&id| scene.surface(id).area()).sum();
    // The longest edge sets the in-plane axes.
    let mut longest = DVec3::ZERO;
    for &id in &surfaces {
        let vertices = scene.surface(id).vertices();
        for (k, &a) in vertices.iter().enumerate() {
            let edge = vertices[(k + 1) % vertices.len()] - a;
            if edge.length_squared() > longest.length_squared() {
                longest = edge;
            }
        }
    }
    PlaneGroup {
        frame: frame_along(normal * offset, normal, longest),
        surfaces,
        area,
    }
}

/// A frame at `origin` with unit `normal` whose `u` follows `along`
/// projected into the plane (any axis when that is nothing).
pub(crate) fn frame_along(origin: DVec3, normal: DVec3, along: DVec3) -> PlaneFrame {
    let in_plane = along - normal * along.dot(normal);
    let u = in_plane
        .try_normalize()
        .unwrap_or_else(|| normal.any_orthonormal_vector());
    PlaneFrame {
        origin,
        u,
        v: normal.cross(u),
        normal,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Material, Surface};

    #[test]
    fn coplanar_faces_of_either_side_group_together() {
        let mut scene = Scene::default();
        scene
            .materials
            .push(Material::diffuse("m", crate::rgb::Rgb::splat(0.5)));
        let square = |z: f64, x0: f64, flip: bool| {
            let mut v = vec![
                DVec3::new(x0, 0.0, z),
                DVec3::new(x0 + 1.0, 0.0, z),
                DVec3::new(x0 + 1.0, 1.0, z),
                DVec3::new(x0, 1.0, z),
            ];
            if flip {
                v.reverse();
            }
            Surface::new("s", 0, v).unwrap()
        };
        scene.surfaces = vec![
            square(0.0, 0.0, false),
            square(0.0, 2.0, true),
            square(1.0, 0.0, false),
        ];
        let groups = plane_groups(&scene, 1e-6);
        assert_eq!(groups.len(), 2);
        assert_eq!(groups[0].surfaces.len(), 2);
        assert!((groups[0].area - 2.0).abs() < 1e-12);
        assert!((groups[0].frame.normal - DVec3::Z).length() < 1e-12);
    }
}
