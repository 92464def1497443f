//! Progress as plain lines, for a stderr that is not a terminal (a log
//! file, a pipe, a CI job), where progress bars draw nothing: a line when a
//! phase starts, one every [`LINE_INTERVAL`] while it runs, and one when it
//! ends.

use std::io::IsTerminal;
use std::sync::{Mutex, PoisonError};
use std::time::{Duration, Instant};

/// The interval between two progress lines of one phase.
pub const LINE_INTERVAL: Duration = Duration::from_secs(10);

/// Whether progress goes out as plain lines: not quiet, and stderr is not a
/// terminal.
pub fn plain_lines_wanted(quiet: bool) -> bool {
    !quiet && !std::io::stderr().is_terminal()
}

/// When the last line was printed: a line is due once [`LINE_INTERVAL`]
/// has passed.
pub struct LineClock {
    last: Mutex<Instant>,
}

impl LineClock {
    /// A clock whose first line is due one interval from now.
    pub fn new() -> LineClock {
        LineClock {
            last: Mutex::new(Instant::now()),
        }
    }

    /// Whether a line is due, restarting the interval when it is.
    pub fn due(&self) -> bool {
        let mut last = self.last.lock().unwrap_or_else(PoisonError::into_inner);
        if last.elapsed() >= LINE_INTERVAL {
            *last = Instant::now();
            true
        } else {
            false
        }
    }

    /// Restarts the interval (a line was printed for another reason).
    pub fn restart(&self) {
        *self.last.lock().unwrap_or_else(PoisonError::into_inner) = Instant::now();
    }
}

/// "meshing: 1,200 of 3,832 surfaces (31 %, 4 s)".
pub fn phase_line(phase: &str, done: usize, total: usize, unit: &str, seconds: f64) -> String {
    let percent = 100.0 * done as f64 / total.max(1) as f64;
    format!("{phase}: {done} of {total} {unit} ({percent:.0} %, {seconds:.0} s)")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_say_how_far_a_phase_is() {
        assert_eq!(
            phase_line("meshing", 1200, 3832, "surfaces", 4.2),
            "meshing: 1200 of 3832 surfaces (31 %, 4 s)"
        );
        assert_eq!(
            phase_line("closed rooms", 0, 0, "zones", 0.0),
            "closed rooms: 0 of 0 zones (0 %, 0 s)"
        );
        let clock = LineClock::new();
        assert!(!clock.due(), "the first line waits an interval");
    }
}
