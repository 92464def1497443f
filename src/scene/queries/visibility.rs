//! Shadow-ray visibility over an obvhs compressed wide BVH: the tree, segment
//! and closest-hit queries. The shadow cache's query is in the
//! `shadow_cache` module, the shaft queries in `shaft_queries`.

use glam::{DVec3, UVec2, Vec3A};
use obvhs::{
    BvhBuildParams, cwbvh::CwBvh, cwbvh::builder::build_cwbvh_from_tris, ray::Ray,
    rt_triangle::RtTriangle, triangle::Triangle,
};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

use crate::scene::{Box3, Scene, SurfaceId};

/// The surface offset as a fraction of the scene's diagonal (see
/// [`Visibility::surface_offset`]).
const SURFACE_OFFSET: f64 = 2e-6;

/// The distance segment ends are lifted off their surfaces in a scene of
/// diagonal `diagonal` ([`Visibility::surface_offset`]).
#[must_use]
pub(crate) fn surface_offset_for(diagonal: f64) -> f64 {
    SURFACE_OFFSET * diagonal.max(f64::MIN_POSITIVE)
}

/// Answers "is the open segment between two points unblocked?" for a scene.
///
/// Every surface is triangulated into an 8-wide compressed BVH (Ylitie et al.
/// 2017, built by obvhs's PLOC builder). Surfaces block light from both sides.
/// Coordinates are stored in f32 relative to the scene's centre and in units
/// of about its half-diagonal (a power of two), so scenes far from the origin
/// keep their precision and scenes measured in 10⁻³⁰ or 10³⁰ neither
/// underflow nor overflow f32. The structure is plain data and is
/// shared by all rayon workers.
///
/// The BVH holds each face as its file gave it ([`Surface::occluder_vertices`]),
/// so faces meet exactly where the file says they do. A segment's two end
/// surfaces never block it (a planar surface cannot block a segment leaving
/// its front), and callers also lift end points off their surfaces (see
/// [`Visibility::surface_offset`]): no self-shadowing speckle on flat walls.
///
/// [`Surface::occluder_vertices`]: crate::scene::Surface::occluder_vertices
pub struct Visibility {
    /// Tells this BVH's [`ShadowCache`] entries from another's.
    pub(super) id: u64,
    pub(super) bvh: CwBvh,
    /// Triangles in the BVH's primitive order (`bvh.primitive_indices` applied).
    pub(super) triangles: Vec<RtTriangle>,
    /// The surface of each triangle, in the same order.
    pub(super) triangle_surfaces: Vec<SurfaceId>,
    pub(super) centre: DVec3,
    /// World length of one BVH unit: the power of two nearest the scene's
    /// half-diagonal.
    pub(super) scale: f64,
    pub(super) surface_offset: f64,
    /// The whole scene's bounding-box diagonal.
    diagonal: f64,
}

impl Visibility {
    /// Builds the BVH over every surface of the scene.
    #[must_use]
    pub fn new(scene: &Scene) -> Visibility {
        Visibility::of_surfaces(scene, |_| true)
    }

    /// Builds the BVH over the surfaces of the scene that `keep` selects,
    /// in the whole scene's coordinates: the same triangles, to the bit, as
    /// [`Visibility::new`] holds for them, and the same surface offset. A
    /// segment that only these surfaces can block (inside a closed room of
    /// them) gets the same answer from both, from a smaller tree.
    #[must_use]
    pub fn of_surfaces(scene: &Scene, keep: impl Fn(SurfaceId) -> bool) -> Visibility {
        let kept: Vec<SurfaceId> = scene
            .surfaces_with_ids()
            .map(|(id, _)| id)
            .filter(|&id| keep(id))
            .collect();
        let Box3 { min, max } = scene.bounds();
        Visibility::of_listed_surfaces(scene, &kept, Box3::new(min, max))
    }

