//! The vertices' rays ([`VertexRays`]): [`VERTEX_RAYS`] from each
//! vertex, stratified in projected solid angle, each with the patch it
//! hits and where it lands; the elements under the landing points, and
//! each vertex's mean over its rays with its standard error (see
//! `solver/ambient/rays.rs`).

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::lighting::SampleStream;
use crate::lighting::cosine_direction_at;
use crate::mesh::Mesh;
use crate::rgb::Rgb;
use crate::scene::{Scene, SurfaceId, Visibility};
use crate::solver::ambient::landing::{Landing, LandingElement};
use crate::solver::ambient::patch_locator::{PatchLocator, RayStart};
use crate::solver::ambient::rays::{
    AmbientEstimate, MISS, PatchResidual, VERTEX_RAYS, VERTEX_RINGS, rays_counted,
};
use crate::solver::light::cell_coordinates::cell_coordinates;

/// Rays [`VertexRays::landing_elements`] sorts at a time: 4 MiB of keys.
const LOCATE_BLOCK: usize = 1 << 18;

/// Sorted rays one thread locates at a time, keeping its hint.
const LOCATE_CHUNK: usize = 4096;

/// The element under the point at parameters (s, t) of patch `p`'s cell
/// and the point's coordinates in it, `None` where no element lies; the
/// `usize` is a hint kept between reads on one patch (see
/// [`VertexRays::landing_elements`]).
pub(crate) type Locate<'a> = dyn Fn(usize, DVec2, &mut usize) -> Option<LandingElement> + Sync + 'a;

/// A value read where vertex ray k (its index among a [`VertexRays`]'s
/// rays) landed, `None` to read its patch's value instead.
pub(crate) type RayValue<'a> = dyn Fn(usize) -> Option<Rgb> + Sync + 'a;

/// The rays of a list of vertices (a closed room's, or all): the patch
/// each hits and where it lands on it, [`VERTEX_RAYS`] per vertex, vertex
/// after vertex in the list's order. Ray k of the list is ray
/// k mod [`VERTEX_RAYS`] of vertex `vertices[k / VERTEX_RAYS]`.
#[derive(Clone, Debug, Default)]
pub(crate) struct VertexRays {
    vertices: Vec<u32>,
    hits: Vec<u32>,
    /// Where each ray lands on its patch: the patch cell's parameters
    /// there ([`crate::mesh::Cell::point`]) to a [`LANDING_STEPS`]th of
    /// its side ([`Landing`]). The unshot light is read at that point,
    /// from the element under it, not as the patch's mean. Two bytes a
    /// ray: with the hit, these are most of what the term holds per vertex
    /// while a room's image is made (96 rays of 6 bytes), with each ray's
    /// landing element, 8 more
    /// ([`VertexRays::landing_elements`]).
    landings: Vec<Landing>,
}

impl VertexRays {
    /// Casts the rays of `vertices`, [`VERTEX_RAYS`] from where each
    /// gathers, stratified in projected solid angle. A vertex's rays are
    /// the same whatever list it is cast in: each is seeded by its vertex
    /// and its index. A ray from surface `s` traverses `visibility_of(s)`.
    #[must_use]
    pub(crate) fn cast<'v>(
        scene: &Scene,
        mesh: &Mesh,
        vertices: Vec<u32>,
        locator: &PatchLocator,
        visibility_of: &(dyn Fn(SurfaceId) -> &'v Visibility + Sync),
    ) -> VertexRays {
        let count = vertices.len() * VERTEX_RAYS;
        let mut hits = vec![MISS; count];
        let mut landings = vec![Landing::NOWHERE; count];
        hits.par_chunks_mut(VERTEX_RAYS)
            .zip(landings.par_chunks_mut(VERTEX_RAYS))
            .zip(vertices.par_iter())
            .for_each(|((hits, landings), &v)| {
                let vertex = &mesh.vertices[v as usize];
                let normal = scene.surface(vertex.surface).normal();
                let visibility = visibility_of(vertex.surface);
                for (k, (hit, landing)) in hits.iter_mut().zip(landings.iter_mut()).enumerate() {
                    let mut stream = SampleStream::new(u64::from(v), k as u64 | 2 << 40);
                    let origin = vertex.receiver_position();
                    let sectors = VERTEX_RAYS / VERTEX_RINGS;
                    let direction =
                        stratified_direction(normal, k, VERTEX_RINGS, sectors, &mut stream);
                    let start = RayStart {
                        origin,
                        normal,
                        surface: vertex.surface,
                    };
                    let (patch, point) = locator.hit(scene, visibility, start, direction);
                    *hit = patch;
                    *landing = mesh
                        .patches
                        .get(patch as usize)
                        .and_then(|patch| cell_coordinates(&patch.cell, point))
                        .filter(|(s, t)| s.is_finite() && t.is_finite())
                        .map_or(Landing::NOWHERE, |st| Landing::at(st.into()));
                }
            });
        VertexRays {
            vertices,
            hits,
            landings,
        }
    }

