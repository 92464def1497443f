//! Which patch shoots next: an emitting patch whose emission is not yet
//! shot, the strongest first, else the strongest unshot power zone by zone
//! (`unshot_by_zone.rs`); and the recount after a shot.

use crate::solver::light::state::LightState;

impl LightState {
    /// The patch to shoot next and its unshot power (sum of channels), by
    /// patch `areas`: the emitting patch with the most emission not yet
    /// shot (taken off the pending list), else the patch with the most
    /// unshot power, the last shot's zone's while it holds the share
    /// `affinity` of the strongest. None when no patch is left.
    pub(crate) fn next_shooter(&mut self, areas: &[f64], affinity: f64) -> Option<(usize, f64)> {
        let power = |p: usize| self.unshot[p].element_sum() * areas[p];
        let pending = self
            .emission_pending
            .iter()
            .enumerate()
            .max_by(|a, b| power(*a.1 as usize).total_cmp(&power(*b.1 as usize)));
        match pending {
            Some((k, &j)) => {
                self.emission_pending.swap_remove(k);
                Some((j as usize, power(j as usize)))
            }
            None => self.unshot_by_zone.next_shooter(affinity),
        }
    }

    /// Counts the unshot power of closed zone `zone`'s patches again after
    /// a shot changed them, or of every patch, by patch `areas`.
    pub(crate) fn recount_unshot(&mut self, zone: Option<usize>, areas: &[f64]) {
        match zone {
            Some(zone) => self.unshot_by_zone.shot_in(zone, &self.unshot, areas),
            None => self.unshot_by_zone.recount_all(&self.unshot, areas),
        }
    }
}