    /// [`Visibility::of_surfaces`] over the surfaces `ids`, with the
    /// scene's bounds (`Scene::bounds`) already known: many zones' BVHs
    /// are built without scanning the whole scene for each.
    #[must_use]
    pub(crate) fn of_listed_surfaces(scene: &Scene, ids: &[SurfaceId], bounds: Box3) -> Visibility {
        let Box3 { min, max } = bounds;
        let centre = 0.5 * (min + max);
        let scale = unit_scale(min, max);
        let to_local = |p: DVec3| {
            let q = (p - centre) / scale;
            Vec3A::new(q.x as f32, q.y as f32, q.z as f32)
        };
        let mut triangles = Vec::new();
        let mut surfaces = Vec::new();
        for &id in ids {
            let surface = scene.surface(id);
            let points = surface.occluder_vertices();
            for [a, b, c] in surface.triangles() {
                triangles.push(Triangle {
                    v0: to_local(points[a]),
                    v1: to_local(points[b]),
                    v2: to_local(points[c]),
                });
                surfaces.push(id);
            }
        }
        let bvh = build_cwbvh_from_tris(
            &triangles,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        let order = &bvh.primitive_indices;
        let triangle_surfaces = order.iter().map(|&i| surfaces[i as usize]).collect();
        let triangles = order
            .iter()
            .map(|&i| RtTriangle::from(&triangles[i as usize]))
            .collect();
        Visibility {
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
            bvh,
            triangles,
            triangle_surfaces,
            centre,
            scale,
            surface_offset: surface_offset_for((max - min).length()),
            diagonal: (max - min).length(),
        }
    }

    /// Distance by which segment end points are lifted off their surfaces
    /// along the normal: 2·10⁻⁶ of the scene's diagonal, about 34 times
    /// the f32 rounding of the BVH's coordinates (2⁻²³ of a unit, the power
    /// of two nearest half the diagonal) yet below any feature a mesh
    /// resolves: it stays under a millimetre in a building 190 m across,
    /// so that the rays from a shelved book's side start short of its
    /// neighbour 1 mm away (a larger lift would find that book's back, and
    /// no office would count as a closed room).
    #[must_use]
    pub fn surface_offset(&self) -> f64 {
        self.surface_offset
    }

    /// The diagonal of the whole scene's bounding box (of every surface,
    /// whichever this BVH holds): a reach no ray inside the scene exceeds.
    #[must_use]
    pub fn diagonal(&self) -> f64 {
        self.diagonal
    }

    /// True when no surface but the two given ones blocks the segment from
    /// `from` to `to`, end points excluded.
    #[must_use]
    pub fn is_unblocked(&self, from: DVec3, to: DVec3, end_surfaces: [SurfaceId; 2]) -> bool {
        let mut ray = self.segment_ray(from, to);
        let mut unblocked = true;
        traverse(&self.bvh, &mut ray, |ray, id| {
            // `intersect` answers t within [tmin, tmax] or infinity, never NaN.
            unblocked = end_surfaces.contains(&self.triangle_surfaces[id])
                || self.triangles[id].intersect(ray) >= ray.tmax;
            unblocked
        });
        unblocked
    }

    /// The BVH's ray for the segment from `from` to `to`: in its units,
    /// t from 0 to 1.
    pub(super) fn segment_ray(&self, from: DVec3, to: DVec3) -> Ray {
        let origin = (from - self.centre) / self.scale;
        let direction = (to - from) / self.scale;
        Ray::new(
            Vec3A::new(origin.x as f32, origin.y as f32, origin.z as f32),
            bvh_direction(direction),
            0.0,
            1.0,
        )
    }

    /// The surface a ray from `origin` along the unit `direction` hits
    /// first within `reach`, ignoring surface `ignore`.
    #[must_use]
    pub fn first_hit(
        &self,
        origin: DVec3,
        direction: DVec3,
        reach: f64,
        ignore: SurfaceId,
    ) -> Option<SurfaceId> {
        self.closest_hit(origin, direction, reach, ignore)
            .map(|(surface, _)| surface)
    }

    /// [`Visibility::first_hit`], with the distance along the ray to the hit.
    #[must_use]
    pub fn closest_hit(
        &self,
        origin: DVec3,
        direction: DVec3,
        reach: f64,
        ignore: SurfaceId,
    ) -> Option<(SurfaceId, f64)> {
        let origin = (origin - self.centre) / self.scale;
        let mut ray = Ray::new(
            Vec3A::new(origin.x as f32, origin.y as f32, origin.z as f32),
            bvh_direction(direction),
            0.0,
            (reach * CLOSEST_HIT_STEPS / self.scale) as f32,
        );
        // t in steps: the direction shortened after its inverse is taken,
        // so that obvhs clamps the same components to 1/ε as for the unit
        // direction (both factors exact, powers of two).
        let steps = CLOSEST_HIT_STEPS as f32;
        ray.direction /= steps;
        ray.inv_direction *= steps;
        let mut hit = None;
        traverse(&self.bvh, &mut ray, |ray, id| {
            if self.triangle_surfaces[id] != ignore {
                let t = self.triangles[id].intersect(ray);
                if t < ray.tmax {
                    ray.tmax = t;
                    hit = Some(id);
                }
            }
            true
        });
        hit.map(|id| {
            (
                self.triangle_surfaces[id],
                f64::from(ray.tmax) * self.scale / CLOSEST_HIT_STEPS,
            )
        })
    }

    /// Number of triangles in the BVH (after any splitting by the builder).
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }
}