    /// The vertices whose rays these are, in the rays' order.
    pub(crate) fn vertices(&self) -> &[u32] {
        &self.vertices
    }

    /// The ambient irradiance G_v of each listed vertex (see the module
    /// docs), in the list's order, for each patch's `residual` A_h
    /// ([`PatchRays::residual`]) and its value ΔB_h + A_h (`patches`).
    /// Ray k reads the unshot radiosity where it lands, `unshot_at(k)` (on
    /// the element under its point, see [`VertexRays::landing_elements`]),
    /// or the patch's mean where that gives none: a floor patch half under
    /// a desk then sends the desk's underside the light of its dark half
    /// and the ceiling that of its lit half, as its shots do.
    /// The residual A_h stays the patch's here (`solver/ambient/sweeps.rs` then
    /// resolves it at the vertices). Each estimate comes with a bound on
    /// its standard error, that of the mean of its rays' values summed
    /// over the channels, from its strata collapsed in pairs of
    /// neighbouring sectors (a miss counted as 0, or its pair left out
    /// where the mean leaves misses out): a surface that fills a ring of
    /// strata evenly adds nothing to it, however bright.
    ///
    /// In a zone that keeps all its light (`lossless` of a surface, see
    /// [`crate::SolverSettings::conserve_closed_zones`]) a ray that ends on
    /// no front (a crack at a contact, a back inside an object) is no light
    /// leaving: a source's mean is then over the rays that land, where at
    /// least half of them do. Counted as dark, such rays (1 % of the
    /// cluttered office's) would darken the term, compounded over the
    /// residual's bounces.
    #[must_use]
    pub(crate) fn irradiance(
        &self,
        mesh: &Mesh,
        patches: &PatchResidual,
        unshot_at: &RayValue<'_>,
        lossless: &(dyn Fn(SurfaceId) -> bool + Sync),
    ) -> Vec<AmbientEstimate> {
        let value_at = |k: usize| {
            let h = self.hits[k] as usize;
            unshot_at(k).map(|w| w + patches.residual[h])
        };
        self.gather(mesh, &value_at, &|h| patches.value[h], lossless)
    }

    /// The element under every ray's landing point, by
    /// `locate(patch, (s, t), hint)`: [`LandingElement::NONE`] for a miss,
    /// or where no element lies. The rays are located in order of patch,
    /// then of s and t, [`LOCATE_BLOCK`] rays at a time: a patch's elements
    /// are then read while they are in cache, and `hint`, the element the
    /// last ray on that patch found, is most often the next ray's (in the
    /// vertices' order, locating would mostly wait on the cache).
    #[must_use]
    pub(crate) fn landing_elements(&self, locate: &Locate<'_>) -> Vec<LandingElement> {
        let mut located = vec![LandingElement::NONE; self.hits.len()];
        for (b, block) in located.chunks_mut(LOCATE_BLOCK).enumerate() {
            let start = b * LOCATE_BLOCK;
            // The block's landed rays, keyed by patch, s step and t step.
            let mut order: Vec<(u64, u32)> = (0..block.len())
                .filter_map(|i| {
                    let (h, landing) = (self.hits[start + i], self.landings[start + i]);
                    let [s, t] = landing.0;
                    let key = (u64::from(h) << 16) | (u64::from(s) << 8) | u64::from(t);
                    (h != MISS && landing != Landing::NOWHERE).then_some((key, i as u32))
                })
                .collect();
            order.par_sort_unstable_by_key(|&(key, _)| key);
            let found: Vec<LandingElement> = order
                .par_chunks(LOCATE_CHUNK)
                .flat_map_iter(|chunk| {
                    let mut last = (usize::MAX, 0);
                    chunk.iter().map(move |&(key, i)| {
                        let h = (key >> 16) as usize;
                        if last.0 != h {
                            last = (h, 0);
                        }
                        self.landings[start + i as usize]
                            .parameters()
                            .and_then(|st| locate(h, st, &mut last.1))
                            .unwrap_or(LandingElement::NONE)
                    })
                })
                .collect();
            for (&(_, i), element) in order.iter().zip(found) {
                block[i as usize] = element;
            }
        }
        located
    }

