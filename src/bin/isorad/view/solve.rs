//! The solve thread of `isorad view`: it owns the solver, loads and meshes
//! the scene, shoots, and between runs of shots answers the pages' requests
//! (probes, the glTF, pause, resume and stop) and publishes what they show.
//! Once the solve ends it adds the ambient term, publishes the final
//! solution and answers requests from it for as long as the server runs.
//!
//! A run of shots ends when the interrupt flag is set: by the progress
//! callback once the publication interval has passed, or by a request
//! arriving, so a page waits at most one shot for an answer.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, Sender, channel};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

use isorad::{
    Ambient, ProbeMode, Solution, Solver, StopReason, ToneMap, Until, calculation::illuminance_lux,
    export::encode_glb, phase::silent, photometry::LUMENS_PER_WATT, scene::ProbePoint,
};
use serde_json::json;

use super::broadcast::Broadcast;
use super::publisher::{Publisher, Status};
use crate::args::{Prepared, SolveArgs, prepare};

/// What a page asks of the solve thread.
pub enum Request {
    /// Read the solution at a point: the reply is the probe's JSON, or an
    /// error message.
    Probe {
        point: ProbePoint,
        reply: Sender<Result<String, String>>,
    },
    /// The solution as a glTF binary.
    Export {
        reply: Sender<Result<Vec<u8>, String>>,
    },
    /// Pause, resume or stop the solve.
    Control(Control),
}

/// A change to the solve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Control {
    Pause,
    Resume,
    Stop,
}

/// How the server reaches the solve thread.
#[derive(Clone)]
pub struct SolveHandle {
    requests: Sender<Request>,
    interrupt: Arc<AtomicBool>,
    /// Why the scene could not be loaded or meshed, once that is known.
    failure: Arc<OnceLock<String>>,
}

impl SolveHandle {
    /// Sends `request` and ends the run of shots under way; false when the
    /// solve thread is gone.
    pub fn ask(&self, request: Request) -> bool {
        let sent = self.requests.send(request).is_ok();
        self.interrupt.store(true, Ordering::SeqCst);
        sent
    }

    /// Why the scene could not be loaded or meshed, if it could not.
    pub fn failure(&self) -> Option<&str> {
        self.failure.get().map(String::as_str)
    }
}

/// Starts the solve thread for `args`.
pub fn start(args: SolveArgs, broadcast: Arc<Broadcast>) -> SolveHandle {
    let (requests, receiver) = channel();
    let interrupt = Arc::new(AtomicBool::new(false));
    let failure = Arc::new(OnceLock::new());
    let (flag, failed) = (Arc::clone(&interrupt), Arc::clone(&failure));
    std::thread::spawn(move || run(&args, &broadcast, &receiver, &flag, &failed));
    SolveHandle {
        requests,
        interrupt,
        failure,
    }
}

/// The thread's body: load, solve, finish, then answer requests.
fn run(
    args: &SolveArgs,
    broadcast: &Broadcast,
    requests: &Receiver<Request>,
    interrupt: &AtomicBool,
    failure: &OnceLock<String>,
) {
    let Prepared {
        mut solver,
        phases,
        source,
        started,
    } = match prepare(args) {
        Ok(prepared) => prepared,
        Err(error) => {
            let _ = failure.set(format!("{error:#}"));
            let mut status = Status::loading();
            status.state = "failed";
            status.error = Some(format!("{error:#}"));
            broadcast.set_status(status.to_json());
            return answer_failed(requests);
        }
    };
    let camera = solver.scene().camera_or_default();
    let mut publisher = Publisher::new(broadcast, camera, started);
    publisher.hello(solver.scene(), &source);
    let solve_start = Instant::now();
    // --time-limit counts from the command's start, loading included.
    let deadline = args
        .until(started)
        .time_budget
        .map(|budget| solve_start + budget);
    let reason = solve(&mut solver, &mut publisher, requests, interrupt, deadline);
    eprintln!(
        "solved: {} shots, {} shadow rays in {:.2} s, unshot {:.3} %",
        solver.stats().shots,
        solver.stats().rays,
        solve_start.elapsed().as_secs_f64(),
        100.0 * solver.unshot_fraction()
    );
    publisher.status.stop_reason = Some(describe(reason));
    publisher.status("ambient", &solver);
    // The pages see the ambient term's progress.
    let ambient = publisher.status.clone();
    let solution = solver.solution(Ambient::Everywhere, &|progress| {
        phases.report(progress);
        let mut status = ambient.clone();
        status.ambient_progress = Some(progress.done as f64 / progress.total.max(1) as f64);
        broadcast.set_status(status.to_json());
    });
    publisher.status.ambient_progress = None;
    phases.finish();
    publisher.frames(&solver, &solution, true);
    publisher.status("done", &solver);
    eprintln!("done: the final solution is on the page");
    while let Ok(request) = requests.recv() {
        answer(&solver, &solution, publisher.status.exposure, request);
    }
}

