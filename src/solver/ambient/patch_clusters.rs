//! Clusters for clutter: a zone's small patches that stand side by side
//! facing the same way, which the patch shots shoot and receive as one.
//!
//! A shelf of books is hundreds of patches of a few square centimetres:
//! the cluttered office of `bench/generate_building.py` has 1,085 book
//! patches among its 1,735. Shot one by one, each casts rays of its own
//! (`solver/ambient/patch_shots.rs`: at least two) and
//! keeps the few shares that happen to land on it. Seen from across the
//! room, a row of spines is one surface: a face cluster (Willmott,
//! Heckbert & Garland 1999) stands for it, with the power and the area of
//! its members. Here a cluster is the zone's small patches, each of at most
//! [`SMALL_AREA`] of a full patch's area (a square a quarter of the patch
//! edge on a side), in one closed zone, whose normals round to one point
//! of a lattice of step [`NORMAL_STEP`] and whose
//! centres lie in one cube of the patch edge and in one slab a quarter of
//! it deep along that normal: spines facing the room on one shelf, the
//! books' tops under the board above, their sides facing left. Faces that
//! look other ways on the same shelf see other things and stay apart,
//! and so do the shelf's back and the spines in front of it.
//!
//! A cluster shoots its pooled unshot power along rays shared among its
//! members by the power each will shoot, and receives what lands on any
//! member: each member's share of what a landing reflects, ρ_h times the
//! share, joins the cluster's pool, and the irradiance each member keeps
//! is the cluster's, its received power over its area. Within one
//! orientation and a quarter of a patch edge, that is the light the
//! members share: their further bounces, which the ambient term reads
//! (`solver/ambient/rays.rs`), not their first, which the vertices' shots resolved.
//!
//! # References
//! A. Willmott, P. Heckbert, M. Garland, "Face Cluster Radiosity", EGWR
//! 1999. B. Smits, J. Arvo, D. Greenberg, "A Clustering Algorithm for
//! Radiosity in Complex Environments", SIGGRAPH 1994. F. Sillion, "A Unified
//! Hierarchical Algorithm for Global Illumination with Scattering Volumes
//! and Object Clusters", IEEE TVCG 1995.

use std::collections::HashMap;

use glam::DVec3;

use crate::rgb::Rgb;

/// The largest patch a cluster takes, as a share of a full patch's area
/// (the patch edge squared): a square a quarter of the edge on a side.
const SMALL_AREA: f64 = 1.0 / 16.0;

/// Normals are rounded to a lattice of this step per component, and only
/// those that round to one point cluster: normals a degree or so apart,
/// and axis-aligned faces exactly (two a hair apart may still round to
/// neighbouring points and stay apart).
const NORMAL_STEP: f64 = 1.0 / 64.0;

/// The depth of a cluster's slab along its normal, as a share of the
/// patch edge.
const SLAB: f64 = 0.25;

/// What clustering reads of a patch.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PatchPlace {
    /// The area its power is counted over (zero: all of it under objects).
    pub(crate) area: f64,
    /// Its surface's unit normal.
    pub(crate) normal: DVec3,
    /// Its cell's centre.
    pub(crate) centre: DVec3,
    /// The closed zone its surface lies in: a cluster keeps to one, even
    /// where a solve shoots several rooms as one zone (without the cull).
    pub(crate) zone: u32,
}

/// A zone's patches as shooting nodes: each node a cluster of small patches
/// or a patch alone. Indices are into the zone's patch list.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Clusters {
    /// The patches, node by node, each node's in ascending order.
    members: Vec<u32>,
    /// Node n's patches are `members[starts[n]..starts[n + 1]]`.
    starts: Vec<usize>,
}

impl Clusters {
    /// Each of `count` patches a node of its own.
    pub(crate) fn singletons(count: usize) -> Clusters {
        Clusters {
            members: (0..count as u32).collect(),
            starts: (0..=count).collect(),
        }
    }

