//! When a command's solve stops: the settings' tolerance, Ctrl-C, and
//! `--time-limit`, and what is said when the limit stops it.

use std::time::{Duration, Instant};

use isorad::{Solver, StopReason, Until};

use crate::args::SolveArgs;
use crate::progress::INTERRUPTED;

impl SolveArgs {
    /// When the solve stops: the settings' tolerance, Ctrl-C (for the
    /// commands that catch it), or `--time-limit` counted from `started`.
    pub fn until(&self, started: Instant) -> Until<'static> {
        let mut until = Until::default().cancelled_by(&INTERRUPTED);
        if let Some(limit) = self.time_limit {
            let budget = Duration::from_secs_f64(limit).saturating_sub(started.elapsed());
            until = until.time_budget(budget);
        }
        until
    }
}

/// `--time-limit`: a positive, finite number of seconds.
pub fn parse_time_limit(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(seconds) if seconds.is_finite() && seconds > 0.0 && seconds < 1e9 => Ok(seconds),
        _ => Err(format!("{text:?} is not a positive number of seconds")),
    }
}

/// Says on stderr that the time limit stopped the solve, and how far it
/// got.
pub fn report_time_limit(solver: &Solver, stop: StopReason) {
    if stop == StopReason::TimeBudget {
        eprintln!(
            "time limit: the solve stopped after {} shots, unshot {:.3} %; the ambient term stands in for the rest",
            solver.stats().shots,
            100.0 * solver.unshot_fraction()
        );
    }
}
