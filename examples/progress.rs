//! Driving the solver: a custom progress display (of meshing, the shots and
//! the ambient term), and cancellation after a time budget from another
//! thread, leaving a solution that is consistent (its energy ledger
//! balanced) and can be resumed.
//!
//! ```sh
//! cargo run --release --example progress
//! ```

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use isorad::{Ambient, PhaseProgress, Settings, Solver, StopReason, Until, load_scene};

fn main() -> isorad::Result<()> {
    let scene = load_scene("cornell")?.scene;
    let mut settings = Settings::default();
    settings.solver.tolerance = 1e-4; // far more than half a second's work
    // Meshing and the ambient term report their phases from the solver's
    // threads: a display of one's own prints where each starts and ends.
    let phase = |p: PhaseProgress| {
        if p.done == 0 || p.done == p.total {
            let at = if p.done == 0 { "starts" } else { "done" };
            println!(
                "{} {at}: {} {}",
                p.phase.describe(),
                p.total,
                p.phase.unit()
            );
        }
    };
    let mut solver = Solver::new_with_progress(scene, settings, &phase)?;

    // Another thread (a GUI's stop button, say) cancels after 0.5 s.
    let cancel = AtomicBool::new(false);
    let stop = std::thread::scope(|scope| {
        scope.spawn(|| {
            std::thread::sleep(Duration::from_millis(500));
            cancel.store(true, Ordering::Relaxed);
        });
        let until = Until::default().cancelled_by(&cancel);
        solver.run_until(&until, |progress| {
            if progress.shots % 50 == 0 {
                println!(
                    "{:>6.3} s  shot {:>4}  unshot {:>7.3} %  {:>5.1} M rays",
                    progress.elapsed.as_secs_f64(),
                    progress.shots,
                    100.0 * progress.unshot_fraction,
                    progress.rays as f64 / 1e6
                );
            }
        })
    });
    let ledger = solver.energy_balance();
    let imbalance = (ledger.absorbed + ledger.unshot + ledger.escaped - ledger.emitted)
        .abs()
        .max_element()
        / ledger.emitted.max_element();
    println!(
        "{stop:?} after {} shots at {:.3} % unshot; energy ledger off by {imbalance:.1e}",
        solver.stats().shots,
        100.0 * solver.unshot_fraction()
    );
    assert!(imbalance < 1e-9);

    // The solution so far, with the ambient term for the light not yet shot.
    let solution = solver.solution(Ambient::Everywhere, &phase);
    let floor = solution.surface_totals()[0];
    println!(
        "floor: mean radiosity {:.2} W/m² (ambient term added)",
        floor.mean_radiosity.r
    );

    // Resume for another quarter of a second, then stop on the time budget.
    let stop = solver.run_until(
        &Until::default().time_budget(Duration::from_millis(250)),
        |_| {},
    );
    println!(
        "resumed: {stop:?} at {} shots, {:.3} % unshot",
        solver.stats().shots,
        100.0 * solver.unshot_fraction()
    );
    assert!(matches!(
        stop,
        StopReason::TimeBudget | StopReason::Converged
    ));
    Ok(())
}
