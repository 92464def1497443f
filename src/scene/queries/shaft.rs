//! Shafts: the region between two boxes that every segment joining them
//! lies in, for testing a whole bundle of shadow rays at once.
//!
//! A shooter's shadow rays to a receiving patch all join a point of one
//! box (the shooter's cell) to a point of another (the patch's receiving
//! points). They lie in the convex hull of the two boxes, and if no
//! triangle reaches into that hull, every one of them is unblocked and
//! none need be cast. Haines & Wallace bound the hull by the boxes' union
//! box cut by at most twelve planes: for each pair of axes (i, j) and each
//! of the union's four edges parallel to the third axis, when one box
//! reaches farthest along i on that edge's side and the other along j,
//! the plane through the two boxes' corresponding edges cuts the union's
//! empty corner off. The shaft holds both boxes, so it holds their hull.
//!
//! Tests here are conservative the safe way: a box or triangle counts as
//! outside only when one plane (or one face of the union box) has all of
//! it beyond or on it. Callers widen the boxes a little, so that what
//! touches them counts as inside: a ray from a vertex on a floor at a
//! wall's foot starts on the wall.
//!
//! # References
//! E. A. Haines, J. R. Wallace, "Shaft Culling for Efficient Ray-Traced
//! Radiosity", Eurographics Workshop on Rendering, 1991.

use glam::Vec3A;

/// The most planes a shaft between two boxes has: three pairs of axes
/// times four edges.
const MAX_PLANES: usize = 12;

/// An axis-aligned box in the BVH's f32 units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Box3A {
    /// The least corner.
    pub(crate) min: Vec3A,
    /// The greatest corner.
    pub(crate) max: Vec3A,
}

impl Box3A {
    /// The box from `min` to `max`.
    pub(crate) const fn new(min: Vec3A, max: Vec3A) -> Box3A {
        Box3A { min, max }
    }

    /// The corner on `side` (0: the minimum, 1: the maximum) along `axis`.
    fn extreme(&self, side: usize, axis: usize) -> f32 {
        if side == 0 {
            self.min[axis]
        } else {
            self.max[axis]
        }
    }
}

/// The convex region between two axis-aligned boxes (see the module docs).
#[derive(Clone, Debug)]
pub(crate) struct Shaft {
    /// The union box.
    min: Vec3A,
    max: Vec3A,
    /// Unit outward normals n and offsets c: inside where n · p < c.
    planes: [(Vec3A, f32); MAX_PLANES],
    count: usize,
}