    /// Each listed vertex's mean over its rays of `value_at(k)` where ray
    /// k lands on patch h, or `fallback(h)` where that gives none, with its
    /// standard error (see [`VertexRays::irradiance`]).
    #[must_use]
    pub(crate) fn gather(
        &self,
        mesh: &Mesh,
        value_at: &RayValue<'_>,
        fallback: &(dyn Fn(usize) -> Rgb + Sync),
        lossless: &(dyn Fn(SurfaceId) -> bool + Sync),
    ) -> Vec<AmbientEstimate> {
        let seen = |(i, &v): (usize, &u32)| {
            let rays = i * VERTEX_RAYS..(i + 1) * VERTEX_RAYS;
            let hits = &self.hits[rays.clone()];
            let mut sum = Rgb::ZERO;
            // Each ray's value summed over the channels, 0 for a miss.
            let mut sums = [0.0; VERTEX_RAYS];
            for (k, &h) in hits.iter().enumerate() {
                if h == MISS {
                    continue;
                }
                let value = value_at(rays.start + k).unwrap_or_else(|| fallback(h as usize));
                sum += value;
                sums[k] = value.element_sum();
            }
            let n = rays_counted(hits, lossless(mesh.vertices[v as usize].surface));
            // Strata collapsed in pairs of neighbouring sectors: each pair
            // estimates twice a stratum's variance, so over the K pairs
            // kept Var(mean) ≈ Σ (x_a − x_b)² / (2 K n) (Cochran 1977,
            // §5A.12; Σ / n² with every pair). Where the mean leaves the
            // misses out, so do the pairs.
            let skip_misses = n < hits.len() as f64;
            let (mut squares, mut pairs) = (0.0, 0.0);
            for (pair, rays) in sums.chunks_exact(2).zip(hits.chunks_exact(2)) {
                if skip_misses && rays.contains(&MISS) {
                    continue;
                }
                squares += (pair[0] - pair[1]).powi(2);
                pairs += 1.0;
            }
            let variance = if pairs > 0.0 {
                squares / (2.0 * pairs * n)
            } else {
                0.0
            };
            AmbientEstimate {
                irradiance: sum / n,
                standard_error: variance.sqrt(),
            }
        };
        self.vertices.par_iter().enumerate().map(seen).collect()
    }

    /// Each listed vertex's harmonic mean distance to where its rays land,
    /// R_v = N / Σ 1/d_k over the N rays that land on a patch (infinite
    /// where none does): the scale over which its ambient irradiance
    /// changes (`solver/ambient/smoothing.rs`).
    #[must_use]
    pub(crate) fn harmonic_distances(&self, mesh: &Mesh) -> Vec<f64> {
        self.vertices
            .par_iter()
            .enumerate()
            .map(|(i, &v)| {
                let rays = i * VERTEX_RAYS..(i + 1) * VERTEX_RAYS;
                let x = mesh.vertices[v as usize].receiver_position();
                let (mut count, mut inverse) = (0.0, 0.0);
                for (&h, landing) in self.hits[rays.clone()].iter().zip(&self.landings[rays]) {
                    let (Some(patch), Some(st)) =
                        (mesh.patches.get(h as usize), landing.parameters())
                    else {
                        continue;
                    };
                    let d = patch.cell.point(st.x, st.y).distance(x);
                    if d > 0.0 && d.is_finite() {
                        count += 1.0;
                        inverse += 1.0 / d;
                    }
                }
                if inverse > 0.0 {
                    count / inverse
                } else {
                    f64::INFINITY
                }
            })
            .collect()
    }
}

