//! What the visibility bench and `examples/bench_report.rs` share: random
//! shadow segments between points on a scene's surfaces, the segments of a
//! mesh's shots as the solver casts them, and a bare obvhs occlusion query
//! over the same triangles, so isorad's `Visibility` layer can be measured
//! against obvhs called directly on the same rays.

use glam::{DVec3, Vec3A};
use isorad::scene::Box3;
use isorad::{Scene, SurfaceId, mesh::Mesh};
use obvhs::{
    BvhBuildParams, cwbvh::CwBvh, cwbvh::builder::build_cwbvh_from_tris, ray::Ray,
    rt_triangle::RtTriangle, triangle::Triangle,
};
use std::time::Duration;

/// SplitMix64: a small, seedable generator, so every run casts the same rays.
pub struct SplitMix64(u64);

impl SplitMix64 {
    pub fn new(seed: u64) -> SplitMix64 {
        SplitMix64(seed)
    }

    /// Uniform in [0, 1).
    pub fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// A shadow segment between two points lifted off their surfaces, with the
/// indices of those surfaces (which isorad's query ignores).
#[derive(Clone, Copy, Debug)]
pub struct Segment {
    pub from: DVec3,
    pub to: DVec3,
    pub end_surfaces: [SurfaceId; 2],
}

/// `count` segments between area-uniform random points on the scene's
/// occluder triangles that face each other (each end in front of the other's surface,
/// the only segments the solver casts), each end lifted off its surface
/// along the normal by 10⁻⁴ of the scene's diagonal (ten times isorad's own
/// offset), so that a bare BVH query that cannot ignore the end surfaces
/// still agrees with isorad's.
pub fn random_segments(scene: &Scene, count: usize, seed: u64) -> Vec<Segment> {
    let lift = 1e-4 * scene.diagonal();
    // Every triangle of every surface with its cumulative area.
    let mut triangles = Vec::new();
    let mut cumulative = Vec::new();
    let mut total = 0.0;
    for (id, surface) in scene.surfaces_with_ids() {
        // The triangles the BVH holds: a face's original, slightly
        // non-planar vertices when the loader projected it.
        let points = surface.occluder_vertices();
        for [a, b, c] in surface.triangles() {
            let (a, b, c) = (points[a], points[b], points[c]);
            let cross = (b - a).cross(c - a);
            total += 0.5 * cross.length();
            triangles.push((id, a, b, c, cross.normalize_or_zero()));
            cumulative.push(total);
        }
    }
    let mut rng = SplitMix64::new(seed);
    let sample = |rng: &mut SplitMix64| {
        let target = rng.next_f64() * total;
        let i = cumulative
            .partition_point(|&c| c < target)
            .min(triangles.len() - 1);
        let (surface, a, b, c, normal) = triangles[i];
        let (mut u, mut v) = (rng.next_f64(), rng.next_f64());
        if u + v > 1.0 {
            (u, v) = (1.0 - u, 1.0 - v);
        }
        (
            surface,
            a + u * (b - a) + v * (c - a) + lift * normal,
            normal,
        )
    };
    let mut segments = Vec::with_capacity(count);
    while segments.len() < count {
        let (s0, from, n0) = sample(&mut rng);
        let (s1, to, n1) = sample(&mut rng);
        // Keep pairs that face each other.
        if n0.dot(to - from) > 0.0 && n1.dot(from - to) > 0.0 {
            segments.push(Segment {
                from,
                to,
                end_surfaces: [s0, s1],
            });
        }
    }
    segments
}

/// The shadow segments of `shots` shots of a mesh's patches, spread evenly
/// over its patch list, as the solver casts a dim reflected shot's: one from
/// every vertex that faces the patch (and is not on the patch's surface), in
/// the mesh's vertex order, to a uniform random point on the patch. Ends are
/// lifted 10⁻⁴ of the scene's diagonal along their normals, as in
/// [`random_segments`].
pub fn shot_segments(scene: &Scene, mesh: &Mesh, shots: usize, seed: u64) -> Vec<Segment> {
    let lift = 1e-4 * scene.diagonal();
    let mut rng = SplitMix64::new(seed);
    let mut segments = Vec::new();
    let stride = (mesh.patches.len() / shots.max(1)).max(1);
    for patch in mesh.patches.iter().step_by(stride).take(shots) {
        let shooter_normal = scene.surface(patch.surface).normal();
        let centre = patch.cell.centre();
        for vertex in &mesh.vertices {
            let normal = scene.surface(vertex.surface).normal();
            let x = vertex.receiver_position();
            if vertex.surface == patch.surface || shooter_normal.dot(x - centre) <= 0.0 {
                continue;
            }
            let y = patch.cell.point(rng.next_f64(), rng.next_f64());
            if normal.dot(y - x) <= 0.0 {
                continue;
            }
            segments.push(Segment {
                from: x + lift * normal,
                to: y + lift * shooter_normal,
                end_surfaces: [vertex.surface, patch.surface],
            });
        }
    }
    segments
}

/// obvhs used directly: the scene's triangles in a CWBVH, built with the same
/// preset and in the same centred f32 coordinates as `isorad::scene::Visibility`.
pub struct RawBvh {
    bvh: CwBvh,
    triangles: Vec<RtTriangle>,
    centre: DVec3,
}

impl RawBvh {
    pub fn new(scene: &Scene) -> RawBvh {
        let Box3 { min, max } = scene.bounds();
        let centre = 0.5 * (min + max);
        let to_local = |p: DVec3| {
            let q = p - centre;
            Vec3A::new(q.x as f32, q.y as f32, q.z as f32)
        };
        let mut triangles = Vec::new();
        for surface in &scene.surfaces {
            let points = surface.occluder_vertices();
            for [a, b, c] in surface.triangles() {
                triangles.push(Triangle {
                    v0: to_local(points[a]),
                    v1: to_local(points[b]),
                    v2: to_local(points[c]),
                });
            }
        }
        let bvh = build_cwbvh_from_tris(
            &triangles,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        let triangles = triangles.iter().map(RtTriangle::from).collect();
        RawBvh {
            bvh,
            triangles,
            centre,
        }
    }

    /// True when nothing blocks the segment; hit ids go through
    /// `primitive_indices` to the caller's triangle order.
    pub fn is_unblocked(&self, segment: &Segment) -> bool {
        let origin = segment.from - self.centre;
        let direction = segment.to - segment.from;
        let ray = Ray::new(
            Vec3A::new(origin.x as f32, origin.y as f32, origin.z as f32),
            Vec3A::new(direction.x as f32, direction.y as f32, direction.z as f32),
            0.0,
            1.0,
        );
        self.bvh.ray_traverse_miss(ray, |ray, id| {
            let triangle = self.bvh.primitive_indices[id] as usize;
            self.triangles[triangle].intersect(ray)
        })
    }
}
