//! The long phases outside the shots, for progress displays: a building's
//! closed rooms, shadow boundaries and mesh take minutes before the first
//! shot, and its ambient term minutes after the last. A phase that does
//! not apply (shadow boundaries without luminaires, contour layouts under
//! the square mesher, the ambient term with nothing unshot) reports
//! nothing.
//!
//! [`crate::Solver::new_with_progress`] and
//! [`crate::Solver::solution`] (its ambient term) call a reporter with a
//! [`PhaseProgress`] as each phase starts, as it goes (at most about 256
//! times a phase, from any thread) and as it ends; the shots themselves
//! report through [`crate::Solver::run_until`].

use std::sync::atomic::{AtomicUsize, Ordering};

/// A phase of preparing a solver or reading its solution.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Phase {
    /// Finding the closed rooms (zones), whose shots stay inside; counted
    /// as one unit.
    ClosedRooms,
    /// The shadow boundaries the luminaires cast, receiver by receiver;
    /// counted in surfaces.
    ShadowBoundaries,
    /// Under the contour mesher, which receivers get contours (the
    /// dominance analysis) and their layouts; counted in surfaces.
    ContourLayouts,
    /// The dominance analysis alone (`isorad info`): which luminaire
    /// dominates each receiver; counted in receivers.
    Dominance,
    /// Meshing, surface by surface, then dropping the parts hidden under
    /// objects; counted in surfaces, and one unit more for the hidden parts.
    Meshing,
    /// The ambient term of the light not yet shot, room by room; counted in
    /// vertices, half a vertex once its rays are cast (or found kept from
    /// the last image) and the other half once its light is gathered.
    AmbientTerm,
}

impl Phase {
    /// The phase in a few words, for a progress bar.
    #[must_use]
    pub fn describe(self) -> &'static str {
        match self {
            Phase::ClosedRooms => "closed rooms",
            Phase::ShadowBoundaries => "shadow boundaries",
            Phase::ContourLayouts => "contour layouts",
            Phase::Dominance => "dominance analysis",
            Phase::Meshing => "meshing",
            Phase::AmbientTerm => "ambient term",
        }
    }

    /// What the phase counts, plural, for a progress bar.
    #[must_use]
    pub fn unit(self) -> &'static str {
        match self {
            Phase::ClosedRooms => "steps",
            Phase::ShadowBoundaries | Phase::ContourLayouts | Phase::Meshing => "surfaces",
            Phase::Dominance => "receivers",
            Phase::AmbientTerm => "vertices",
        }
    }
}

/// How far a phase has got: `done` of `total` units ([`Phase::unit`]).
/// A phase reports `done == 0` as it starts and `done == total` as it ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct PhaseProgress {
    /// The phase.
    pub phase: Phase,
    /// Units done.
    pub done: usize,
    /// Units in all.
    pub total: usize,
}

/// What a solver calls with its phases' progress, from any thread.
pub type PhaseReporter<'a> = &'a (dyn Fn(PhaseProgress) + Sync);

/// A reporter that ignores every report: `&silent` where a
/// [`PhaseReporter`] is asked for and no progress is wanted.
pub fn silent(_: PhaseProgress) {}

/// Counts one phase's units from any thread and reports every 1/256 of
/// the total: at the start on creation, at the end on
/// [`PhaseCounter::finish`].
pub(crate) struct PhaseCounter<'a> {
    phase: Phase,
    total: usize,
    step: usize,
    done: AtomicUsize,
    report: PhaseReporter<'a>,
}

/// Reports per phase, at most (and the start and end).
const REPORTS: usize = 256;

impl<'a> PhaseCounter<'a> {
    /// Starts `phase` of `total` units: reports 0 done.
    pub(crate) fn start(phase: Phase, total: usize, report: PhaseReporter<'a>) -> Self {
        report(PhaseProgress {
            phase,
            done: 0,
            total,
        });
        PhaseCounter {
            phase,
            total,
            step: total.div_ceil(REPORTS).max(1),
            done: AtomicUsize::new(0),
            report,
        }
    }

    /// Counts `units` more done, reporting when the count crosses a step.
    pub(crate) fn add(&self, units: usize) {
        if units == 0 {
            return;
        }
        let before = self.done.fetch_add(units, Ordering::Relaxed);
        let after = before + units;
        if after / self.step != before / self.step && after < self.total {
            (self.report)(PhaseProgress {
                phase: self.phase,
                done: after,
                total: self.total,
            });
        }
    }

    /// Ends the phase: reports all done.
    pub(crate) fn finish(self) {
        (self.report)(PhaseProgress {
            phase: self.phase,
            done: self.total,
            total: self.total,
        });
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Mutex;

    use rayon::prelude::*;

    use super::*;

    #[test]
    fn a_phase_reports_its_start_its_steps_and_its_end() {
        let seen = Mutex::new(Vec::new());
        let record = |p: PhaseProgress| seen.lock().unwrap().push(p.done);
        let counter = PhaseCounter::start(Phase::Meshing, 10_000, &record);
        (0..10_000).into_par_iter().for_each(|_| counter.add(1));
        counter.finish();
        let seen = seen.into_inner().unwrap();
        assert_eq!(seen.first(), Some(&0));
        assert_eq!(seen.last(), Some(&10_000));
        // Every step of 40 is crossed once, the last by finish.
        assert_eq!(seen.len(), 1 + 10_000 / 40);
        let mut steps = seen[1..seen.len() - 1].to_vec();
        steps.sort_unstable();
        assert!(steps.windows(2).all(|w| w[0] < w[1]));
        assert!(steps.iter().all(|&d| d % 40 == 0));
    }

    #[test]
    fn an_empty_phase_reports_its_start_and_end() {
        let seen = Mutex::new(Vec::new());
        let record = |p: PhaseProgress| seen.lock().unwrap().push((p.done, p.total));
        let counter = PhaseCounter::start(Phase::AmbientTerm, 0, &record);
        counter.add(0);
        counter.finish();
        assert_eq!(seen.into_inner().unwrap(), vec![(0, 0), (0, 0)]);
    }
}
