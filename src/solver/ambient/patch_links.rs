//! A zone's patch-to-patch links: each node's rays with the patch each
//! lands on ([`Links`]), cast from what the patch shots read of a solver
//! ([`PatchShotInput`]), and the sweeps that shoot the nodes' unshot
//! power along them (see `solver/ambient/patch_shots.rs`).

use rayon::prelude::*;

use crate::mesh::Mesh;
use crate::rgb::Rgb;
use crate::scene::{Scene, SurfaceId, Visibility};
use crate::solver::ambient::patch_clusters::Clusters;
use crate::solver::ambient::patch_locator::PatchLocator;
use crate::solver::ambient::patch_rays::patch_ray;
use crate::solver::ambient::rays::{MISS, rays_counted};

/// A zone shoots at most this many sweeps: with reflectances near 1 in a
/// closed room it would need more to reach its share.
const MAX_SWEEPS: usize = 1000;

/// What the patch shots read of a solver.
pub(crate) struct PatchShotInput<'a, 'v> {
    pub(crate) scene: &'a Scene,
    pub(crate) mesh: &'a Mesh,
    /// Each zone's patches, ascending.
    pub(crate) zones: &'a [Vec<u32>],
    /// Unshot radiosity ΔB_p per patch, W/m².
    pub(crate) unshot: &'a [Rgb],
    /// The area the unshot power is counted over, per patch.
    pub(crate) areas: &'a [f64],
    /// Reflectance per surface.
    pub(crate) reflectance: &'a [Rgb],
    /// Whether each surface's zone keeps all its light.
    pub(crate) lossless: &'a [bool],
    pub(crate) locator: &'a PatchLocator,
    /// The closed zone of each surface, which a cluster keeps to.
    pub(crate) surface_zone: &'a [u32],
    /// The patch edge the mesh was made for, which bounds a cluster's
    /// extent (`solver/ambient/patch_clusters.rs`); `None` for no clusters.
    pub(crate) cluster_edge: Option<f64>,
    /// The BVH a ray from a surface traverses: its closed zone's.
    pub(crate) visibility_of: &'a (dyn Fn(SurfaceId) -> &'v Visibility + Sync),
}

/// A zone's rays, node by node: where each lands, and what each node's
/// shares are over.
pub(crate) struct Links {
    /// Each ray's landing patch as an index into the zone's list, or
    /// [`MISS`] (none, or a patch of another zone: a leak through a seam);
    /// node n's are `hits[starts[n]..starts[n + 1]]`.
    pub(crate) hits: Vec<u32>,
    starts: Vec<usize>,
    /// The rays each node's shares are over ([`rays_counted`]).
    counted: Vec<f64>,
    /// Each patch's reflectance.
    reflectance: Vec<Rgb>,
    /// Each patch's node.
    node_of: Vec<u32>,
}

/// What a zone's sweeps did: the power each patch received, in the zone's
/// order, and the ledger.
pub(crate) struct Swept {
    pub(crate) received: Vec<Rgb>,
    pub(crate) left: Rgb,
    pub(crate) absorbed: Rgb,
    pub(crate) escaped: Rgb,
    pub(crate) sweeps: usize,
}

impl Links {
    /// Casts the rays of the zone of `patches` (ascending), `counts[k]`
    /// from patch k, node by node of `clusters`. A ray that lands on a
    /// patch without area lands nowhere: nothing there receives.
    pub(crate) fn cast(
        input: &PatchShotInput,
        patches: &[u32],
        clusters: &Clusters,
        counts: &[usize],
    ) -> Links {
        let (scene, mesh) = (input.scene, input.mesh);
        let (locator, visibility_of) = (input.locator, input.visibility_of);
        let mut starts = Vec::with_capacity(clusters.len() + 1);
        starts.push(0);
        for rays in clusters.sum_by_node(|k| counts[k]) {
            starts.push(starts[starts.len() - 1] + rays);
        }
        let hits: Vec<u32> = clusters
            .order()
            .par_iter()
            .flat_map_iter(|&k| {
                let (p, count) = (patches[k as usize] as usize, counts[k as usize]);
                (0..count).map(move |ray| {
                    let h = patch_ray(scene, mesh, p, ray, count, locator, visibility_of);
                    match patches.binary_search(&h) {
                        Ok(landing) if input.areas[h as usize] > 0.0 => landing as u32,
                        _ => MISS,
                    }
                })
            })
            .collect();
        let surface = |k: usize| input.mesh.patches[patches[k] as usize].surface.index();
        // A node's patches lie in one closed zone (the cluster key holds
        // it), which keeps its light or not.
        let counted = (0..clusters.len())
            .map(|n| {
                let rays = &hits[starts[n]..starts[n + 1]];
                let first = clusters.members(n)[0] as usize;
                rays_counted(rays, input.lossless[surface(first)])
            })
            .collect();
        let reflectance = (0..patches.len())
            .map(|k| input.reflectance[surface(k)])
            .collect();
        Links {
            hits,
            starts,
            counted,
            reflectance,
            node_of: clusters.node_of(),
        }
    }

