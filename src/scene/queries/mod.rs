//! Ray queries on a scene: shadow rays and closest hits over a BVH
//! ([`Visibility`]), the shadow cache, the shafts between two boxes and the
//! triangles that reach into them, and per-surface bounding boxes.

mod shadow_cache;
mod shaft;
mod shaft_queries;
mod surface_boxes;
mod visibility;

pub use shadow_cache::ShadowCache;
pub use surface_boxes::SurfaceBoxes;
pub use visibility::Visibility;
pub(crate) use visibility::surface_offset_for;

/// Tests of the queries against obvhs's own traversal, and the scenes the
/// queries' tests share.
#[cfg(test)]
mod tests {
    use glam::{DVec3, Vec3A};
    use obvhs::ray::Ray;

    use super::visibility::{CLOSEST_HIT_STEPS, bvh_direction};
    use super::{ShadowCache, Visibility};
    use crate::rgb::Rgb;
    use crate::scene::{Material, Scene, SurfaceId};

    /// A floor at y = 0 under a plate at y = 1 (x, z in [−1, 1]).
    pub(super) fn plate_over_floor() -> Scene {
        let mut scene = Scene::new();
        let grey = scene
            .add_material(Material::diffuse("grey", Rgb::splat(0.5)))
            .unwrap();
        let square = |y: f64, size: f64| -> Vec<DVec3> {
            [(-1.0, -1.0), (-1.0, 1.0), (1.0, 1.0), (1.0, -1.0)]
                .iter()
                .map(|&(x, z)| DVec3::new(x * size, y, z * size))
                .collect()
        };
        scene.add_polygon("floor", grey, &square(0.0, 3.0)).unwrap();
        scene.add_polygon("plate", grey, &square(1.0, 1.0)).unwrap();
        scene
    }

    /// The queries through the inlined traversal answer as obvhs's own
    /// `ray_traverse_miss` and `ray_traverse` do, with the queries' own
    /// tests as closures: over 5,000 random segments and rays among
    /// 60 random small squares in the plate-over-floor scene.
    #[test]
    fn the_inlined_traversal_answers_as_obvhs_functions() {
        let mut scene = plate_over_floor();
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut random = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            ((state >> 11) as f64) / ((1u64 << 53) as f64)
        };
        let point = |random: &mut dyn FnMut() -> f64| {
            DVec3::new(4.0 * random() - 2.0, 2.0 * random(), 4.0 * random() - 2.0)
        };
        for k in 0..60 {
            let c = point(&mut random);
            let (u, v) = (0.2 * random(), 0.2 * random());
            let corners = [
                c,
                c + DVec3::new(u, 0.0, 0.0),
                c + DVec3::new(u, v, 0.1),
                c + DVec3::new(0.0, v, 0.1),
            ];
            scene
                .add_polygon(&format!("square {k}"), 0, &corners)
                .unwrap();
        }
        let visibility = Visibility::new(&scene);
        let ids: Vec<SurfaceId> = scene.surfaces_with_ids().map(|(id, _)| id).collect();
        let (mut blocked, mut hits) = (0, 0);
        for k in 0..5000 {
            let (from, to) = (point(&mut random), point(&mut random));
            let ends = [ids[k % ids.len()], ids[(7 * k + 3) % ids.len()]];
            let ray = visibility.segment_ray(from, to);
            let expected = visibility.bvh.ray_traverse_miss(ray, |ray, id| {
                if ends.contains(&visibility.triangle_surfaces[id]) {
                    f32::INFINITY
                } else {
                    visibility.triangles[id].intersect(ray)
                }
            });
            assert_eq!(
                visibility.is_unblocked(from, to, ends),
                expected,
                "segment {k}"
            );
            let mut cache = ShadowCache::default();
            assert_eq!(
                visibility.is_unblocked_cached(from, to, ends, &mut cache),
                expected
            );
            blocked += usize::from(!expected);
            let direction = (to - from).normalize();
            let found = visibility.closest_hit(from, direction, 10.0, ends[0]);
            let origin = (from - visibility.centre) / visibility.scale;
            let steps = CLOSEST_HIT_STEPS as f32;
            let mut ray = Ray::new(
                Vec3A::new(origin.x as f32, origin.y as f32, origin.z as f32),
                bvh_direction(direction),
                0.0,
                (10.0 * CLOSEST_HIT_STEPS / visibility.scale) as f32,
            );
            ray.direction /= steps;
            ray.inv_direction *= steps;
            let mut hit = obvhs::ray::RayHit::none();
            let any = visibility.bvh.ray_traverse(ray, &mut hit, |ray, id| {
                if visibility.triangle_surfaces[id] == ends[0] {
                    f32::INFINITY
                } else {
                    visibility.triangles[id].intersect(ray)
                }
            });
            let expected = any.then(|| {
                let surface = visibility.triangle_surfaces[hit.primitive_id as usize];
                (
                    surface,
                    f64::from(hit.t) * visibility.scale / CLOSEST_HIT_STEPS,
                )
            });
            assert_eq!(found, expected, "ray {k}");
            hits += usize::from(found.is_some());
        }
        // Both answers occur often.
        assert!(blocked > 500 && blocked < 4500, "{blocked} blocked");
        assert!(hits > 500, "{hits} hits");
    }
}