    /// Clusters the small patches of `places` (one zone's) that stand side
    /// by side facing the same way, for patches whose edge is at most
    /// `patch_edge`. Nodes come in the order of their first patch, so
    /// that sweeps over them keep the zone's order.
    pub(crate) fn of(places: &[PatchPlace], patch_edge: f64) -> Clusters {
        if !(patch_edge.is_finite() && patch_edge > 0.0) {
            return Clusters::singletons(places.len());
        }
        let small = SMALL_AREA * patch_edge * patch_edge;
        let mut node_of_key: HashMap<[i64; 8], usize> = HashMap::new();
        let mut node_of = Vec::with_capacity(places.len());
        let mut nodes = 0usize;
        for place in places {
            let key = cluster_key(place, small, patch_edge);
            let node = match key {
                Some(key) => *node_of_key.entry(key).or_insert_with(|| {
                    nodes += 1;
                    nodes - 1
                }),
                None => {
                    nodes += 1;
                    nodes - 1
                }
            };
            node_of.push(node);
        }
        let mut starts = vec![0usize; nodes + 1];
        for &node in &node_of {
            starts[node + 1] += 1;
        }
        for n in 0..nodes {
            starts[n + 1] += starts[n];
        }
        let mut filled = starts.clone();
        let mut members = vec![0u32; places.len()];
        for (k, &node) in node_of.iter().enumerate() {
            members[filled[node]] = k as u32;
            filled[node] += 1;
        }
        Clusters { members, starts }
    }

    /// The number of nodes.
    pub(crate) fn len(&self) -> usize {
        self.starts.len() - 1
    }

    /// Node n's patches, ascending.
    pub(crate) fn members(&self, n: usize) -> &[u32] {
        &self.members[self.starts[n]..self.starts[n + 1]]
    }

    /// Every patch, node by node.
    pub(crate) fn order(&self) -> &[u32] {
        &self.members
    }

    /// Each patch's node.
    pub(crate) fn node_of(&self) -> Vec<u32> {
        let mut node_of = vec![0u32; self.members.len()];
        for n in 0..self.len() {
            for &k in self.members(n) {
                node_of[k as usize] = n as u32;
            }
        }
        node_of
    }

    /// Σ_{k ∈ n} value(k) for each node n, patches indexed as the zone's.
    pub(crate) fn sum_by_node<T: std::iter::Sum<T>>(&self, value: impl Fn(usize) -> T) -> Vec<T> {
        (0..self.len())
            .map(|n| self.members(n).iter().map(|&k| value(k as usize)).sum())
            .collect()
    }

    /// The irradiance each patch keeps, E_k = Σ_{m ∈ n} P_m / Σ_{m ∈ n} A_m
    /// over the members m of its node n, from the power P each patch
    /// `received` and its `area` A: a cluster receives as one, and its
    /// members share its light; a patch alone keeps its own; a node
    /// without area keeps none.
    pub(crate) fn pooled_irradiance(&self, received: &[Rgb], area: &[f64]) -> Vec<Rgb> {
        let mut irradiance = vec![Rgb::ZERO; received.len()];
        let power = self.sum_by_node(|k| received[k]);
        let node_area = self.sum_by_node(|k| area[k]);
        for (n, (&power, &node_area)) in power.iter().zip(&node_area).enumerate() {
            if node_area > 0.0 {
                for &k in self.members(n) {
                    irradiance[k as usize] = power / node_area;
                }
            }
        }
        irradiance
    }

