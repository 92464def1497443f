//! The shaft queries of [`Visibility`]: which triangles reach into the
//! shaft between two boxes (Haines & Wallace's shaft culling, the `shaft`
//! module), traversing the BVH with the shaft in place of a ray, and
//! segments answered against such a list of triangles.

use glam::{DVec3, UVec2, Vec3A};
use obvhs::cwbvh::node::{CwBvhNode, extract_byte64};

use super::shaft::{Box3A, Shaft};
use super::visibility::Visibility;
use crate::scene::{Box3, SurfaceId};

/// Shaft boxes are widened by this many BVH units (the scene's
/// half-diagonal, about): for the rounding of their corners to f32, and so
/// that a triangle touching a box reaches into the shaft (a floor
/// vertex at a wall's foot, whose rays start on the wall).
const SHAFT_WIDENING: f32 = 1e-6;

impl Visibility {
    /// True when no triangle but those of the two `end_surfaces` reaches
    /// into the shaft between boxes `a` and `b`: then
    /// every segment from a point of one box to a point of the other is
    /// unblocked, as [`Visibility::is_unblocked`] would find ray by ray
    /// (Haines & Wallace's shaft culling, `shaft.rs`). The BVH is
    /// traversed with the shaft in place of a ray, and stops at the first
    /// triangle that reaches into it or touches a box; the test is
    /// conservative, so a shaft a triangle only grazes from outside may be
    /// called blocked.
    #[must_use]
    pub fn is_shaft_clear(&self, a: Box3, b: Box3, end_surfaces: [SurfaceId; 2]) -> bool {
        self.shaft_occluders(a, b, end_surfaces, 0, &mut Vec::new())
    }

    /// Appends to `occluders` the triangles but those of the two
    /// `end_surfaces` that reach into the shaft between boxes `a` and `b`,
    /// as [`Visibility::is_shaft_clear`] finds them, and returns true, when
    /// there are at most `most` of them. When there are more it stops,
    /// takes back what it appended, and returns false.
    ///
    /// Every segment from a point of one box to a point of the other lies
    /// in the shaft, so only these triangles can block it: tested one by
    /// one ([`Visibility::is_unblocked_among`]), a handful of them answer
    /// a segment for less than a traversal of the BVH costs (the candidate
    /// lists of Haines & Wallace 1991).
    #[must_use]
    pub(crate) fn shaft_occluders(
        &self,
        a: Box3,
        b: Box3,
        end_surfaces: [SurfaceId; 2],
        most: usize,
        occluders: &mut Vec<u32>,
    ) -> bool {
        let shaft = self.shaft(a, b);
        let mut state = self.bvh.new_traversal(Vec3A::ONE);
        let mut node;
        let start = occluders.len();
        let mut complete = true;
        'outer: {
            obvhs::traverse!(
                self.bvh,
                node,
                state,
                shaft_hit_mask(node, &shaft, state.oct_inv4),
                {
                    let id = state.primitive_id as usize;
                    if !end_surfaces.contains(&self.triangle_surfaces[id]) {
                        let t = &self.triangles[id];
                        if shaft.overlaps_triangle([t.v0, t.v0 - t.e1, t.v0 + t.e2]) {
                            if occluders.len() - start == most {
                                complete = false;
                                break 'outer;
                            }
                            occluders.push(id as u32);
                        }
                    }
                }
            );
        }
        if !complete {
            occluders.truncate(start);
        }
        complete
    }

    /// [`Visibility::shaft_occluders`] for a shaft that lies within
    /// another, whose triangles `candidates` are: those of them that reach
    /// into it, tested one by one instead of traversing the BVH. A triangle
    /// that reaches into the inner shaft reaches into the outer one, so the
    /// list holds every one that can block a segment of the inner shaft.
    #[must_use]
    pub(crate) fn shaft_occluders_among(
        &self,
        a: Box3,
        b: Box3,
        candidates: &[u32],
        most: usize,
        occluders: &mut Vec<u32>,
    ) -> bool {
        let shaft = self.shaft(a, b);
        let start = occluders.len();
        for &id in candidates {
            debug_assert!(
                (id as usize) < self.triangles.len(),
                "another BVH's triangle"
            );
            let Some(t) = self.triangles.get(id as usize) else {
                continue;
            };
            if shaft.overlaps_triangle([t.v0, t.v0 - t.e1, t.v0 + t.e2]) {
                if occluders.len() - start == most {
                    occluders.truncate(start);
                    return false;
                }
                occluders.push(id);
            }
        }
        true
    }

    /// The shaft between boxes `a` and `b` in the BVH's units, each widened
    /// by [`SHAFT_WIDENING`].
    fn shaft(&self, a: Box3, b: Box3) -> Shaft {
        let local = |bounds: Box3| {
            let to_local = |p: DVec3| {
                let q = (p - self.centre) / self.scale;
                Vec3A::new(q.x as f32, q.y as f32, q.z as f32)
            };
            let widen = Vec3A::splat(SHAFT_WIDENING);
            Box3A::new(to_local(bounds.min) - widen, to_local(bounds.max) + widen)
        };
        Shaft::new(local(a), local(b))
    }

    /// [`Visibility::is_unblocked`] for a segment that only the
    /// `occluders` can block (found by [`Visibility::shaft_occluders`] for
    /// a shaft that holds it): true when none of them crosses it farther
    /// than the surface offset from `from`.
    ///
    /// The triangles' own tests decide, as for the shadow cache's answers
    /// of [`Visibility::is_unblocked_cached`]. Where they would disagree
    /// with the BVH's traversal, it is almost always over a triangle met
    /// at the very start of the segment (t = 0 to 10⁻⁷): a receiving point
    /// lifted off its surface where another meets it, a desk's leg on the
    /// floor. The traversal's f32 boxes leave most of those out, so hits
    /// within the lift are left out here too: counted in, they darken
    /// pixels of the cluttered office of `bench/generate_building.py`
    /// against both the BVH's answers and the path tracer's reference.
    #[must_use]
    pub(crate) fn is_unblocked_among(&self, from: DVec3, to: DVec3, occluders: &[u32]) -> bool {
        let mut ray = self.segment_ray(from, to);
        ray.tmin = (self.surface_offset / from.distance(to)) as f32;
        occluders.iter().all(|&id| {
            debug_assert!(
                (id as usize) < self.triangles.len(),
                "another BVH's triangle"
            );
            self.triangles
                .get(id as usize)
                .is_none_or(|t| t.intersect(&ray) >= ray.tmax)
        })
    }
}

