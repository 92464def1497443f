//! The unshot power ΔB_p A_p of the patches, kept zone by zone: the next
//! shooter and the unshot total without a pass over every patch at every
//! shot.
//!
//! Progressive refinement shoots the patch with the most unshot power
//! (Cohen, Chen, Wallace & Greenberg 1988), and stops when the unshot
//! power falls under a share of the emitted. Found by scanning every
//! patch, both cost a pass over the building per shot, which grows with
//! the square of the rooms. A shot changes the
//! unshot power of its own closed zone's patches only (see `meshing/zones/`), so
//! each zone keeps its strongest patch and its total, and a shot recounts
//! its zone alone; the choice is then among the zones' strongest.
//!
//! The stop criterion reads a second total, Σ w_p ΔB_p A_p, with w_p the
//! setting `closed_zone_weight` (0.1) on the patches of a closed zone that
//! keeps all its light and 1 elsewhere: there the ambient term places the
//! residual whole (see `solver/ambient/rays.rs`), so a closed room stops at ten times
//! the tolerance while an open scene is held to it.
//!
//! The zones exchange no light, so the order in which their shots come
//! changes no zone's solution, only which zones have shot more when the
//! solve stops. The next shooter is therefore the last shot's zone's
//! strongest patch while that holds at least a share (the setting
//! `zone_affinity`, 0.5) of the strongest power of all: shots stay in one
//! room for a while, and its vertices, elements and BVH stay in the
//! processor's caches, which keeps a building's ray rate near one room's.
//! Within a zone the choice is the one a
//! scan of its patches makes: the greatest power, and of equals the
//! highest index.
//!
//! # References
//! M. F. Cohen, S. E. Chen, J. R. Wallace, D. P. Greenberg, "A progressive
//! refinement approach to fast radiosity image generation", SIGGRAPH 1988.

use crate::rgb::Rgb;

/// The strongest unshot patch and the unshot power of every zone.
#[derive(Clone, Debug, Default)]
pub(crate) struct UnshotByZone {
    /// The patches of each zone, in increasing order.
    patches: Vec<Vec<u32>>,
    /// Per zone, its patch with the most unshot power (summed over the
    /// channels) and that power; None for a zone without patches.
    strongest: Vec<Option<(u32, f64)>>,
    /// Per zone, the unshot power of its patches, ΣΔB_p A_p.
    total: Vec<Rgb>,
    /// Each patch's weight toward the tolerance (`closed_zone_weight` in a
    /// zone that keeps its light, else 1).
    weights: Vec<f64>,
    /// Per zone, Σ w_p ΔB_p A_p summed over the channels.
    weighted: Vec<f64>,
    /// The zone of the last shot.
    current: Option<usize>,
}

impl UnshotByZone {
    /// Counts the unshot power of patches whose zones `zone_of_patch` gives
    /// (indices below `zones`), from their unshot radiosity `unshot` and
    /// `areas`, each weighted toward the tolerance by `weights` (one per
    /// patch).
    pub(crate) fn new(
        zone_of_patch: impl Iterator<Item = usize>,
        zones: usize,
        unshot: &[Rgb],
        areas: &[f64],
        mut weights: Vec<f64>,
    ) -> UnshotByZone {
        debug_assert_eq!(weights.len(), unshot.len());
        weights.resize(unshot.len(), 1.0);
        let mut patches = vec![Vec::new(); zones.max(1)];
        for (p, zone) in zone_of_patch.enumerate() {
            patches[zone].push(p as u32);
        }
        let mut counted = UnshotByZone {
            strongest: vec![None; patches.len()],
            total: vec![Rgb::ZERO; patches.len()],
            weighted: vec![0.0; patches.len()],
            weights,
            patches,
            current: None,
        };
        for zone in 0..counted.patches.len() {
            counted.recount(zone, unshot, areas);
        }
        counted
    }

    /// Counts zone `zone` again after a shot there changed its patches'
    /// unshot radiosity.
    pub(crate) fn shot_in(&mut self, zone: usize, unshot: &[Rgb], areas: &[f64]) {
        self.recount(zone, unshot, areas);
        self.current = Some(zone);
    }

    /// Counts zone `zone` again.
    fn recount(&mut self, zone: usize, unshot: &[Rgb], areas: &[f64]) {
        let mut strongest: Option<(u32, f64)> = None;
        let mut total = Rgb::ZERO;
        let mut weighted = 0.0;
        for &p in &self.patches[zone] {
            let (b, area) = (unshot[p as usize], areas[p as usize]);
            total += b * area;
            let sum = b.element_sum() * area;
            weighted += sum * self.weights[p as usize];
            // Of equals the later, as `Iterator::max_by` keeps.
            if strongest.is_none_or(|(_, best)| sum.total_cmp(&best).is_ge()) {
                strongest = Some((p, sum));
            }
        }
        self.strongest[zone] = strongest;
        self.total[zone] = total;
        self.weighted[zone] = weighted;
    }