    /// The rays each patch casts when node n casts `node_rays[n]`, shared
    /// among its members by their `weights` (the power each will shoot;
    /// their areas where the weights are no use), systematically: ray j
    /// of a node's c leaves from the member whose span of the cumulative
    /// weight holds (j + ½) / c of the total. Indexed by patch.
    pub(crate) fn member_rays(
        &self,
        node_rays: &[usize],
        weights: &[f64],
        areas: &[f64],
    ) -> Vec<usize> {
        let mut rays = vec![0usize; self.members.len()];
        for (n, &count) in node_rays.iter().enumerate() {
            let members = self.members(n);
            if let [only] = members {
                rays[*only as usize] = count;
                continue;
            }
            let sum = |of: &[f64]| members.iter().map(|&k| of[k as usize]).sum::<f64>();
            let by_weight = sum(weights);
            let of = if by_weight.is_finite() && by_weight > 0.0 {
                weights
            } else {
                areas
            };
            let total = sum(of);
            if !(total.is_finite() && total > 0.0) {
                continue;
            }
            let (mut member, mut reached) = (0usize, of[members[0] as usize]);
            for j in 0..count {
                let at = (j as f64 + 0.5) / count as f64 * total;
                while at > reached && member + 1 < members.len() {
                    member += 1;
                    reached += of[members[member] as usize];
                }
                rays[members[member] as usize] += 1;
            }
        }
        rays
    }

    /// The nodes of more than one patch, and the patches in them.
    pub(crate) fn clustered(&self) -> (usize, usize) {
        (0..self.len())
            .map(|n| self.members(n).len())
            .filter(|&size| size > 1)
            .fold((0, 0), |(clusters, patches), size| {
                (clusters + 1, patches + size)
            })
    }
}

