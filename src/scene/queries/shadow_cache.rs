//! The shadow cache: the triangles that blocked the last shadow rays, tried
//! before a traversal of the BVH (Haines & Greenberg 1986).

use glam::DVec3;

use super::visibility::{Visibility, traverse};
use crate::scene::SurfaceId;

impl Visibility {
    /// [`Visibility::is_unblocked`], trying first the triangles that
    /// blocked the last shadow rays through `cache`: the shadow cache of
    /// ray tracers (Haines & Greenberg 1986). Neighbouring receivers'
    /// rays to one shooter are nearly parallel, so what blocked one
    /// mostly blocks the next: in the cluttered office of
    /// `bench/generate_building.py` half the solver's rays are blocked,
    /// and the two cached triangles answer three in four of those with one
    /// triangle test each instead of a traversal.
    ///
    /// A cached triangle that the segment crosses blocks it, whatever the
    /// BVH says, so the answer is [`Visibility::is_unblocked`]'s except
    /// for a segment that grazes a triangle which the BVH's f32 boxes
    /// leave out (about one in eight thousand of the cached answers in
    /// that office, on seams): there the triangle's own test decides. A
    /// cache used for a fixed sequence of rays gives a fixed answer, so
    /// callers that want reproducible results keep one per fixed run of
    /// rays (the solver: one per run of 256 of a shot's receivers), not
    /// one per thread.
    ///
    /// # References
    /// E. A. Haines, D. P. Greenberg, "The Light Buffer: A Shadow-Testing
    /// Accelerator", IEEE Computer Graphics and Applications 6(9), 1986.
    #[must_use]
    pub fn is_unblocked_cached(
        &self,
        from: DVec3,
        to: DVec3,
        end_surfaces: [SurfaceId; 2],
        cache: &mut ShadowCache,
    ) -> bool {
        let ray = self.segment_ray(from, to);
        let blocks = |id: u32| {
            let id = id as usize;
            id < self.triangles.len()
                && !end_surfaces.contains(&self.triangle_surfaces[id])
                && self.triangles[id].intersect(&ray) < ray.tmax
        };
        if cache.owner == self.id {
            let [first, second] = cache.recent;
            if blocks(first) {
                return false;
            }
            if blocks(second) {
                cache.recent = [second, first];
                return false;
            }
        }
        let mut blocker = ShadowCache::NONE;
        let mut ray = ray;
        traverse(&self.bvh, &mut ray, |ray, id| {
            if !end_surfaces.contains(&self.triangle_surfaces[id])
                && self.triangles[id].intersect(ray) < ray.tmax
            {
                blocker = id as u32;
            }
            blocker == ShadowCache::NONE
        });
        let unblocked = blocker == ShadowCache::NONE;
        if !unblocked {
            let kept = if cache.owner == self.id {
                cache.recent[0]
            } else {
                ShadowCache::NONE
            };
            *cache = ShadowCache {
                owner: self.id,
                recent: [blocker, kept],
            };
        }
        unblocked
    }
}

/// The triangles that blocked the last shadow rays of one run of queries
/// ([`Visibility::is_unblocked_cached`]), most recent first. Start each
/// run with [`ShadowCache::default`].
#[derive(Clone, Copy, Debug)]
pub struct ShadowCache {
    /// The [`Visibility`] whose triangles `recent` indexes.
    owner: u64,
    recent: [u32; 2],
}

impl ShadowCache {
    /// No triangle.
    const NONE: u32 = u32::MAX;

    /// Whether no blocked ray has filled it yet.
    #[cfg(test)]
    pub(crate) fn is_fresh(&self) -> bool {
        self.owner == NO_OWNER
    }

    /// Fills it as a blocked ray would, for tests of its users.
    #[cfg(test)]
    pub(crate) fn fill_for_test(&mut self) {
        self.owner = 0;
        self.recent = [0, 0];
    }
}

impl Default for ShadowCache {
    fn default() -> ShadowCache {
        ShadowCache {
            owner: NO_OWNER,
            recent: [ShadowCache::NONE; 2],
        }
    }
}

/// No [`Visibility`]'s id: an empty cache.
const NO_OWNER: u64 = u64::MAX;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::queries::tests::plate_over_floor;

    /// A blocked ray leaves its blocker in the cache, where the next ray
    /// through the plate finds it; a ray beside the plate traverses and
    /// keeps it; another BVH's query replaces the owner.
    #[test]
    fn the_cache_keeps_the_triangle_that_blocked_the_last_ray() {
        let scene = plate_over_floor();
        let visibility = Visibility::new(&scene);
        let plate = SurfaceId::new(1);
        let ends = [SurfaceId::NONE; 2];
        let mut cache = ShadowCache::default();
        let up = |x: f64| (DVec3::new(x, 0.01, 0.0), DVec3::new(x, 2.0, 0.0));
        let (from, to) = up(0.1);
        assert!(!visibility.is_unblocked_cached(from, to, ends, &mut cache));
        assert_eq!(cache.owner, visibility.id);
        let first = cache.recent[0];
        assert_eq!(visibility.triangle_surfaces[first as usize], plate);
        // Nearly parallel, through the same triangle or its neighbour.
        let (from, to) = up(0.12);
        assert!(!visibility.is_unblocked_cached(from, to, ends, &mut cache));
        assert!(cache.recent.contains(&first));
        // Beside the plate: unblocked, and the cache is kept.
        let (from, to) = up(2.0);
        assert!(visibility.is_unblocked_cached(from, to, ends, &mut cache));
        assert!(cache.recent.contains(&first));
        // Another BVH's blocked ray makes the cache its own.
        let other = Visibility::new(&scene);
        let (from, to) = up(0.1);
        assert!(!other.is_unblocked_cached(from, to, ends, &mut cache));
        assert_eq!(cache.owner, other.id);
        assert_eq!(cache.recent[1], ShadowCache::NONE);
    }
}