    /// Node n's rays.
    fn of(&self, n: usize) -> &[u32] {
        &self.hits[self.starts[n]..self.starts[n + 1]]
    }

    /// Shoots the nodes' `unshot_power` along the links, a sweep at a time,
    /// each node its whole unshot power in order, until at most `target`
    /// (summed over the channels) is left or [`MAX_SWEEPS`] sweeps are
    /// done. A share landing on a patch is received there, and what the
    /// patch reflects of it joins its node's unshot power.
    pub(crate) fn shoot(&self, mut unshot_power: Vec<Rgb>, target: f64) -> Swept {
        let mut swept = Swept {
            received: vec![Rgb::ZERO; self.reflectance.len()],
            left: unshot_power.iter().copied().sum(),
            absorbed: Rgb::ZERO,
            escaped: Rgb::ZERO,
            sweeps: 0,
        };
        while swept.left.element_sum() > target && swept.sweeps < MAX_SWEEPS {
            for n in 0..unshot_power.len() {
                let power = std::mem::replace(&mut unshot_power[n], Rgb::ZERO);
                if power == Rgb::ZERO {
                    continue;
                }
                if self.counted[n] <= 0.0 {
                    // No rays: nothing of the zone receives it.
                    swept.escaped += power;
                    continue;
                }
                let share = power / self.counted[n];
                let mut landed = 0usize;
                for &h in self.of(n) {
                    if h == MISS {
                        continue;
                    }
                    let (h, reflectance) = (h as usize, self.reflectance[h as usize]);
                    landed += 1;
                    swept.received[h] += share;
                    unshot_power[self.node_of[h] as usize] += reflectance * share;
                    swept.absorbed += (Rgb::ONE - reflectance) * share;
                }
                swept.escaped += share * (self.counted[n] - landed as f64);
            }
            swept.left = unshot_power.iter().copied().sum();
            swept.sweeps += 1;
        }
        swept
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Links of patches whose rays land as `targets` says, each patch's
    /// rays alike, every one counted.
    fn links(targets: &[u32], reflectance: &[f64]) -> Links {
        const RAYS: usize = 8;
        let hits = targets
            .iter()
            .flat_map(|&t| std::iter::repeat_n(t, RAYS))
            .collect();
        Links {
            hits,
            starts: (0..=targets.len()).map(|k| k * RAYS).collect(),
            counted: vec![RAYS as f64; targets.len()],
            reflectance: reflectance.iter().map(|&r| Rgb::splat(r)).collect(),
            node_of: (0..targets.len() as u32).collect(),
        }
    }

    /// Two patches that see only each other, reflectances ρ₀ and ρ₁, the
    /// first holding power 1: the second receives 1 / (1 − ρ₀ρ₁) in all,
    /// the first ρ₁ times that, and the ledger closes.
    #[test]
    fn two_facing_patches_trade_a_geometric_series() {
        let (r0, r1) = (0.5, 0.8);
        let links = links(&[1, 0], &[r0, r1]);
        let swept = links.shoot(vec![Rgb::ONE, Rgb::ZERO], 1e-12);
        let second = 1.0 / (1.0 - r0 * r1);
        assert!(
            (swept.received[1].r - second).abs() < 1e-9,
            "{:?}",
            swept.received
        );
        assert!((swept.received[0].r - r1 * second).abs() < 1e-9);
        let total = swept.absorbed + swept.escaped + swept.left;
        assert!((total.r - 1.0).abs() < 1e-12, "{total:?}");
        assert_eq!(swept.escaped, Rgb::ZERO);
        assert!(swept.left.r <= 1e-12 / 3.0 && swept.sweeps > 10);
    }

    /// A large patch of reflectance ρ₀ holding power 1 faces a cluster of
    /// two small ones, ρ₁ and ρ₂, half its rays landing on each; the
    /// cluster's rays all land back on it. The cluster pools what its
    /// members reflect, ρ̄ = (ρ₁ + ρ₂) / 2 of what it receives, and shoots
    /// it as one: it receives 1 / (1 − ρ₀ρ̄) in all, half on each member,
    /// and the ledger closes.
    #[test]
    fn a_cluster_pools_what_its_members_reflect_and_shoots_it_as_one() {
        let (r0, r1, r2) = (0.5, 0.2, 0.8);
        let links = Links {
            hits: vec![1, 2, 1, 2, 0, 0, 0],
            starts: vec![0, 4, 7],
            counted: vec![4.0, 3.0],
            reflectance: [r0, r1, r2].map(Rgb::splat).to_vec(),
            node_of: vec![0, 1, 1],
        };
        let swept = links.shoot(vec![Rgb::ONE, Rgb::ZERO], 1e-12);
        let cluster = 1.0 / (1.0 - r0 * (r1 + r2) / 2.0);
        let received: Vec<f64> = swept.received.iter().map(|r| r.r).collect();
        assert!((received[1] - cluster / 2.0).abs() < 1e-9, "{received:?}");
        assert!((received[2] - cluster / 2.0).abs() < 1e-9, "{received:?}");
        assert!((received[0] - (r1 + r2) / 2.0 * cluster).abs() < 1e-9);
        let total = swept.absorbed + swept.escaped + swept.left;
        assert!((total.r - 1.0).abs() < 1e-12, "{total:?}");
    }

    /// Rays that land nowhere carry their shares out of the zone, and the
    /// sweeps stop once the target is met: one sweep here, in which the
    /// second patch sends back at once what it took from the first.
    #[test]
    fn rays_that_land_nowhere_escape() {
        let mut links = links(&[1, 0], &[0.5, 0.5]);
        // Half of the first patch's rays miss.
        for ray in links.hits.iter_mut().take(4) {
            *ray = MISS;
        }
        let swept = links.shoot(vec![Rgb::ONE, Rgb::ZERO], 0.5);
        assert_eq!(swept.sweeps, 1);
        assert_eq!(swept.escaped.r, 0.5);
        assert_eq!((swept.left.r, swept.absorbed.r), (0.125, 0.375));
        assert_eq!(
            swept.received.iter().map(|r| r.r).collect::<Vec<_>>(),
            [0.25, 0.5]
        );
    }

    /// Reflectances of 1 would trade the power back and forth for ever:
    /// the sweeps stop at the most, with all of it left and none lost.
    #[test]
    fn sweeps_stop_at_the_most() {
        let links = links(&[1, 0], &[1.0, 1.0]);
        let swept = links.shoot(vec![Rgb::ONE, Rgb::ZERO], 1e-6);
        assert_eq!(swept.sweeps, MAX_SWEEPS);
        assert_eq!(
            (swept.left.r, swept.absorbed.r, swept.escaped.r),
            (1.0, 0.0, 0.0)
        );
    }

    /// In a zone that keeps its light the shares are over the rays that
    /// land: what a ray lost through a seam would have carried goes with
    /// the others, and nothing escapes.
    #[test]
    fn a_zone_that_keeps_its_light_shares_over_the_rays_that_land() {
        let mut links = links(&[1, 0], &[0.0, 0.0]);
        for ray in links.hits.iter_mut().take(3) {
            *ray = MISS;
        }
        links.counted[0] = rays_counted(links.of(0), true);
        assert_eq!(links.counted[0], 5.0);
        let swept = links.shoot(vec![Rgb::ONE, Rgb::ZERO], 0.0);
        assert_eq!((swept.escaped.r, swept.received[1].r), (0.0, 1.0));
        assert_eq!((swept.absorbed.r, swept.left.r), (1.0, 0.0));
    }

    /// A patch without rays (without area) that holds power keeps none of
    /// the zone's: its power escapes, and the ledger still closes.
    #[test]
    fn power_on_a_patch_without_rays_escapes() {
        let mut links = links(&[1, 0], &[0.5, 0.5]);
        links.hits.truncate(8);
        links.starts = vec![0, 8, 8];
        links.counted[1] = 0.0;
        let swept = links.shoot(vec![Rgb::ZERO, Rgb::ONE], 0.0);
        assert_eq!(
            (swept.escaped.r, swept.absorbed.r, swept.left.r),
            (1.0, 0.0, 0.0)
        );
        assert!(swept.received.iter().all(|r| *r == Rgb::ZERO));
    }
}