/// Traverses `bvh` along `ray`, handing `visit` each primitive in a leaf
/// the ray reaches (with the ray, whose `tmax` it may shorten to the
/// nearest hit), until `visit` returns false: obvhs's traversal loop (its
/// exported `traverse!`, which `ray_traverse` and `ray_traverse_miss`
/// wrap), inlined into each query as the shaft query's is. Whether the
/// compiler inlines obvhs's functions into the queries depends on code
/// elsewhere in the crate (out of line, the ray is passed through
/// memory); written here, the loop stays in place.
#[inline(always)]
pub(super) fn traverse(bvh: &CwBvh, ray: &mut Ray, mut visit: impl FnMut(&mut Ray, usize) -> bool) {
    let mut state = bvh.new_traversal(ray.direction);
    let mut node;
    'outer: {
        obvhs::traverse!(bvh, node, state, node.intersect_ray(ray, state.oct_inv4), {
            if !visit(ray, state.primitive_id as usize) {
                break 'outer;
            }
        });
    }
}

/// The next [`Visibility`]'s id.
static NEXT_ID: AtomicU64 = AtomicU64::new(0);

/// A ray direction for the BVH, in f32, with negative zeros made positive:
/// obvhs's traversal picks a box's near and far planes by the direction's
/// sign bits, and a −0 component (the negation of an axis, −X = (−1, −0,
/// −0)) made it miss every box, so such a ray hit nothing at all.
pub(super) fn bvh_direction(direction: DVec3) -> Vec3A {
    // Adding +0 turns −0 into +0 and leaves every other value as it is.
    Vec3A::new(
        direction.x as f32 + 0.0,
        direction.y as f32 + 0.0,
        direction.z as f32 + 0.0,
    )
}

/// Steps of a closest-hit ray's parameter t per BVH unit. obvhs's wide
/// BVH skips a node whose box the ray leaves before t = 10⁻⁴
/// (`cwbvh::node::EPSILON`): with t in BVH units, whatever lies within
/// 10⁻⁴ of a unit of the ray's origin (0.4 mm in one office, 1.6 mm in a
/// floor of 16, 13 mm in a building of 624) would not be there: a closed
/// room's books, 1 mm apart, would let a floor's zone rays through their
/// neighbours' near faces onto their far faces' backs, and each office
/// would count as losing light (`meshing/zones/labels.rs`). With 2¹⁰ steps per unit
/// (a power of two: the change is exact) the nodes skipped lie within
/// 10⁻⁷ of half the scene's diagonal.
pub(super) const CLOSEST_HIT_STEPS: f64 = 1024.0;