/// Where a small patch clusters: its normal on the lattice, the cube of the
/// patch edge its centre lies in, its slab along the normal and its zone;
/// `None` for
/// a patch that stays alone (too large, without area, or not a number).
fn cluster_key(place: &PatchPlace, small: f64, patch_edge: f64) -> Option<[i64; 8]> {
    let finite = place.normal.is_finite() && place.centre.is_finite();
    if !(finite && place.area > 0.0 && place.area <= small) {
        return None;
    }
    let normal = (place.normal / NORMAL_STEP).round();
    let cube = (place.centre / patch_edge).floor();
    let depth = place.centre.dot(normal.normalize_or_zero()) / (SLAB * patch_edge);
    let [nx, ny, nz] = normal.to_array().map(|c| c as i64);
    let [cx, cy, cz] = cube.to_array().map(|c| c as i64);
    let zone = i64::from(place.zone);
    Some([nx, ny, nz, cx, cy, cz, depth.floor() as i64, zone])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn place(area: f64, normal: DVec3, centre: DVec3) -> PatchPlace {
        PatchPlace {
            area,
            normal,
            centre,
            zone: 0,
        }
    }

    /// A shelf with a patch edge of 1 m: four spines facing +z side by
    /// side, a book's top and its side, a spine standing 30 cm further
    /// forward, a spine in the next cube along x, the shelf's large back
    /// behind them, and a spine under an object (no area).
    #[test]
    fn small_patches_side_by_side_facing_one_way_cluster() {
        let z = DVec3::Z;
        let places = [
            place(1.0, z, DVec3::new(0.5, 0.5, 0.0)),
            place(0.0075, z, DVec3::new(0.10, 0.2, 0.2)),
            place(0.0075, z, DVec3::new(0.13, 0.2, 0.2)),
            place(0.0075, DVec3::Y, DVec3::new(0.10, 0.32, 0.1)),
            place(0.0075, z, DVec3::new(0.16, 0.2, 0.21)),
            place(0.0075, DVec3::X, DVec3::new(0.17, 0.2, 0.1)),
            place(0.0075, z, DVec3::new(0.19, 0.2, 0.5)),
            place(0.0075, z, DVec3::new(1.05, 0.2, 0.2)),
            place(0.0, z, DVec3::new(0.22, 0.2, 0.2)),
            place(0.0075, z, DVec3::new(0.25, 0.2, 0.2)),
        ];
        let clusters = Clusters::of(&places, 1.0);
        let nodes: Vec<&[u32]> = (0..clusters.len()).map(|n| clusters.members(n)).collect();
        assert_eq!(
            nodes,
            [&[0][..], &[1, 2, 4, 9], &[3], &[5], &[6], &[7], &[8]]
        );
        assert_eq!(clusters.clustered(), (1, 4));
    }

    /// A patch just over the small area stays alone, one just under joins;
    /// normals a little apart share the lattice point, further apart not.
    #[test]
    fn the_size_and_the_normals_bound_a_cluster() {
        let centre = DVec3::new(0.3, 0.3, 0.3);
        let tilted = |angle: f64| DVec3::new(angle.sin(), 0.0, angle.cos());
        let places = [
            place(0.0624, DVec3::Z, centre),
            place(0.0626, DVec3::Z, centre),
            place(0.01, tilted(0.002), centre),
            place(0.01, tilted(0.05), centre),
        ];
        let clusters = Clusters::of(&places, 1.0);
        assert_eq!(clusters.members(0), [0, 2]);
        assert_eq!(clusters.len(), 3);
    }

    /// A node's rays go to its members by the power each will shoot, in
    /// proportion and systematically; by area where no member has any; a
    /// patch alone takes its node's.
    #[test]
    fn a_clusters_rays_go_to_its_members_by_their_power() {
        let clusters = Clusters {
            members: vec![0, 1, 2, 3],
            starts: vec![0, 3, 4],
        };
        let areas = [1.0, 1.0, 2.0, 5.0];
        let rays = clusters.member_rays(&[8, 5], &[1.0, 0.0, 3.0, 7.0], &areas);
        assert_eq!(rays, [2, 0, 6, 5]);
        let rays = clusters.member_rays(&[8, 5], &[0.0; 4], &areas);
        assert_eq!(rays, [2, 2, 4, 5]);
        let rays = clusters.member_rays(&[4, 0], &[f64::NAN, 1.0, 1.0, 1.0], &areas);
        assert_eq!(rays, [1, 1, 2, 0]);
    }

    /// A cluster's members share what it received over its area; a patch
    /// alone keeps its own, and one without area none.
    #[test]
    fn a_clusters_members_share_its_irradiance() {
        let areas = [0.01, 2.0, 0.03, 0.0];
        let places = areas.map(|area| place(area, DVec3::Z, DVec3::ZERO));
        let clusters = Clusters::of(&places, 1.0);
        let received = [1.0, 4.0, 0.0, 3.0].map(Rgb::splat);
        let irradiance = clusters.pooled_irradiance(&received, &areas);
        let red: Vec<f64> = irradiance.iter().map(|e| e.r).collect();
        assert_eq!(red, [25.0, 2.0, 25.0, 0.0]);
        assert_eq!(clusters.node_of(), [0, 1, 0, 2]);
    }

    /// Patches of different zones stay apart, however close.
    #[test]
    fn a_cluster_keeps_to_its_zone() {
        let mut places = [place(0.01, DVec3::Z, DVec3::splat(0.5)); 3];
        places[1].zone = 1;
        let clusters = Clusters::of(&places, 1.0);
        assert_eq!(clusters.members(0), [0, 2]);
        assert_eq!(clusters.members(1), [1]);
    }

    /// Without a usable patch edge, or with places that are no numbers,
    /// every patch stays alone.
    #[test]
    fn nothing_clusters_without_a_patch_edge_or_a_number() {
        let places = [place(0.01, DVec3::Z, DVec3::ZERO); 3];
        for edge in [0.0, f64::NAN, f64::INFINITY] {
            assert_eq!(Clusters::of(&places, edge), Clusters::singletons(3));
        }
        let nan = [place(0.01, DVec3::Z, DVec3::splat(f64::NAN)); 2];
        assert_eq!(Clusters::of(&nan, 1.0), Clusters::singletons(2));
        assert_eq!(Clusters::of(&places, 1.0).clustered(), (1, 3));
    }
}
