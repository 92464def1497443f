//! Patch shots: the unshot power left when the vertices' shots stop, shot
//! patch to patch along fixed random lines until a small share is left.
//!
//! The vertices' shots stop at the tolerance, a closed room's unshot power
//! counted at a tenth: in the offices after their lamps' shots, with half
//! of the light still unshot. Held in full to 1 %, a floor of closed
//! offices would take tens of thousands more shots, each a few
//! milliseconds of work around few rays: a dim reflected shot is smooth,
//! and its vertex gathers buy little. A patch shot is the coarsest level of the
//! hierarchy (Hanrahan, Salzman & Aupperle 1991): patch to patch, with
//! the form factors estimated by the patches' own rays, a few a patch or
//! cluster ([`ray_counts`]), cosine-weighted from stratified points on each
//! patch's elements, cast as the ambient term's are (`solver/ambient/rays.rs`). Ray k
//! of patch p landing on patch h is a sample of F_ph: p's unshot power
//! Φ_p goes out in equal shares
//! Φ_p / n_p along its n_p rays, and a share landing on h is received
//! there,
//!
//! ```text
//!   P_h += Φ_p / n_p,   ΔΦ_h += ρ_h Φ_p / n_p,   absorbed += (1 − ρ_h) Φ_p / n_p,
//! ```
//!
//! a share that lands nowhere of p's zone escapes. In a zone that keeps its
//! light the shares are over the rays that land (n_p counts those, where at
//! least half do: `ambient::rays_counted`), as the zone's vertex shots land
//! whole. Every share goes somewhere, so the energy ledger closes exactly:
//! Σ Φ before = absorbed + escaped + Σ Φ left. The patches shoot in sweeps,
//! each node (a patch, or a cluster below) its whole unshot power in the
//! order of its first patch, what it receives shot at its next turn
//! (Gauss–Seidel: Cohen & Wallace 1993, §5.3; with fixed lines, Neumann
//! et al. 1994, Bekaert 1999). A sweep costs one
//! addition a ray, so a room's few thousand rays carry every bounce.
//! Zones exchange no light: each casts its own rays, in its own BVH, and
//! shoots on its own until it holds at most its share of the tolerance,
//! the same share of its unshot power for every zone.
//!
//! A room's small patches that stand side by side facing the same way
//! (a shelf's spines) shoot and receive as one node N, a cluster
//! (`solver/ambient/patch_clusters.rs`): its rays leave from its members, what lands on
//! a member h joins N's pooled unshot power, ΔΦ_N += ρ_h Φ_p / n_p, and
//! each member keeps the cluster's irradiance. Other patches are nodes
//! alone.
//!
//! Each patch keeps the irradiance its node received, Σ_{h ∈ N} P_h /
//! Σ_{h ∈ N} A_h (a patch alone: P_h / A_h). The ambient
//! term reads ρ_h times it as what patch h will still reflect, its
//! residual (`solver/ambient/rays.rs`), and gathers it at the vertices of the rooms an
//! image, a probe or an export reads; `Solver::solution` keeps the
//! vertices' own shots (pushed down to the vertices as a patch value, a
//! book's spine in its slot would read the patch's mean, far off its own
//! light).
//!
//! # References
//! P. Hanrahan, D. Salzman, L. Aupperle, "A Rapid Hierarchical Radiosity
//! Algorithm", SIGGRAPH 1991. L. Neumann, M. Feda, M. Kopp, W. Purgathofer,
//! "A New Stochastic Radiosity Method for Highly Complex Scenes", EGWR 1994.
//! P. Bekaert, "Hierarchical and Stochastic Algorithms for Radiosity",
//! PhD thesis, KU Leuven, 1999, ch. 4. M. F. Cohen, J. R. Wallace,
//! "Radiosity and Realistic Image Synthesis" (1993), §5.3.

use rayon::prelude::*;

use crate::rgb::Rgb;
use crate::scene::SurfaceId;
use crate::solver::ambient::patch_clusters::{Clusters, PatchPlace};
use crate::solver::ambient::patch_links::{Links, PatchShotInput};
use crate::solver::ambient::patch_locator::PatchLocator;
use crate::solver::ambient::term::AmbientTerm;

