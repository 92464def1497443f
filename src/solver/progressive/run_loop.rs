//! A solver's run: shots until a stop criterion of [`Until`] is met, with
//! a progress report after each.

use std::sync::atomic::Ordering;
use std::time::Instant;

use crate::solver::progressive::Solver;
use crate::solver::stop::{Progress, StopReason, Until};

impl Solver {
    /// Shoots until a criterion of `until` is met, calling `progress` after
    /// every shot. Criteria are checked between shots, so a cancelled or
    /// timed-out run leaves a consistent solution (one shot is typically a
    /// few milliseconds). The buffers a shot works in are given back when
    /// the run stops, before an image's ambient term needs the memory. A
    /// run that converges (or finds nothing to shoot) then shoots what is
    /// left patch to patch ([`Solver::shoot_patches`]).
    pub fn run_until(&mut self, until: &Until, mut progress: impl FnMut(&Progress)) -> StopReason {
        let start = Instant::now();
        let tolerance = until.tolerance.unwrap_or(self.settings().tolerance);
        let total_shots = until.total_shots.unwrap_or(self.settings().max_shots);
        let reason = loop {
            if until.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                break StopReason::Cancelled;
            }
            if self.convergence_fraction() <= tolerance && !self.emission_pending() {
                break StopReason::Converged;
            }
            if self.stats().shots >= total_shots {
                break StopReason::ShotLimit;
            }
            if until.time_budget.is_some_and(|b| start.elapsed() >= b) {
                break StopReason::TimeBudget;
            }
            if !self.step() {
                break StopReason::NothingToShoot;
            }
            progress(&Progress {
                unshot_fraction: self.unshot_fraction(),
                convergence_fraction: self.convergence_fraction(),
                shots: self.stats().shots,
                rays: self.stats().rays,
                elapsed: start.elapsed(),
            });
        };
        self.release_shot_buffers();
        // Patch shots made since the last shot stand: no shot came after.
        let made = self.patch_shot_summary().is_some();
        if matches!(reason, StopReason::Converged | StopReason::NothingToShoot) && !made {
            self.shoot_patches();
        }
        reason
    }

    /// Shoots until the settings' tolerance or shot limit is reached.
    pub fn run(&mut self) -> StopReason {
        self.run_until(&Until::default(), |_| {})
    }
}
