//! The patches' rays ([`PatchRays`]): [`PATCH_RAYS`] from each patch,
//! cast once and kept, and the residual A_p found along them by Jacobi
//! iteration (see `solver/ambient/rays.rs`); and one patch ray
//! ([`patch_ray`]), which the patch shots cast too.

use glam::DVec3;
use rayon::prelude::*;

use crate::lighting::SampleStream;
use crate::lighting::cosine_direction;
use crate::mesh::Mesh;
use crate::rgb::Rgb;
use crate::scene::{Scene, SurfaceId, Visibility};
use crate::solver::ambient::patch_locator::{PatchLocator, RayStart};
use crate::solver::ambient::rays::{MISS, PATCH_RAYS, rays_counted};

/// The Jacobi iteration stops when no patch's value changes by more than
/// this fraction of the largest unshot radiosity, or after
/// [`MAX_ITERATIONS`].
const CONVERGENCE: f64 = 1e-6;
const MAX_ITERATIONS: usize = 1000;

/// The patch each of the patches' cached rays hits, [`PATCH_RAYS`] per
/// patch: cast once, read by every image. Only the patches a solution
/// needs are cast (the rooms its readings lie in, see
/// [`crate::Ambient::For`]), the others when one
/// needs them; a patch's rays are the same whichever solution casts
/// them.
#[derive(Clone, Debug, Default)]
pub(crate) struct PatchRays {
    /// The cast patches' rays, [`PATCH_RAYS`] at a time in the order cast.
    hits: Vec<u32>,
    /// Where each patch's rays start in `hits`, over [`PATCH_RAYS`], or
    /// [`NOT_CAST`]: 4 bytes a patch, and 256 more for each cast one.
    slot: Vec<u32>,
}

/// A patch whose rays are not cast.
const NOT_CAST: u32 = u32::MAX;

impl PatchRays {
    /// Those of `patches` (all of `mesh`'s, by `None`) whose rays are not
    /// cast yet: every one when `mesh`'s patches are not those the rays
    /// were cast for.
    pub(crate) fn uncast(&self, mesh: &Mesh, patches: Option<&[u32]>) -> Vec<u32> {
        let fresh = self.slot.len() != mesh.patches.len();
        let cast = |p: u32| !fresh && self.slot.get(p as usize).is_none_or(|&k| k != NOT_CAST);
        match patches {
            Some(patches) => patches.iter().copied().filter(|&p| !cast(p)).collect(),
            None => (0..mesh.patches.len() as u32)
                .filter(|&p| !cast(p))
                .collect(),
        }
    }

    /// Patch p's rays, if cast.
    fn of(&self, p: usize) -> Option<&[u32]> {
        let k = *self.slot.get(p).filter(|&&k| k != NOT_CAST)? as usize;
        self.hits.get(k * PATCH_RAYS..(k + 1) * PATCH_RAYS)
    }

    /// Casts the rays of `patches` (ascending): from stratified points on
    /// each one's elements, cosine-weighted. A ray from surface `s`
    /// traverses `visibility_of(s)`: the BVH of its closed zone's bounds,
    /// or the scene's.
    pub(crate) fn cast<'v>(
        &mut self,
        scene: &Scene,
        mesh: &Mesh,
        patches: &[u32],
        locator: &PatchLocator,
        visibility_of: &(dyn Fn(SurfaceId) -> &'v Visibility + Sync),
    ) {
        if self.slot.len() != mesh.patches.len() {
            self.hits = Vec::new();
            self.slot = vec![NOT_CAST; mesh.patches.len()];
        }
        let hits: Vec<u32> = patches
            .par_iter()
            .flat_map_iter(|&p| (0..PATCH_RAYS).map(move |k| (p as usize, k)))
            .map(|(p, k)| patch_ray(scene, mesh, p, k, PATCH_RAYS, locator, visibility_of))
            .collect();
        let first = self.hits.len() / PATCH_RAYS;
        for (k, &p) in patches.iter().enumerate() {
            self.slot[p as usize] = (first + k) as u32;
        }
        self.hits.extend(hits);
    }

    /// The fixed point A_p = ρ_p ⟨ΔB_h + A_h⟩_p, by Jacobi iteration, for
    /// unshot radiosity `unshot` and reflectance `reflectance` per patch;
    /// the mean of a `lossless` patch's rays as
    /// [`VertexRays::irradiance`] takes it. Found on the patches whose rays
    /// are cast and `within` (ascending; all, by `None`); zero elsewhere.
    #[must_use]
    pub(crate) fn residual(
        &self,
        unshot: &[Rgb],
        reflectance: &[Rgb],
        lossless: &[bool],
        within: Option<&[u32]>,
    ) -> Vec<Rgb> {
        let patches = unshot.len();
        let mut residual = vec![Rgb::ZERO; patches];
        if self.slot.len() != patches {
            return residual;
        }
        let listed: Vec<u32> = match within {
            Some(within) => within.to_vec(),
            None => (0..patches as u32).collect(),
        };
        let listed: Vec<(usize, &[u32])> = listed
            .into_iter()
            .map(|p| p as usize)
            .filter_map(|p| Some((p, self.of(p)?)))
            .collect();
        let scale = listed
            .iter()
            .map(|&(p, _)| unshot[p].max_element())
            .fold(0.0, f64::max);
        for _ in 0..MAX_ITERATIONS {
            let next: Vec<Rgb> = listed
                .par_iter()
                .map(|&(p, hits)| {
                    let seen = hits
                        .iter()
                        .filter(|&&h| h != MISS)
                        .map(|&h| unshot[h as usize] + residual[h as usize])
                        .sum::<Rgb>();
                    reflectance[p] * seen / rays_counted(hits, lossless[p])
                })
                .collect();
            let mut change = 0.0_f64;
            for (&(p, _), value) in listed.iter().zip(next) {
                change = change.max((value - residual[p]).abs().max_element());
                residual[p] = value;
            }
            if change <= CONVERGENCE * scale {
                break;
            }
        }
        residual
    }
}