/// Which children of a wide BVH node reach into `shaft`, as the hit mask
/// obvhs's traversal takes (the layout of `CwBvhNode::intersect_aabb`).
fn shaft_hit_mask(node: &CwBvhNode, shaft: &Shaft, oct_inv4: u32) -> u32 {
    let (child_bits, bit_index) = node.get_child_and_index_bits(oct_inv4);
    let mut hits = 0;
    for child in 0..8 {
        let aabb = node.child_aabb(child);
        if shaft.overlaps_box(aabb.min, aabb.max) {
            hits |= extract_byte64(child_bits, child) << extract_byte64(bit_index, child);
        }
    }
    hits
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::queries::tests::plate_over_floor;

    /// A shaft through the plate is blocked, one beside it clear, and the
    /// plate does not block a shaft that ends on it.
    #[test]
    fn a_shaft_is_clear_only_where_nothing_reaches_into_it() {
        let scene = plate_over_floor();
        let visibility = Visibility::new(&scene);
        let (floor, plate) = (SurfaceId::new(0), SurfaceId::new(1));
        let ends = [floor, SurfaceId::NONE];
        assert!(!visibility.is_shaft_clear(flat(0.0, 0.01, 0.2), flat(0.0, 2.0, 0.2), ends));
        assert!(visibility.is_shaft_clear(flat(2.5, 0.01, 0.2), flat(2.5, 2.0, 0.2), ends));
        // From the floor under the plate to the plate's underside.
        let to_plate = [floor, plate];
        assert!(visibility.is_shaft_clear(flat(0.0, 0.01, 0.5), flat(0.0, 0.99, 0.5), to_plate));
        // Leaning into the plate: blocked.
        assert!(!visibility.is_shaft_clear(flat(0.0, 0.01, 0.2), flat(1.5, 2.0, 0.2), ends));
        // Passing beside it, through the corner of the union box over it.
        assert!(visibility.is_shaft_clear(flat(0.0, 0.01, 0.2), flat(2.6, 2.0, 0.2), ends));
    }

    /// A flat box at height y, centred on (x, y, 0), `half` wide each way
    /// along x and z: a patch's receiving points or a lamp.
    fn flat(x: f64, y: f64, half: f64) -> Box3 {
        Box3::new(
            DVec3::new(x - half, y, -half),
            DVec3::new(x + half, y, half),
        )
    }

    /// Random boxes over and under the plate of [`plate_over_floor`], and
    /// random points in them, from a small deterministic generator.
    struct RandomBoxes(u64);

    impl RandomBoxes {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }

        fn next_box(&mut self) -> Box3 {
            let centre = DVec3::new(
                4.0 * self.next() - 2.0,
                0.05 + 2.0 * self.next(),
                4.0 * self.next() - 2.0,
            );
            let half = DVec3::new(0.4 * self.next(), 0.4 * self.next(), 0.4 * self.next());
            Box3::new(centre - half, centre + half)
        }

        fn point_in(&mut self, bounds: Box3) -> DVec3 {
            let Box3 { min, max } = bounds;
            min + (max - min) * DVec3::new(self.next(), self.next(), self.next())
        }
    }

    /// A shaft lists the triangles that reach into it: the plate's two
    /// between the floor under it and a box above it, nothing for a clear
    /// shaft; with room for fewer than reach in, it lists none and leaves
    /// what the list held before.
    #[test]
    fn a_shaft_lists_the_triangles_that_reach_into_it() {
        let scene = plate_over_floor();
        let visibility = Visibility::new(&scene);
        let (floor, plate) = (SurfaceId::new(0), SurfaceId::new(1));
        let ends = [floor, SurfaceId::NONE];
        let (under, over) = (flat(0.0, 0.01, 0.2), flat(0.0, 2.0, 0.2));
        let mut listed = vec![7];
        assert!(visibility.shaft_occluders(under, over, ends, 8, &mut listed));
        assert_eq!(listed.len(), 3, "{listed:?}");
        assert!(
            listed[1..]
                .iter()
                .all(|&t| visibility.triangle_surfaces[t as usize] == plate)
        );
        let mut listed = vec![7];
        assert!(!visibility.shaft_occluders(under, over, ends, 1, &mut listed));
        assert_eq!(listed, [7]);
        let beside = (flat(2.5, 0.01, 0.2), flat(2.5, 2.0, 0.2));
        assert!(visibility.shaft_occluders(beside.0, beside.1, ends, 8, &mut listed));
        assert_eq!(listed, [7]);
    }

    /// Every segment between points of two random boxes whose shaft holds
    /// a few triangles is answered by those triangles as the BVH answers
    /// it, blocked or not.
    #[test]
    fn a_shaft_s_triangles_answer_its_segments_as_the_bvh_does() {
        let scene = plate_over_floor();
        let visibility = Visibility::new(&scene);
        let mut random = RandomBoxes(5);
        let ends = [SurfaceId::NONE; 2];
        let (mut blocked, mut unblocked) = (0, 0);
        let mut listed = Vec::new();
        for _ in 0..400 {
            let (a, b) = (random.next_box(), random.next_box());
            listed.clear();
            if !visibility.shaft_occluders(a, b, ends, 8, &mut listed) || listed.is_empty() {
                continue;
            }
            for _ in 0..64 {
                let (p, q) = (random.point_in(a), random.point_in(b));
                let seen = visibility.is_unblocked_among(p, q, &listed);
                assert_eq!(
                    seen,
                    visibility.is_unblocked(p, q, ends),
                    "{a:?} {b:?}: {p} to {q}"
                );
                if seen {
                    unblocked += 1;
                } else {
                    blocked += 1;
                }
            }
        }
        assert!(
            blocked > 500 && unblocked > 500,
            "{blocked} blocked, {unblocked} unblocked"
        );
    }

    /// A shaft within another picks its triangles from the outer one's
    /// list, and those answer its segments as the BVH does: from the floor
    /// under the plate to a box above it, an inner box under the plate's
    /// middle lists the plate; one beside the plate, under the outer
    /// shaft's edge, lists nothing and is clear.
    #[test]
    fn a_shaft_within_another_picks_its_triangles_from_the_outer_list() {
        let scene = plate_over_floor();
        let visibility = Visibility::new(&scene);
        let ends = [SurfaceId::new(0), SurfaceId::NONE];
        let (outer, top) = (flat(1.0, 0.01, 1.2), flat(1.0, 2.0, 0.1));
        let mut candidates = Vec::new();
        assert!(visibility.shaft_occluders(outer, top, ends, 8, &mut candidates));
        assert_eq!(candidates.len(), 2, "{candidates:?}");
        let mut listed = Vec::new();
        let under = flat(0.0, 0.01, 0.1);
        assert!(visibility.shaft_occluders_among(under, top, &candidates, 8, &mut listed));
        assert_eq!(listed.len(), 2);
        for k in 0..=10 {
            let p = DVec3::new(-0.1 + 0.02 * f64::from(k), 0.01, 0.05);
            let q = DVec3::new(1.0, 2.0, 0.1 - 0.02 * f64::from(k));
            assert_eq!(
                visibility.is_unblocked_among(p, q, &listed),
                visibility.is_unblocked(p, q, ends),
                "{p} to {q}"
            );
        }
        listed.clear();
        let beside = flat(2.1, 0.01, 0.1);
        assert!(visibility.shaft_occluders_among(beside, top, &candidates, 8, &mut listed));
        assert!(listed.is_empty());
        assert!(visibility.is_shaft_clear(beside, top, ends));
        assert!(!visibility.shaft_occluders_among(under, top, &candidates, 1, &mut listed));
        assert!(listed.is_empty());
    }

    /// Wherever a shaft between two random boxes is clear, every segment
    /// between points of the boxes is unblocked.
    #[test]
    fn every_segment_of_a_clear_shaft_is_unblocked() {
        let scene = plate_over_floor();
        let visibility = Visibility::new(&scene);
        let mut random = RandomBoxes(3);
        let ends = [SurfaceId::NONE; 2];
        let (mut clear, mut blocked) = (0, 0);
        for _ in 0..400 {
            let (a, b) = (random.next_box(), random.next_box());
            if !visibility.is_shaft_clear(a, b, ends) {
                blocked += 1;
                continue;
            }
            clear += 1;
            for _ in 0..64 {
                let (p, q) = (random.point_in(a), random.point_in(b));
                assert!(
                    visibility.is_unblocked(p, q, ends),
                    "{a:?} {b:?}: {p} to {q}"
                );
            }
        }
        assert!(
            clear > 50 && blocked > 50,
            "{clear} clear, {blocked} blocked"
        );
    }
}
