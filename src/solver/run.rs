//! Driving the solver: when to stop, progress reports, cancellation.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use super::progressive::Solver;

/// When [`Solver::run_until`] stops: whichever criterion is met first.
///
/// Built with chained methods; criteria left out do not apply, except the
/// tolerance and the shot limit, which default to the solver's settings.
///
/// ```
/// use std::sync::atomic::AtomicBool;
/// use std::time::Duration;
/// let cancel = AtomicBool::new(false);
/// let until = isorad::Until::default()
///     .tolerance(1e-3)
///     .time_budget(Duration::from_secs(10))
///     .cancelled_by(&cancel);
/// # let _ = until;
/// ```
#[derive(Clone, Copy, Debug, Default)]
#[non_exhaustive]
pub struct Until<'c> {
    /// Stop when the unshot power the vertices' shots leave is at most
    /// this fraction of the emitted power, closed zones' counted at their
    /// weight ([`Solver::convergence_fraction`], which the patch shots do
    /// not change); `None`: the solver settings' tolerance.
    pub tolerance: Option<f64>,
    /// Stop when the solver has made this many shots in all (earlier runs
    /// included); `None`: the solver settings' `max_shots`.
    pub total_shots: Option<usize>,
    /// Stop when this run has taken this long (checked between shots).
    pub time_budget: Option<Duration>,
    /// Stop when this flag is set (checked between shots), from another
    /// thread or a signal handler.
    pub cancel: Option<&'c AtomicBool>,
}

impl<'c> Until<'c> {
    /// Stop at this unshot fraction of the emitted power.
    #[must_use]
    pub fn tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = Some(tolerance);
        self
    }

    /// Stop once the solver has made this many shots in all.
    #[must_use]
    pub fn total_shots(mut self, shots: usize) -> Self {
        self.total_shots = Some(shots);
        self
    }

    /// Stop once this run has taken this long.
    #[must_use]
    pub fn time_budget(mut self, budget: Duration) -> Self {
        self.time_budget = Some(budget);
        self
    }

    /// Stop once `cancel` is set.
    #[must_use]
    pub fn cancelled_by(mut self, cancel: &'c AtomicBool) -> Self {
        self.cancel = Some(cancel);
        self
    }
}

/// Why [`Solver::run_until`] stopped. In every case the solver is between
/// two shots: its solution is consistent and its energy ledger balanced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum StopReason {
    /// The unshot power fell to the tolerance.
    Converged,
    /// The shot limit was reached.
    ShotLimit,
    /// The time budget was spent.
    TimeBudget,
    /// The cancellation flag was set.
    Cancelled,
    /// No patch has unshot power left (or the scene emits nothing).
    NothingToShoot,
}

/// What the progress callback of [`Solver::run_until`] sees after each shot.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Progress {
    /// Unshot power over emitted power.
    pub unshot_fraction: f64,
    /// The unshot fraction the tolerance is held to (closed zones' counted
    /// at [`crate::SolverSettings::closed_zone_weight`]; see
    /// [`Solver::convergence_fraction`]).
    pub convergence_fraction: f64,
    /// Shots made so far, in all.
    pub shots: usize,
    /// Shadow rays cast so far, in all.
    pub rays: u64,
    /// Time since this run started.
    pub elapsed: Duration,
}

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
