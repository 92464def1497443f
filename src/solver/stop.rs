//! When a run of the solver stops ([`Until`]: tolerance, shot limit, time
//! budget, cancellation), why it stopped, and the progress it reports after
//! each shot.

use std::sync::atomic::AtomicBool;
use std::time::Duration;

/// When [`Solver::run_until`](crate::Solver::run_until) stops: whichever criterion is met first.
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
    /// weight ([`Solver::convergence_fraction`](crate::Solver::convergence_fraction), which the patch shots do
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

/// Why [`Solver::run_until`](crate::Solver::run_until) stopped. In every case the solver is between
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

/// What the progress callback of [`Solver::run_until`](crate::Solver::run_until) sees after each shot.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Progress {
    /// Unshot power over emitted power.
    pub unshot_fraction: f64,
    /// The unshot fraction the tolerance is held to (closed zones' counted
    /// at [`crate::SolverSettings::closed_zone_weight`]; see
    /// [`Solver::convergence_fraction`](crate::Solver::convergence_fraction)).
    pub convergence_fraction: f64,
    /// Shots made so far, in all.
    pub shots: usize,
    /// Shadow rays cast so far, in all.
    pub rays: u64,
    /// Time since this run started.
    pub elapsed: Duration,
}
