//! The solve loop behind a progress bar, previews between shots, and
//! Ctrl-C.

use std::sync::Mutex;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};
use isorad::{
    Ambient, Phase, PhaseProgress, Progress, Solution, Solver, StopReason, Until,
    solver::ReadingPlace,
};

use crate::progress_lines::{LineClock, phase_line, plain_lines_wanted};
use crate::stop::report_time_limit;

/// Set by Ctrl-C: the solve stops between two shots and the solution so far
/// is written.
pub static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// The error `render` ends with after Ctrl-C, once the images are written.
#[derive(Debug)]
pub struct Interrupted(pub String);

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Interrupted {}

/// Solves until `until` (the tolerance, or a time limit) with a progress
/// bar (none when `quiet`) and no previews: what the commands that read a
/// solution need.
pub fn solve_to_tolerance(
    solver: &mut Solver,
    until: &Until,
    quiet: bool,
) -> anyhow::Result<StopReason> {
    let no_previews = |_: &Solver| Ok(());
    let (stop, _) = solve_with_progress(solver, until, quiet, None, no_previews)?;
    report_time_limit(solver, stop);
    Ok(stop)
}

/// Runs the solver until `until` stops it, with a progress bar of the
/// unshot fraction on a log scale from 100 % down to the tolerance (plain
/// lines when stderr is not a terminal), and calls `preview` every
/// `preview_every` shots. `until`'s time budget counts from this call,
/// previews included. Returns why it stopped and the seconds spent solving
/// (previews not counted).
pub fn solve_with_progress(
    solver: &mut Solver,
    until: &Until,
    quiet: bool,
    preview_every: Option<u64>,
    mut preview: impl FnMut(&Solver) -> anyhow::Result<()>,
) -> anyhow::Result<(StopReason, f64)> {
    let start = Instant::now();
    let deadline = until.time_budget.map(|budget| start + budget);
    let mut preview_seconds = 0.0;
    let tolerance = solver.settings().tolerance;
    let lines = plain_lines_wanted(quiet);
    let clock = LineClock::new();
    let bar = if quiet || lines {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(1000)
    };
    bar.set_style(
        ProgressStyle::with_template("{spinner} solving [{bar:40}] {msg} ({elapsed})")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.enable_steady_tick(Duration::from_millis(100));
    let show = |progress: &Progress| {
        let unshot = progress.unshot_fraction.max(1e-12);
        let counted = progress.convergence_fraction.max(1e-12);
        let done = (counted.ln() / tolerance.ln()).clamp(0.0, 1.0);
        bar.set_position((1000.0 * done) as u64);
        // Closed rooms' unshot power counts at its weight toward the tolerance.
        let counted = if (unshot - counted).abs() > 1e-9 {
            format!(" ({:.2} % counted)", 100.0 * counted)
        } else {
            String::new()
        };
        let message = format!(
            "unshot {:.2} %{counted}, {} shots",
            100.0 * unshot,
            progress.shots
        );
        if lines && clock.due() {
            eprintln!(
                "solving: {message} ({:.0} s)",
                start.elapsed().as_secs_f64()
            );
        }
        bar.set_message(message);
    };
    let max_shots = until.total_shots.unwrap_or(solver.settings().max_shots);
    let stop = loop {
        // Solve to the next preview, if any, then draw it.
        let next = match preview_every {
            Some(every) => {
                let every = usize::try_from(every).unwrap_or(usize::MAX);
                max_shots.min(solver.stats().shots.saturating_add(every))
            }
            None => max_shots,
        };
        let mut run = until.total_shots(next);
        if let Some(deadline) = deadline {
            run = run.time_budget(deadline.saturating_duration_since(Instant::now()));
        }
        let stop = solver.run_until(&run, show);
        if stop != StopReason::ShotLimit || next >= max_shots {
            break stop;
        }
        let preview_start = Instant::now();
        bar.suspend(|| preview(solver))?;
        preview_seconds += preview_start.elapsed().as_secs_f64();
    };
    bar.finish_and_clear();
    warn_if_nothing_is_lit(solver);
    Ok((stop, start.elapsed().as_secs_f64() - preview_seconds))
}

/// Warns when the emitters' light reaches no surface (they face away from
/// the scene, or nothing else is there): the image is black but for them.
fn warn_if_nothing_is_lit(solver: &Solver) {
    let lit = |v: usize| solver.irradiance_at(v).element_sum() > 0.0;
    if solver.stats().shots > 0 && !(0..solver.mesh().vertices.len()).any(lit) {
        eprintln!(
            "warning: no surface receives light from the emitters: all of it leaves the scene. \
             Faces emit from their front only (vertices counter-clockwise seen from the front); \
             check that the emitting faces face the scene"
        );
    }
}

/// Progress bars for the long phases outside the shots (`isorad::phase`):
/// a building's closed rooms, shadow boundaries and mesh before the first
/// shot, its ambient term after the last. One bar at a time (the solve's
/// is suspended while a preview's ambient term shows its own), none when
/// quiet; how long each phase took, from its start to its last unit, is
/// kept for the summary.
pub struct PhaseBars {
    quiet: bool,
    /// Plain lines instead of bars (stderr is not a terminal).
    lines: bool,
    clock: LineClock,
    state: Mutex<PhaseState>,
}

#[derive(Default)]
struct PhaseState {
    /// The phase under way, its bar and when it started.
    current: Option<(Phase, ProgressBar, Instant)>,
    /// Seconds per phase, in the order they first ran (a phase that runs
    /// again, the ambient term of each preview, adds up).
    seconds: Vec<(Phase, f64)>,
}

impl PhaseBars {
    pub fn new(quiet: bool) -> Self {
        PhaseBars {
            quiet,
            lines: plain_lines_wanted(quiet),
            clock: LineClock::new(),
            state: Mutex::new(PhaseState::default()),
        }
    }

    /// Shows `progress` (called by the library from any thread).
    pub fn report(&self, progress: PhaseProgress) {
        let mut state = self
            .state
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let same = matches!(&state.current, Some((phase, ..)) if *phase == progress.phase);
        // A phase that reports its start again (the ambient term of the next
        // image) starts a new bar.
        if !same || progress.done == 0 {
            state.close();
            if self.lines {
                eprintln!("{}: started", progress.phase.describe());
                self.clock.restart();
            }
            let bar = if self.quiet || self.lines {
                ProgressBar::hidden()
            } else {
                ProgressBar::new(progress.total as u64)
            };
            bar.set_style(
                ProgressStyle::with_template(
                    "{spinner} {prefix} [{bar:40}] {human_pos}/{human_len} {msg} ({elapsed})",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
            );
            bar.set_prefix(progress.phase.describe());
            bar.set_message(progress.phase.unit());
            bar.enable_steady_tick(Duration::from_millis(100));
            state.current = Some((progress.phase, bar, Instant::now()));
        }
        if let Some((phase, bar, started)) = &state.current {
            // Reports from several threads may arrive out of order.
            bar.set_position(bar.position().max(progress.done as u64));
            let ongoing = progress.done < progress.total;
            if self.lines && ongoing && self.clock.due() {
                let (done, seconds) = (bar.position() as usize, started.elapsed().as_secs_f64());
                let line = phase_line(
                    phase.describe(),
                    done,
                    progress.total,
                    phase.unit(),
                    seconds,
                );
                eprintln!("{line}");
            }
        }
        // The phase's time ends with its last unit.
        if progress.done >= progress.total {
            if let Some((phase, _, started)) = state.current.as_ref().filter(|_| self.lines) {
                let seconds = started.elapsed().as_secs_f64();
                eprintln!("{}: done in {seconds:.1} s", phase.describe());
            }
            state.close();
        }
    }

    /// The solver's solution with its ambient term, behind a bar.
    pub fn solution_everywhere<'a>(&self, solver: &'a Solver) -> Solution<'a> {
        let solution = solver.solution(Ambient::Everywhere, &|p| self.report(p));
        self.finish();
        solution
    }

    /// The solution that readings at `places` need, behind a bar: the
    /// ambient term of the closed rooms they lie in alone
    /// ([`isorad::Ambient::For`]; a camera's position for
    /// its images).
    pub fn solution_for<'a>(&self, solver: &'a Solver, places: &[ReadingPlace]) -> Solution<'a> {
        let solution = solver.solution(Ambient::For(places), &|p| self.report(p));
        self.finish();
        solution
    }

    /// Closes the bar under way, if any.
    pub fn finish(&self) {
        self.state
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .close();
    }

    /// Seconds per phase so far, in the order the phases first ran, the
    /// one under way included.
    pub fn seconds(&self) -> Vec<(Phase, f64)> {
        let mut state = self
            .state
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        state.close();
        state.seconds.clone()
    }
}

impl PhaseState {
    /// Clears the bar under way and adds its time to its phase's.
    fn close(&mut self) {
        let Some((phase, bar, start)) = self.current.take() else {
            return;
        };
        bar.finish_and_clear();
        let seconds = start.elapsed().as_secs_f64();
        match self.seconds.iter_mut().find(|(p, _)| *p == phase) {
            Some((_, total)) => *total += seconds,
            None => self.seconds.push((phase, seconds)),
        }
    }
}

/// "closed rooms 0.7 s, shadow boundaries 4.6 s, meshing 3.8 s, solve
/// 7.0 s, ambient term 22.8 s": the phases' times for the summary, in the
/// order they run, with the shots' `solve_seconds` before the ambient term.
pub fn phase_times(seconds: &[(Phase, f64)], solve_seconds: f64) -> String {
    let solve = format!("solve {solve_seconds:.1} s");
    let mut parts: Vec<String> = Vec::new();
    for (phase, s) in seconds {
        if *phase == Phase::AmbientTerm {
            parts.push(solve.clone());
        }
        parts.push(format!("{} {s:.1} s", phase.describe()));
    }
    if !parts.contains(&solve) {
        parts.push(solve);
    }
    parts.join(", ")
}