/// Rays a node of a zone (a patch, or a cluster of small patches) has in
/// its budget: each casts its share of the zone's in proportion to the
/// power it will shoot ([`ray_counts`]),
/// rounded and held between [`FEWEST_RAYS`] and [`MOST_RAYS`], from as
/// many stratified points on its elements (a cluster's shared among its
/// members). Where most nodes are small and dim, most take the fewest and
/// the mean falls below the budget (in the offices, about 3 a patch).
///
/// The image's ambient term resolves the patches' further bounces at its
/// vertices along their own rays (`solver/ambient/sweeps.rs`), so the
/// patches' noise hardly shows: by the golden tests' metric, a larger
/// budget changes the offices' images by no more than their noise, while
/// the rays are most of the patch shots' time.
const MEAN_RAYS: f64 = 8.0;

/// The fewest rays a node casts.
const FEWEST_RAYS: usize = 2;

/// The most rays a node casts.
const MOST_RAYS: usize = 32;

/// What the patch shots did: the irradiance each patch received, and the
/// ledger of their power.
#[derive(Clone, Debug, Default)]
pub(crate) struct PatchShots {
    /// Irradiance each patch received from the patch shots, W/m², in
    /// `f32`: 12 bytes a patch.
    irradiance: Vec<[f32; 3]>,
    /// The unshot power when they started, Σ ΔB_p A_p.
    pub(crate) before: Rgb,
    /// The unshot power left.
    pub(crate) left: Rgb,
    /// The power the receiving patches absorbed.
    pub(crate) absorbed: Rgb,
    /// The power that landed nowhere in its zone.
    pub(crate) escaped: Rgb,
    /// The most sweeps a zone took.
    pub(crate) sweeps: usize,
    /// Rays cast.
    pub(crate) rays: u64,
    /// Clusters of more than one patch.
    pub(crate) clusters: usize,
    /// The patches in those clusters.
    pub(crate) clustered_patches: usize,
}

/// What [`crate::Solver::shoot_patches`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct PatchShotSummary {
    /// Unshot power over emitted power (sums of channels) when they
    /// started: what the vertices' shots left.
    pub unshot_before: f64,
    /// Unshot power over emitted power that they left.
    pub unshot_after: f64,
    /// The most sweeps over its patches a zone took.
    pub sweeps: usize,
    /// Rays cast: 2 to 32 for each patch alone and each cluster, which
    /// shares its rays among its members (none in a zone without unshot
    /// power).
    pub rays: u64,
    /// Clusters of small patches that shot and received as one.
    pub clusters: usize,
    /// The patches in those clusters.
    pub clustered_patches: usize,
}

impl PatchShots {
    /// Shoots the unshot power of the solver whose parts are `term`, zone
    /// by zone, until each zone holds at most `left_share` of what it had
    /// ([`PatchShots::shoot`]).
    pub(crate) fn shoot_from(term: &AmbientTerm<'_>, left_share: f64) -> PatchShots {
        let visibility_of = |surface: SurfaceId| term.visibility_of(surface);
        let locator = PatchLocator::new(term.scene, term.mesh);
        let (layout, light) = (term.layout, term.light);
        let input = PatchShotInput {
            scene: term.scene,
            mesh: term.mesh,
            zones: light.unshot_by_zone.zone_patches(),
            unshot: &light.unshot,
            areas: &layout.patch_areas,
            reflectance: &layout.surface_reflectance,
            lossless: &layout.surface_lossless,
            locator: &locator,
            surface_zone: &layout.surface_zone,
            cluster_edge: term.settings.patch_clusters.then_some(layout.patch_edge),
            visibility_of: &visibility_of,
        };
        PatchShots::shoot(&input, left_share)
    }

    /// What they did, their unshot powers as fractions of the `emitted`
    /// power (sums of channels; 0 for a dark scene).
    pub(crate) fn summary(&self, emitted: Rgb) -> PatchShotSummary {
        let emitted = emitted.element_sum();
        let fraction = |power: Rgb| {
            if emitted > 0.0 {
                power.element_sum() / emitted
            } else {
                0.0
            }
        };
        PatchShotSummary {
            unshot_before: fraction(self.before),
            unshot_after: fraction(self.left),
            sweeps: self.sweeps,
            rays: self.rays,
            clusters: self.clusters,
            clustered_patches: self.clustered_patches,
        }
    }