/// Cosine-weighted direction k of a rings × sectors stratification of the
/// projected solid angle about the unit `normal`, jittered in its stratum:
/// ring k / sectors (of equal projected area, u₁ = r² uniform), sector
/// k mod sectors. Only a vertex's rays are stratified so: a patch's rays
/// are stratified by where they leave from, and pairing that stratum with
/// a direction stratum would bias the mean.
fn stratified_direction(
    normal: DVec3,
    k: usize,
    rings: usize,
    sectors: usize,
    stream: &mut SampleStream,
) -> DVec3 {
    let (ring, sector) = (k / sectors % rings, k % sectors);
    let u1 = (ring as f64 + stream.next_f64()) / rings as f64;
    let u2 = (sector as f64 + stream.next_f64()) / sectors as f64;
    cosine_direction_at(normal, u1, u2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::ambient::landing::LANDING_STEPS;

    /// A vertex ray reads the unshot light where it landed, and the
    /// patch's mean where that gives none or it landed off the patch; a
    /// miss reads nothing.
    #[test]
    fn a_vertex_ray_reads_where_it_landed() {
        let landings: Vec<Landing> = (0..VERTEX_RAYS)
            .map(|k| match k % 4 {
                0 | 1 => Landing::at(DVec2::new(0.1, 0.9)),
                2 => Landing::at(DVec2::new(0.7, 0.2)),
                _ => Landing::NOWHERE,
            })
            .collect();
        let hits: Vec<u32> = (0..VERTEX_RAYS)
            .map(|k| if k % 8 == 7 { MISS } else { 0 })
            .collect();
        let rays = VertexRays {
            vertices: vec![0],
            hits,
            landings,
        };
        let mut mesh = Mesh::default();
        let surface = crate::scene::SurfaceId::new(0);
        mesh.vertices
            .push(crate::mesh::MeshVertex::new(DVec3::ZERO, surface));
        let unshot = [Rgb::splat(1.0)];
        // 2 left of s = 0.5 and 4 right of it; each point read within a
        // step of where its ray landed.
        // Element 0 lies left of s = 0.5, element 1 right of it.
        let locate = |patch: usize, st: DVec2, _: &mut usize| {
            let (s, t) = (st.x, st.y);
            assert_eq!(patch, 0);
            let step = 1.0 / f64::from(LANDING_STEPS);
            let near = |a: f64, b: f64| (a - b).abs() <= step;
            assert!((near(s, 0.1) && near(t, 0.9)) || (near(s, 0.7) && near(t, 0.2)));
            Some(LandingElement::new(u32::from(s >= 0.5), st))
        };
        let landed = rays.landing_elements(&locate);
        assert_eq!(landed.len(), VERTEX_RAYS);
        let field = |k: usize| {
            let element = landed[k].element();
            element.map(|e| Rgb::splat(if e == 0 { 2.0 } else { 4.0 }))
        };
        let patches = PatchResidual {
            residual: vec![Rgb::ZERO],
            value: unshot.to_vec(),
        };
        let g = rays.irradiance(&mesh, &patches, &field, &|_| false);
        // Of every 8 rays: four at 2, two at 4, one nowhere (the mean, 1)
        // and one miss: (4·2 + 2·4 + 1) / 8.
        assert!((g[0].irradiance.g - 17.0 / 8.0).abs() < 1e-12, "{g:?}");
        // Its standard error's bound, from the ray pairs (6, 6), (12, 3),
        // (6, 6) and (12, 0) of the channels' sums in each of the n / 8
        // groups of 8 rays: √(n / 8 · (9² + 12²)) / n.
        let (n, groups) = (VERTEX_RAYS as f64, (VERTEX_RAYS / 8) as f64);
        let expected = (groups * (81.0 + 144.0)).sqrt() / n;
        assert!((g[0].standard_error - expected).abs() < 1e-12, "{g:?}");
        // In a zone that keeps its light the miss is left out: / 7.
        let g = rays.irradiance(&mesh, &patches, &field, &|_| true);
        assert!((g[0].irradiance.g - 17.0 / 7.0).abs() < 1e-12, "{g:?}");
        // And so is the pair that holds it: 3 pairs kept in each group,
        // Σ = groups · 9², over the 7 rays in each that land.
        let expected = (groups * 81.0 / (2.0 * 3.0 * groups * 7.0 * groups)).sqrt();
        assert!((g[0].standard_error - expected).abs() < 1e-12, "{g:?}");
    }

    /// Rays located in order of patch and place come back to their own
    /// slots, across blocks: each gets what its own patch and point give,
    /// and a miss or a landing off its patch gets none.
    #[test]
    fn rays_located_in_sorted_order_keep_their_own_elements() {
        let count = LOCATE_BLOCK + LOCATE_BLOCK / 2 + 7 * VERTEX_RAYS;
        let mut stream = SampleStream::new(17, 3);
        let (mut hits, mut landings) = (Vec::new(), Vec::new());
        for _ in 0..count {
            let u = stream.next_f64();
            hits.push(if u < 0.05 { MISS } else { (u * 500.0) as u32 });
            landings.push(if stream.next_f64() < 0.02 {
                Landing::NOWHERE
            } else {
                Landing::at(DVec2::new(stream.next_f64(), stream.next_f64()))
            });
        }
        let rays = VertexRays {
            vertices: (0..(count / VERTEX_RAYS) as u32).collect(),
            hits,
            landings,
        };
        // An element per patch and step of s; the point's (s, t) kept.
        let locate = |patch: usize, st: DVec2, _: &mut usize| {
            let step = (st.x * f64::from(LANDING_STEPS)) as u32;
            Some(LandingElement::new(patch as u32 * 256 + step, st))
        };
        let landed = rays.landing_elements(&locate);
        assert_eq!(landed.len(), count);
        for (k, found) in landed.iter().enumerate() {
            let (h, landing) = (rays.hits[k], rays.landings[k]);
            let expected = match landing.parameters() {
                Some(st) if h != MISS => locate(h as usize, st, &mut 0).unwrap(),
                _ => LandingElement::NONE,
            };
            assert_eq!(*found, expected, "ray {k}");
        }
    }
}