/// The patch that ray `k` of `count` of patch `p` hits first, or [`MISS`]:
/// from the `k`-th of `count` stratified points on its elements,
/// cosine-weighted, traversing `visibility_of` its surface. A patch without
/// elements (all hidden) casts only misses. The same ray whoever casts it:
/// seeded by the patch and its index.
pub(crate) fn patch_ray<'v>(
    scene: &Scene,
    mesh: &Mesh,
    p: usize,
    k: usize,
    count: usize,
    locator: &PatchLocator,
    visibility_of: &(dyn Fn(SurfaceId) -> &'v Visibility + Sync),
) -> u32 {
    let patch = &mesh.patches[p];
    let normal = scene.surface(patch.surface).normal();
    let mut stream = SampleStream::new(p as u64, k as u64 | 1 << 40);
    point_on_elements(mesh, p, k, count, &mut stream).map_or(MISS, |origin| {
        // Not stratified: the points are, by k.
        let direction = cosine_direction(normal, &mut stream);
        let start = RayStart {
            origin,
            normal,
            surface: patch.surface,
        };
        let visibility = visibility_of(patch.surface);
        locator.hit(scene, visibility, start, direction).0
    })
}

/// The `k`-th of `count` stratified points on patch `p`'s elements
/// (its visible part: the cell less what objects standing on it hide),
/// stratified by area over the elements in order, jittered within each.
/// `None` for a patch without elements.
fn point_on_elements(
    mesh: &Mesh,
    p: usize,
    k: usize,
    count: usize,
    stream: &mut SampleStream,
) -> Option<DVec3> {
    let patch = &mesh.patches[p];
    let total: f64 = patch
        .elements
        .iter()
        .map(|&e| mesh.elements[e as usize].area)
        .sum();
    if patch.elements.is_empty() || total <= 0.0 {
        return None;
    }
    let mut target = (k as f64 + stream.next_f64()) / count as f64 * total;
    let mut chosen = patch.elements[patch.elements.len() - 1];
    for &e in &patch.elements {
        let area = mesh.elements[e as usize].area;
        if target < area {
            chosen = e;
            break;
        }
        target -= area;
    }
    let cell = mesh.element_cell(&mesh.elements[chosen as usize]);
    Some(cell.point(stream.next_f64(), stream.next_f64()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Patches' rays, `PATCH_RAYS` hits after another.
    fn patch_rays(hits: Vec<u32>) -> PatchRays {
        let slot = (0..(hits.len() / PATCH_RAYS) as u32).collect();
        PatchRays { hits, slot }
    }

    /// Two patches that see only each other (every ray of each hits the
    /// other): A = ρ (ΔB + A) on both, so A = ρ ΔB / (1 − ρ) and the ambient
    /// irradiance G = ΔB + A = ΔB / (1 − ρ), Cohen's closed-scene term.
    #[test]
    fn an_enclosure_of_uniform_patches_gets_cohens_term() {
        let rays = patch_rays([vec![1; PATCH_RAYS], vec![0; PATCH_RAYS]].concat());
        let unshot = [Rgb::splat(2.0), Rgb::splat(2.0)];
        let reflectance = [Rgb::splat(0.5), Rgb::splat(0.5)];
        let residual = rays.residual(&unshot, &reflectance, &[false; 2], None);
        for a in residual {
            // ρ ΔB / (1 − ρ) = 0.5 · 2 / 0.5.
            assert!((a.g - 2.0).abs() < 1e-5, "{a:?}");
        }
    }

    /// Rays that leave the scene carry nothing: a patch half of whose rays
    /// miss sees half the other's light.
    #[test]
    fn light_that_leaves_adds_nothing() {
        let half: Vec<u32> = (0..PATCH_RAYS)
            .map(|k| if k % 2 == 0 { 1 } else { MISS })
            .collect();
        let rays = patch_rays([half, vec![MISS; PATCH_RAYS]].concat());
        let unshot = [Rgb::ZERO, Rgb::splat(4.0)];
        let reflectance = [Rgb::splat(0.5), Rgb::splat(0.5)];
        let residual = rays.residual(&unshot, &reflectance, &[false; 2], None);
        assert!((residual[0].r - 1.0).abs() < 1e-12, "{residual:?}");
        assert_eq!(residual[1], Rgb::ZERO);
        // In a zone that keeps its light, the misses are left out of the
        // mean (half the rays land: just enough); a patch none of whose
        // rays land still sees nothing.
        let residual = rays.residual(&unshot, &reflectance, &[true; 2], None);
        assert!((residual[0].r - 2.0).abs() < 1e-12, "{residual:?}");
        assert_eq!(residual[1], Rgb::ZERO);
        // Fewer than half landing: inside an object, the mean over all.
        let few: Vec<u32> = (0..PATCH_RAYS)
            .map(|k| if k % 4 == 0 { 1 } else { MISS })
            .collect();
        let rays = patch_rays([few, vec![MISS; PATCH_RAYS]].concat());
        let residual = rays.residual(&unshot, &reflectance, &[true; 2], None);
        assert!((residual[0].r - 0.5).abs() < 1e-12, "{residual:?}");
    }
}
