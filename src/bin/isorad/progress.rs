//! The solve loop behind a progress bar, previews between shots, and
//! Ctrl-C.

use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};
use isorad::{Progress, Solver, StopReason, Until};

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

/// Solves to the settings' tolerance with a progress bar (none when
/// `quiet`) and no previews: what the commands that read a solution need.
pub fn solve_to_tolerance(solver: &mut Solver, quiet: bool) -> anyhow::Result<StopReason> {
    let no_previews = |_: &Solver| Ok(());
    let (stop, _) = solve_with_progress(solver, &Until::default(), quiet, None, no_previews)?;
    Ok(stop)
}

/// Runs the solver until `until` stops it, with a progress bar of the
/// unshot fraction on a log scale from 100 % down to the tolerance, and
/// calls `preview` every `preview_every` shots. Returns why it stopped and
/// the seconds spent solving (previews not counted).
pub fn solve_with_progress(
    solver: &mut Solver,
    until: &Until,
    quiet: bool,
    preview_every: Option<u64>,
    mut preview: impl FnMut(&Solver) -> anyhow::Result<()>,
) -> anyhow::Result<(StopReason, f64)> {
    let start = Instant::now();
    let mut preview_seconds = 0.0;
    let tolerance = solver.settings().tolerance;
    let bar = if quiet {
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
        bar.set_message(format!(
            "unshot {:.2} %{counted}, {} shots",
            100.0 * unshot,
            progress.shots
        ));
    };
    let max_shots = until.total_shots.unwrap_or(solver.settings().max_shots);
    let stop = loop {
        // Solve to the next preview, if any, then draw it.
        let next = match preview_every {
            Some(every) => {
                let every = usize::try_from(every).unwrap_or(usize::MAX);
                max_shots.min(solver.shots().saturating_add(every))
            }
            None => max_shots,
        };
        let stop = solver.run_until(&until.total_shots(next), show);
        if stop != StopReason::ShotLimit || next >= max_shots {
            break stop;
        }
        let preview_start = Instant::now();
        preview(solver)?;
        preview_seconds += preview_start.elapsed().as_secs_f64();
    };
    bar.finish_and_clear();
    warn_if_nothing_is_lit(solver);
    Ok((stop, start.elapsed().as_secs_f64() - preview_seconds))
}

/// Warns when the emitters' light reaches no surface (they face away from
/// the scene, or nothing else is there): the image is black but for them.
fn warn_if_nothing_is_lit(solver: &Solver) {
    let lit = |h: &isorad::Rgb| h.element_sum() > 0.0;
    if solver.shots() > 0 && !solver.irradiance().iter().any(lit) {
        eprintln!(
            "warning: no surface receives light from the emitters: all of it leaves the scene. \
             Faces emit from their front only (vertices counter-clockwise seen from the front); \
             check that the emitting faces face the scene"
        );
    }
}