    /// The patches of each zone, each list ascending.
    pub(crate) fn zone_patches(&self) -> &[Vec<u32>] {
        &self.patches
    }

    /// Counts every zone again.
    pub(crate) fn recount_all(&mut self, unshot: &[Rgb], areas: &[f64]) {
        for zone in 0..self.patches.len() {
            self.recount(zone, unshot, areas);
        }
    }

    /// The patch to shoot next and its unshot power (summed over the
    /// channels): the last shot's zone's strongest while it holds at least
    /// the share `affinity` of the strongest of all, that one otherwise.
    /// None without patches.
    ///
    /// When the solve stops, no zone's
    /// strongest patch holds more than 1/`affinity` times the power a scan
    /// of all patches would have left it.
    #[must_use]
    pub(crate) fn next_shooter(&self, affinity: f64) -> Option<(usize, f64)> {
        let strongest = self.strongest()?;
        let current = self
            .current
            .and_then(|zone| self.strongest.get(zone).copied().flatten());
        Some(match current {
            // Of equals, the highest index, as without zones.
            Some((p, power)) if power >= affinity * strongest.1 && power < strongest.1 => {
                (p as usize, power)
            }
            _ => strongest,
        })
    }

    /// The patch with the most unshot power (summed over the channels) and
    /// that power: of equals, the highest index. None without patches.
    #[must_use]
    fn strongest(&self) -> Option<(usize, f64)> {
        self.strongest
            .iter()
            .flatten()
            .max_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
            .map(|&(p, power)| (p as usize, power))
    }

    /// The unshot power of all patches, ΣΔB_p A_p.
    #[must_use]
    pub(crate) fn total(&self) -> Rgb {
        self.total.iter().copied().sum()
    }

    /// The unshot power of all patches as the tolerance counts it,
    /// Σ w_p ΔB_p A_p, summed over the channels.
    #[must_use]
    pub(crate) fn weighted_total(&self) -> f64 {
        self.weighted.iter().sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against a scan of every patch (and of the last shot's zone's),
    /// through random changes to random zones' patches, ties included; the
    /// weighted total against a weighted sum.
    #[test]
    fn the_choice_and_totals_are_full_scans() {
        let zone_of: Vec<usize> = (0..40).map(|p| (p * 7 + p / 5) % 6).collect();
        let areas: Vec<f64> = (0..40).map(|p| 0.5 + (p % 3) as f64).collect();
        let mut unshot = vec![Rgb::ZERO; 40];
        let weights: Vec<f64> = (0..40)
            .map(|p| if p % 4 == 0 { 0.5 } else { 1.0 })
            .collect();
        let mut counted =
            UnshotByZone::new(zone_of.iter().copied(), 6, &unshot, &areas, weights.clone());
        assert_eq!(counted.strongest().map(|(_, power)| power), Some(0.0));
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            state >> 33
        };
        for _ in 0..500 {
            let zone = (next() % 6) as usize;
            for p in (0..40).filter(|&p| zone_of[p] == zone) {
                // Few values, so that equal powers come up.
                let level = (next() % 4) as f64;
                unshot[p] = Rgb::new(level, 0.5 * level, 0.0) / areas[p];
            }
            counted.shot_in(zone, &unshot, &areas);
            let power = |p: usize| unshot[p].element_sum() * areas[p];
            let scan = (0..40)
                .map(|p| (p, power(p)))
                .max_by(|a, b| a.1.total_cmp(&b.1));
            assert_eq!(counted.strongest(), scan);
            // The next shooter: this zone's strongest while it holds half.
            let in_zone = (0..40)
                .filter(|&p| zone_of[p] == zone)
                .map(|p| (p, power(p)))
                .max_by(|a, b| a.1.total_cmp(&b.1));
            let expected = match (in_zone, scan) {
                (Some(here), Some(all)) if here.1 >= 0.5 * all.1 && here.1 < all.1 => Some(here),
                _ => scan,
            };
            assert_eq!(counted.next_shooter(0.5), expected);
            assert_eq!(counted.next_shooter(1.0), scan);
            let total: Rgb = (0..40).map(|p| unshot[p] * areas[p]).sum();
            assert!((counted.total() - total).abs().max_element() < 1e-12);
            let weighted: f64 = (0..40).map(|p| power(p) * weights[p]).sum();
            assert!((counted.weighted_total() - weighted).abs() < 1e-12);
        }
    }
}