    /// Patch `p`'s irradiance from the patch shots, W/m² (zero for a patch
    /// they did not reach).
    pub(crate) fn irradiance(&self, p: usize) -> Rgb {
        self.irradiance.get(p).map_or(Rgb::ZERO, |e| {
            Rgb::new(f64::from(e[0]), f64::from(e[1]), f64::from(e[2]))
        })
    }

    /// Shoots `input`'s unshot power zone by zone until each zone holds at
    /// most `left_share` of what it had (or has shot `patch_links::MAX_SWEEPS`
    /// sweeps).
    pub(crate) fn shoot(input: &PatchShotInput, left_share: f64) -> PatchShots {
        let zones: Vec<ZoneShots> = input
            .zones
            .par_iter()
            .map(|patches| ZoneShots::shoot(input, patches, left_share))
            .collect();
        let mut shots = PatchShots {
            irradiance: vec![[0.0; 3]; input.mesh.patches.len()],
            ..PatchShots::default()
        };
        for (patches, zone) in input.zones.iter().zip(zones) {
            shots.before += zone.before;
            shots.left += zone.left;
            shots.absorbed += zone.absorbed;
            shots.escaped += zone.escaped;
            shots.sweeps = shots.sweeps.max(zone.sweeps);
            shots.rays += zone.rays;
            shots.clusters += zone.clusters;
            shots.clustered_patches += zone.clustered_patches;
            for (&p, e) in patches.iter().zip(&zone.irradiance) {
                shots.irradiance[p as usize] = [e.r as f32, e.g as f32, e.b as f32];
            }
        }
        shots
    }
}

/// One zone's patch shots.
#[derive(Default)]
struct ZoneShots {
    /// The irradiance each of the zone's patches received, in its list's
    /// order.
    irradiance: Vec<Rgb>,
    before: Rgb,
    left: Rgb,
    absorbed: Rgb,
    escaped: Rgb,
    sweeps: usize,
    rays: u64,
    /// Clusters of more than one patch.
    clusters: usize,
    /// The patches in those clusters.
    clustered_patches: usize,
}

impl ZoneShots {
    /// Shoots the zone of `patches` (ascending) until it holds at most
    /// `left_share` of its unshot power.
    fn shoot(input: &PatchShotInput, patches: &[u32], left_share: f64) -> ZoneShots {
        let unshot_power: Vec<Rgb> = patches
            .iter()
            .map(|&p| input.unshot[p as usize] * input.areas[p as usize])
            .collect();
        let before: Rgb = unshot_power.iter().copied().sum();
        if before.element_sum() <= 0.0 {
            return ZoneShots {
                irradiance: vec![Rgb::ZERO; patches.len()],
                before,
                left: before,
                ..ZoneShots::default()
            };
        }
        let area: Vec<f64> = patches.iter().map(|&p| input.areas[p as usize]).collect();
        let reflectance: Vec<f64> = patches
            .iter()
            .map(|&p| {
                let surface = input.mesh.patches[p as usize].surface.index();
                input.reflectance[surface].element_sum() / 3.0
            })
            .collect();
        let clusters = zone_clusters(input, patches);
        let weights = shooting_weights(&area, &reflectance, &unshot_power);
        let node_rays = ray_counts(
            &clusters.sum_by_node(|k| weights[k]),
            &clusters.sum_by_node(|k| area[k]),
        );
        let counts = clusters.member_rays(&node_rays, &weights, &area);
        let node_power = clusters.sum_by_node(|k| unshot_power[k]);
        let links = Links::cast(input, patches, &clusters, &counts);
        let shot = links.shoot(node_power, left_share * before.element_sum());
        // What each cluster received, over its area, for each of its
        // patches: unbiased, as the ledger counts it. Gathered back along
        // each patch's own rays instead (the mean of what the patches it
        // sees sent), a patch would read its own light returned along the
        // very rays that carried it out, and a closed room of high
        // reflectance would come out bright.
        let irradiance = clusters.pooled_irradiance(&shot.received, &area);
        let (clustered, clustered_patches) = clusters.clustered();
        ZoneShots {
            irradiance,
            before,
            left: shot.left,
            absorbed: shot.absorbed,
            escaped: shot.escaped,
            sweeps: shot.sweeps,
            rays: links.hits.len() as u64,
            clusters: clustered,
            clustered_patches,
        }
    }
}