impl Shaft {
    /// The shaft between boxes `a` and `b`.
    pub(crate) fn new(a: Box3A, b: Box3A) -> Shaft {
        // Which box reaches farther on a side of an axis: 1 for a, -1 for
        // b, 0 when level. Side 0 is the minimum, 1 the maximum.
        let outer = |side: usize, axis: usize| {
            let (ea, eb) = (a.extreme(side, axis), b.extreme(side, axis));
            let (ea, eb) = if side == 0 { (-ea, -eb) } else { (ea, eb) };
            if ea > eb {
                1
            } else if eb > ea {
                -1
            } else {
                0
            }
        };
        let mut planes = [(Vec3A::ZERO, 0.0); MAX_PLANES];
        let mut count = 0;
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            for (si, sj) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                let (oi, oj) = (outer(si, i), outer(sj, j));
                if oi == 0 || oj == 0 || oi == oj {
                    continue;
                }
                // The two boxes' edges on this side, in the (i, j) plane.
                let (pa, pb) = (
                    (a.extreme(si, i), a.extreme(sj, j)),
                    (b.extreme(si, i), b.extreme(sj, j)),
                );
                let mut n = Vec3A::ZERO;
                n[i] = pb.1 - pa.1;
                n[j] = pa.0 - pb.0;
                let sign = |side: usize| if side == 0 { -1.0 } else { 1.0 };
                if n[i] * sign(si) + n[j] * sign(sj) < 0.0 {
                    n = -n;
                }
                let length = n.length();
                if !(length > 0.0 && length.is_finite()) {
                    continue;
                }
                n /= length;
                planes[count] = (n, n[i] * pa.0 + n[j] * pa.1);
                count += 1;
            }
        }
        Shaft {
            min: a.min.min(b.min),
            max: a.max.max(b.max),
            planes,
            count,
        }
    }

    /// Whether the box from `min` to `max` may reach into the shaft.
    pub(crate) fn overlaps_box(&self, min: Vec3A, max: Vec3A) -> bool {
        if min.cmpge(self.max).any() || max.cmple(self.min).any() {
            return false;
        }
        self.planes[..self.count].iter().all(|&(n, c)| {
            // The box's corner deepest inside the plane.
            let deepest = Vec3A::select(n.cmpgt(Vec3A::ZERO), min, max);
            n.dot(deepest) < c
        })
    }

    /// Whether the triangle with corners `v` may reach into the shaft.
    pub(crate) fn overlaps_triangle(&self, v: [Vec3A; 3]) -> bool {
        let min = v[0].min(v[1]).min(v[2]);
        let max = v[0].max(v[1]).max(v[2]);
        if min.cmpge(self.max).any() || max.cmple(self.min).any() {
            return false;
        }
        self.planes[..self.count]
            .iter()
            .all(|&(n, c)| v.iter().any(|&p| n.dot(p) < c))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::vec3a;

    /// A small deterministic generator for test points.
    fn next(state: &mut u64) -> f32 {
        *state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (*state >> 40) as f32 / (1u64 << 24) as f32
    }

    fn point_in(state: &mut u64, bounds: Box3A) -> Vec3A {
        let t = vec3a(next(state), next(state), next(state));
        bounds.min + (bounds.max - bounds.min) * t
    }

    /// Every segment between the two boxes stays inside: no point on it
    /// is beyond a plane, and a tiny box around any such point overlaps.
    #[test]
    fn holds_every_segment_between_its_boxes() {
        let mut state = 7;
        for _ in 0..200 {
            let mut random_box = || {
                let (p, q) = (
                    point_in(
                        &mut state,
                        Box3A::new(Vec3A::splat(-2.0), Vec3A::splat(2.0)),
                    ),
                    point_in(
                        &mut state,
                        Box3A::new(Vec3A::splat(-2.0), Vec3A::splat(2.0)),
                    ),
                );
                Box3A::new(p.min(q), p.max(q))
            };
            let (a, b) = (random_box(), random_box());
            let shaft = Shaft::new(a, b);
            for _ in 0..50 {
                let (p, q) = (point_in(&mut state, a), point_in(&mut state, b));
                let x = p.lerp(q, next(&mut state));
                let e = Vec3A::splat(1e-4);
                assert!(shaft.overlaps_box(x - e, x + e), "{a:?} {b:?} {x:?}");
            }
        }
    }

    /// Between a floor patch and a ceiling patch offset sideways, the
    /// union box's empty corners are cut off: a box there is outside the
    /// shaft, one on the line between the patches' centres inside.
    #[test]
    fn cuts_the_union_boxs_empty_corners() {
        let floor = Box3A::new(vec3a(0.0, 0.0, 0.0), vec3a(1.0, 0.0, 1.0));
        let ceiling = Box3A::new(vec3a(3.0, 2.0, 0.0), vec3a(4.0, 2.0, 1.0));
        let shaft = Shaft::new(floor, ceiling);
        // Above the floor patch, near the ceiling: in the union box only.
        let corner = (vec3a(0.2, 1.6, 0.2), vec3a(0.4, 1.8, 0.4));
        assert!(!shaft.overlaps_box(corner.0, corner.1));
        // Half way along the shaft.
        let middle = (vec3a(1.9, 0.9, 0.4), vec3a(2.1, 1.1, 0.6));
        assert!(shaft.overlaps_box(middle.0, middle.1));
        // A triangle lying across the middle, and one in the empty corner.
        let across = [
            vec3a(1.0, 1.0, -1.0),
            vec3a(3.0, 1.0, -1.0),
            vec3a(2.0, 1.0, 3.0),
        ];
        assert!(shaft.overlaps_triangle(across));
        let cornered = [
            vec3a(0.1, 1.5, 0.1),
            vec3a(0.5, 1.9, 0.1),
            vec3a(0.3, 1.7, 0.9),
        ];
        assert!(!shaft.overlaps_triangle(cornered));
    }

    /// A wall that meets the boxes at their edges, in the plane of the
    /// shaft's side, is outside; one reaching in is inside.
    #[test]
    fn touching_is_outside() {
        let floor = Box3A::new(vec3a(0.0, 0.0, 0.0), vec3a(1.0, 0.0, 1.0));
        let ceiling = Box3A::new(vec3a(0.0, 2.0, 0.0), vec3a(1.0, 2.0, 1.0));
        let shaft = Shaft::new(floor, ceiling);
        let wall = (vec3a(-1.0, 0.0, 0.0), vec3a(0.0, 2.0, 1.0));
        assert!(!shaft.overlaps_box(wall.0, wall.1));
        let inside = (vec3a(-1.0, 0.0, 0.0), vec3a(1e-3, 2.0, 1.0));
        assert!(shaft.overlaps_box(inside.0, inside.1));
    }
}