/// Shoots until the solve converges or a page stops it, answering requests
/// and publishing between runs of shots.
fn solve(
    solver: &mut Solver,
    publisher: &mut Publisher<'_>,
    requests: &Receiver<Request>,
    interrupt: &AtomicBool,
    deadline: Option<Instant>,
) -> StopReason {
    let mut paused = false;
    // A request that woke a paused solve, answered by the next pass.
    let mut carried: Vec<Request> = Vec::new();
    loop {
        interrupt.store(false, Ordering::SeqCst);
        let mut pending = std::mem::take(&mut carried);
        pending.extend(requests.try_iter());
        let (controls, queries): (Vec<Request>, Vec<Request>) = pending
            .into_iter()
            .partition(|request| matches!(request, Request::Control(_)));
        for request in controls {
            match request {
                Request::Control(Control::Stop) => return StopReason::Cancelled,
                Request::Control(Control::Pause) => paused = true,
                Request::Control(Control::Resume) => paused = false,
                _ => {}
            }
        }
        let frames_due = publisher.frames_due();
        if !queries.is_empty() || frames_due {
            let solution = solver.solution(Ambient::Omitted, &silent);
            for query in queries {
                answer(solver, &solution, publisher.status.exposure, query);
            }
            if frames_due {
                publisher.frames(solver, &solution, false);
            }
        }
        publisher.status(if paused { "paused" } else { "solving" }, solver);
        if paused {
            // Wake for the next request, or to publish for a new page.
            if let Ok(request) = requests.recv_timeout(Duration::from_millis(100)) {
                carried.push(request);
            }
            continue;
        }
        let interval = publisher.interval();
        let run_start = Instant::now();
        let mut until = Until::default().cancelled_by(interrupt);
        if let Some(deadline) = deadline {
            until = until.time_budget(deadline.saturating_duration_since(Instant::now()));
        }
        let reason = solver.run_until(&until, |_| {
            if run_start.elapsed() >= interval {
                interrupt.store(true, Ordering::SeqCst);
            }
        });
        if reason != StopReason::Cancelled {
            return reason;
        }
    }
}

/// Answers a probe or an export from `solution`; controls after the solve
/// has ended change nothing.
fn answer(solver: &Solver, solution: &Solution<'_>, exposure: f64, request: Request) {
    match request {
        Request::Probe { point, reply } => {
            let _ = reply.send(probe_json(solver, solution, &point));
        }
        Request::Export { reply } => {
            let bytes = encode_glb(solution, &ToneMap { exposure }, Path::new("solution.glb"));
            let _ = reply.send(bytes.map_err(|error| error.to_string()));
        }
        Request::Control(_) => {}
    }
}

/// The probe's reading at `point` as the page shows it: illuminance (lx),
/// luminance (cd/m², 179 lm/W · Y(B) / π) and the surface's name, as
/// `isorad probe --mode gather` computes them.
fn probe_json(
    solver: &Solver,
    solution: &Solution<'_>,
    point: &ProbePoint,
) -> Result<String, String> {
    let probe = solution
        .probe(point, ProbeMode::Gather)
        .map_err(|error| error.to_string())?;
    let surface = &solver.scene().surface(probe.surface).name;
    let rgb = |c: isorad::Rgb| [c.r, c.g, c.b];
    let p = probe.position;
    Ok(json!({
        "surface": surface,
        "position": [p.x, p.y, p.z],
        "illuminance_lx": illuminance_lux(probe.irradiance),
        "luminance_cd_m2": probe.radiosity.luminance() * LUMENS_PER_WATT / std::f64::consts::PI,
        "irradiance": rgb(probe.irradiance),
        "radiosity": rgb(probe.radiosity),
    })
    .to_string())
}

/// After a failed load: every request gets the error.
fn answer_failed(requests: &Receiver<Request>) {
    while let Ok(request) = requests.recv() {
        match request {
            Request::Probe { reply, .. } => {
                let _ = reply.send(Err("the scene could not be loaded".into()));
            }
            Request::Export { reply } => {
                let _ = reply.send(Err("the scene could not be loaded".into()));
            }
            Request::Control(_) => {}
        }
    }
}

/// The status's word for why the solve stopped.
fn describe(reason: StopReason) -> &'static str {
    match reason {
        StopReason::Converged => "converged",
        StopReason::ShotLimit => "shot limit",
        StopReason::TimeBudget => "time budget",
        StopReason::Cancelled => "stopped",
        StopReason::NothingToShoot => "nothing to shoot",
        _ => "stopped",
    }
}