/// The world length of one BVH unit for a scene spanning `min`..`max`: the
/// power of two nearest half its diagonal, or 1 for a scene without extent.
/// A power of two makes the change of units exact, so that f32 rounding (and
/// which grazing rays hit) is the same as without it for any scene whose
/// coordinates fit f32 anyway.
fn unit_scale(min: DVec3, max: DVec3) -> f64 {
    let half_diagonal = 0.5 * (max - min).length();
    if half_diagonal.is_normal() {
        2f64.powi(half_diagonal.log2().round() as i32)
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rgb::Rgb;
    use crate::scene::Material;

    /// A surface a millimetre in front of a ray's origin, lifted off its
    /// own by the surface offset, is its closest hit however large the
    /// scene: a row of books' sides, pairs of small squares facing each
    /// other 1 mm apart every 5 cm, in a scene that a square 40 m away
    /// widens to a diagonal of 40 m (a BVH unit of 16 m, whose 10⁻⁴ is
    /// 1.6 mm), or one 200 m away to 200 m, a building of 624 offices
    /// (whose 10⁻⁵ is 2 mm).
    #[test]
    fn a_surface_a_millimetre_away_is_hit_in_a_large_scene() {
        for far in [40.0, 200.0] {
            a_surface_a_millimetre_away_is_hit(far);
        }
    }

    fn a_surface_a_millimetre_away_is_hit(far: f64) {
        let mut scene = Scene::new();
        let grey = scene
            .add_material(Material::diffuse("grey", Rgb::splat(0.5)))
            .unwrap();
        // A 0.2 m square in the plane x, facing +x or −x.
        let square = |x: f64, towards_plus_x: bool| -> Vec<DVec3> {
            let mut corners: Vec<DVec3> = [(-1.0, -1.0), (-1.0, 1.0), (1.0, 1.0), (1.0, -1.0)]
                .iter()
                .map(|&(y, z)| DVec3::new(x, 0.1 * y, 0.1 * z))
                .collect();
            if towards_plus_x {
                corners.reverse();
            }
            corners
        };
        for k in 0..40 {
            let x = 0.05 * f64::from(k);
            scene.add_polygon("left", grey, &square(x, true)).unwrap();
            scene
                .add_polygon("right", grey, &square(x + 0.001, false))
                .unwrap();
        }
        scene.add_polygon("far", grey, &square(far, false)).unwrap();
        let visibility = Visibility::new(&scene);
        for k in 0..40 {
            let (left, right) = (SurfaceId::new(2 * k), SurfaceId::new(2 * k + 1));
            assert!(scene.surface(left).normal().x > 0.9);
            assert!(scene.surface(right).normal().x < -0.9);
            let x = 0.05 * k as f64 + visibility.surface_offset();
            let origin = DVec3::new(x, 0.01, -0.02);
            // Slanted, and along the axis (whose zero components obvhs
            // inverts to 1/ε).
            for direction in [DVec3::new(1.0, 0.3, 0.2).normalize(), DVec3::X] {
                let hit = visibility.closest_hit(origin, direction, 100.0, left);
                let (surface, distance) = hit.expect("the near square");
                let expected = (0.05 * k as f64 + 0.001 - x) / direction.x;
                assert_eq!(surface, right, "pair {k}: {distance} m, not {expected} m");
                // Within the BVH's f32 rounding (a few micrometres at 40 m).
                assert!(
                    (distance - expected).abs() < 1e-5_f64.max(2e-7 * far),
                    "{distance} against {expected}"
                );
            }
        }
    }
}