/// The nodes of the zone of `patches`: its small patches side by side
/// facing one way clustered (`solver/ambient/patch_clusters.rs`), unless the input's
/// clusters are off; every other patch a node alone.
fn zone_clusters(input: &PatchShotInput, patches: &[u32]) -> Clusters {
    let places: Vec<PatchPlace> = patches
        .iter()
        .map(|&p| {
            let patch = &input.mesh.patches[p as usize];
            PatchPlace {
                area: input.areas[p as usize],
                normal: input.scene.surface(patch.surface).normal(),
                centre: patch.cell.centre(),
                zone: input.surface_zone[patch.surface.index()],
            }
        })
        .collect();
    match input.cluster_edge {
        Some(edge) => Clusters::of(&places, edge),
        None => Clusters::singletons(places.len()),
    }
}

/// The power each patch of a zone will shoot, for its `area`, mean
/// `reflectance` and `unshot_power`: its unshot power and what it reflects
/// of the light to come, which is taken as ρ A times the zone's mean
/// unshot radiosity (channels summed). The books on a shelf, small and
/// dim, weigh little; the floor under a lamp, much.
fn shooting_weights(area: &[f64], reflectance: &[f64], unshot_power: &[Rgb]) -> Vec<f64> {
    let zone_area: f64 = area.iter().sum();
    let zone_power: f64 = unshot_power.iter().map(|u| u.element_sum()).sum();
    let level = if zone_area > 0.0 {
        zone_power / zone_area
    } else {
        0.0
    };
    (0..area.len())
        .map(|k| unshot_power[k].element_sum() + reflectance[k] * area[k] * level)
        .collect()
}

/// The rays each node of a zone (a patch, or a cluster of patches) casts,
/// for the power it will shoot, `weights` w ([`shooting_weights`]), and its
/// `area`: n = clamp(round(8 N w / Σ w), 2, 32) for N nodes
/// ([`MEAN_RAYS`], [`FEWEST_RAYS`], [`MOST_RAYS`]); none for a node
/// without area (all of it under objects), which neither receives nor
/// shoots. The power a node sends
/// along n rays reaches each patch it lands on with a variance of Φ² / n,
/// and the sum of those over the patches is least, for a given number of
/// rays, where n goes as Φ.
fn ray_counts(weights: &[f64], area: &[f64]) -> Vec<usize> {
    let total: f64 = weights.iter().sum();
    let rays = MEAN_RAYS * area.len() as f64;
    weights
        .iter()
        .zip(area)
        .map(|(&w, &area)| {
            let share = if total > 0.0 { rays * w / total } else { 0.0 };
            let count = (share.round() as usize).clamp(FEWEST_RAYS, MOST_RAYS);
            if area > 0.0 { count } else { 0 }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rays go by the power a patch will shoot: its own unshot power, and
    /// ρ A times the zone's mean unshot radiosity; rounded and held
    /// between the fewest and the most, none where there is no area, and
    /// the fewest where the weights are no number.
    #[test]
    fn rays_go_by_the_power_a_patch_will_shoot() {
        let grey = Rgb::splat;
        // A lit floor, a dim wall as large, four small books, a hidden patch.
        let area = [4.0, 4.0, 0.01, 0.01, 0.01, 0.01, 0.0];
        let reflectance = [0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5];
        let unshot = [
            grey(30.0),
            grey(2.0),
            Rgb::ZERO,
            Rgb::ZERO,
            Rgb::ZERO,
            Rgb::ZERO,
            Rgb::ZERO,
        ];
        let counts = ray_counts(&shooting_weights(&area, &reflectance, &unshot), &area);
        // A budget of 56 rays. The zone's level is 96 / 8.04 = 11.9 W/m²
        // (channels summed), so the floor weighs 90 + 23.9, the wall
        // 6 + 23.9 and a book 0.06: the floor's 44 rays are held to the
        // most, the wall takes 12, the books the fewest.
        assert_eq!(counts, [MOST_RAYS, 12, FEWEST_RAYS, 2, 2, 2, 0]);
        let counts = |unshot: &[Rgb]| {
            let weights = shooting_weights(&[1.0, 1.0], &[0.5, 0.5], unshot);
            ray_counts(&weights, &[1.0, 1.0])
        };
        assert_eq!(counts(&[Rgb::ZERO; 2]), [2, 2]);
        assert_eq!(counts(&[Rgb::splat(f64::NAN), Rgb::ZERO]), [2, 2]);
    }
}
