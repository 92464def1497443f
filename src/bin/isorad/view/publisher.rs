//! What the solve thread tells the pages, and when: the status after every
//! run of shots, the mesh and its light when a page is there to see them,
//! and the exposure and false-colour tops the scene camera's view gets.
//!
//! **Pacing.** Publishing takes the solve thread's time: about 10 ms for
//! the light of 100,000 vertices, and about 0.2 s to fit the exposure,
//! which renders the scene camera's view (the rasterizer's cost follows
//! the triangles, not the pixels). Each gets at most [`SHARE`] of the solve:
//!
//! - publications are at least [`MIN_INTERVAL`] apart, and at least
//!   (1 − s) / s times what the last one cost, s = [`SHARE`];
//! - the exposure is refitted only after as long, measured against the
//!   last fit's cost, and only once the unshot power has halved since
//!   (the light has changed enough to show).
//!
//! So publishing costs the solve at most 2 · [`SHARE`] = 10 %.

use std::time::{Duration, Instant};

use isorad::{
    Camera, RenderSettings, Scene, Solution, Solver,
    calculation::{FalseColorScale, illuminance_lux},
    render::{Image, auto_exposure},
};
use serde::Serialize;
use serde_json::json;

use super::broadcast::{Broadcast, light_message, mesh_message};

/// The shortest interval between two publications.
pub const MIN_INTERVAL: Duration = Duration::from_millis(330);

/// The share of the solve's time publications may take, and so may the
/// exposure's fits.
const SHARE: f64 = 0.05;

/// The preview render's width for the exposure while solving, pixels.
const PREVIEW_WIDTH: u32 = 160;

/// The quantile of the view's values the false-colour scale is fitted to,
/// as `render --falsecolor` fits it.
const FALSE_COLOUR_QUANTILE: f64 = 0.99;

/// The `status` message.
#[derive(Clone, Debug, Serialize)]
pub struct Status {
    /// Always "status".
    #[serde(rename = "type")]
    pub kind: &'static str,
    /// loading, solving, paused, ambient, done or failed.
    pub state: &'static str,
    pub shots: usize,
    /// Unshot power over emitted power.
    pub unshot: f64,
    /// Seconds since the command started.
    pub elapsed_s: f64,
    pub vertices: usize,
    pub triangles: usize,
    /// The PNG's automatic exposure for the scene camera, stops.
    pub exposure: f64,
    /// The default top of the luminance false-colour scale, cd/m².
    pub luminance_max: f64,
    /// The default top of the illuminance false-colour scale, lx.
    pub illuminance_max: f64,
    /// Why the solve stopped, once it has.
    pub stop_reason: Option<&'static str>,
    /// The ambient term's progress, 0 … 1, while it is gathered.
    pub ambient_progress: Option<f64>,
    /// What went wrong, when the state is "failed".
    pub error: Option<String>,
}

impl Status {
    /// The status before the scene is loaded.
    pub fn loading() -> Status {
        Status {
            kind: "status",
            state: "loading",
            shots: 0,
            unshot: 1.0,
            elapsed_s: 0.0,
            vertices: 0,
            triangles: 0,
            exposure: 0.0,
            luminance_max: 1.0,
            illuminance_max: 1.0,
            stop_reason: None,
            ambient_progress: None,
            error: None,
        }
    }

    /// The status as JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).unwrap_or_else(|_| String::from("{}"))
    }
}

/// The publishing side of the solve thread.
pub struct Publisher<'a> {
    pub broadcast: &'a Broadcast,
    pub status: Status,
    /// The scene's camera: the view the exposure is fitted to.
    pub camera: Camera,
    started: Instant,
    /// The mesh the pages hold: its version and triangles.
    mesh_version: u32,
    triangles: Vec<[u32; 3]>,
    vertex_count: usize,
    /// When the last publication ended, and what it cost.
    last: Instant,
    cost: Duration,
    /// The last fit of the exposure, if any.
    last_fit: Option<Fit>,
}

/// When the exposure was fitted, what it cost, and the unshot fraction
/// then.
#[derive(Clone, Copy, Debug)]
struct Fit {
    ended: Instant,
    cost: Duration,
    unshot: f64,
}

/// How long work that cost `cost` waits before it is done again, to take
/// at most [`SHARE`] of the time: cost · (1 − s) / s.
fn wait_after(cost: Duration) -> Duration {
    cost.mul_f64((1.0 - SHARE) / SHARE)
}

impl<'a> Publisher<'a> {
    pub fn new(broadcast: &'a Broadcast, camera: Camera, started: Instant) -> Publisher<'a> {
        Publisher {
            broadcast,
            status: Status::loading(),
            camera,
            started,
            mesh_version: 0,
            triangles: Vec::new(),
            vertex_count: 0,
            last: Instant::now(),
            cost: Duration::ZERO,
            last_fit: None,
        }
    }

    /// The `hello` message: the scene's name, camera and bounds.
    pub fn hello(&self, scene: &Scene, source: &str) {
        let c = &self.camera;
        let bounds = scene.bounds();
        let xyz = |v: glam::DVec3| [v.x, v.y, v.z];
        let hello = json!({
            "type": "hello",
            "scene": source,
            "camera": {
                "position": xyz(c.position),
                "look_at": xyz(c.look_at),
                "up": xyz(c.up),
                "vfov_deg": c.vfov_deg,
                "width": c.width,
                "height": c.height,
            },
            "bounds": {"min": xyz(bounds.min), "max": xyz(bounds.max)},
        });
        self.broadcast
            .publish(|state| state.hello = Some(hello.to_string()));
    }

    /// How long the solve runs before the next publication.
    pub fn interval(&self) -> Duration {
        MIN_INTERVAL.max(wait_after(self.cost))
    }

    /// Whether the pages want the mesh and light now: one is connected
    /// and the interval has passed, or one has just connected.
    pub fn frames_due(&self) -> bool {
        use std::sync::atomic::Ordering;
        self.broadcast.wanted.load(Ordering::SeqCst)
            || (self.broadcast.clients.load(Ordering::SeqCst) > 0
                && self.last.elapsed() >= self.interval())
    }

    /// Publishes the status, the solver's counters updated.
    pub fn status(&mut self, state: &'static str, solver: &Solver) {
        let status = &mut self.status;
        status.state = state;
        status.shots = solver.stats().shots;
        status.unshot = solver.unshot_fraction();
        status.elapsed_s = self.started.elapsed().as_secs_f64();
        status.vertices = solver.mesh().vertices.len();
        self.broadcast.set_status(status.to_json());
    }

    /// Publishes the mesh (when its vertices or triangles changed) and the
    /// light of `solution`, and refits the view's exposure every few
    /// seconds (`final_view`: now, at the camera's full size and
    /// anti-aliasing, as `isorad render` does).
    pub fn frames(&mut self, solver: &Solver, solution: &Solution<'_>, final_view: bool) {
        use std::sync::atomic::Ordering;
        let begin = Instant::now();
        self.broadcast.wanted.store(false, Ordering::SeqCst);
        let vertices = &solver.mesh().vertices;
        // While solving, a quad keeps the diagonal it was first drawn with
        // (resending the mesh for every flip would cost the solve more
        // than the picture gains); the final mesh splits as the renderer
        // does.
        let keep = vertices.len() == self.vertex_count && self.mesh_version > 0 && !final_view;
        if !keep {
            let triangles = solution.triangle_indices();
            if triangles != self.triangles || vertices.len() != self.vertex_count {
                self.mesh_version += 1;
                let positions: Vec<glam::DVec3> = vertices.iter().map(|v| v.position).collect();
                let message = mesh_message(self.mesh_version, &positions, &triangles);
                self.broadcast.set_mesh(self.mesh_version, message);
                self.status.triangles = triangles.len();
                self.triangles = triangles;
                self.vertex_count = vertices.len();
            }
        }
        let light = light_message(
            self.mesh_version,
            &solution.radiosity(),
            &solution.irradiance(),
        );
        self.broadcast.set_light(light);
        let unshot = solver.unshot_fraction();
        let fit_due = self.last_fit.is_none_or(|fit| {
            fit.ended.elapsed() >= wait_after(fit.cost) && unshot <= 0.5 * fit.unshot
        });
        self.last = Instant::now();
        self.cost = self.last - begin;
        if final_view || fit_due {
            self.fit_view(solution, final_view);
            self.last_fit = Some(Fit {
                ended: Instant::now(),
                cost: self.last.elapsed(),
                unshot,
            });
            self.last = Instant::now();
        }
    }

    /// Fits the exposure and the false-colour tops to the scene camera's
    /// view, as `isorad render` chooses them for its PNG and its
    /// `--falsecolor` picture. At the end (`full`), from the full images of
    /// radiance and irradiance. While solving, from a small preview of the
    /// radiance alone, the illuminance's top from the vertices' values
    /// (the same quantile), which costs no second render.
    fn fit_view(&mut self, solution: &Solution<'_>, full: bool) {
        let (camera, settings) = if full {
            (self.camera.clone(), RenderSettings::default())
        } else {
            (preview_camera(&self.camera), RenderSettings::preview())
        };
        let image = solution.render(&camera, &settings);
        self.status.exposure = auto_exposure(&image);
        self.status.luminance_max = false_colour_top(&image);
        self.status.illuminance_max = if full {
            false_colour_top(&solution.render_irradiance(&camera, &settings))
        } else {
            let lux: Vec<f64> = solution
                .irradiance()
                .into_iter()
                .map(illuminance_lux)
                .collect();
            FalseColorScale::fitted_to_quantile(&lux, FALSE_COLOUR_QUANTILE).maximum
        };
    }
}

/// The camera at [`PREVIEW_WIDTH`] pixels across, its aspect kept.
fn preview_camera(camera: &Camera) -> Camera {
    let mut preview = camera.clone();
    if camera.width > PREVIEW_WIDTH {
        let scale = f64::from(PREVIEW_WIDTH) / f64::from(camera.width);
        preview.width = PREVIEW_WIDTH;
        preview.height = ((f64::from(camera.height) * scale).round() as u32).max(1);
    }
    preview
}

/// The top of a false-colour scale fitted to an image's values, 179 lm/W
/// times the luminance Y of each pixel (cd/m² of radiance, lx of
/// irradiance), as `render --falsecolor` fits it.
fn false_colour_top(image: &Image) -> f64 {
    FalseColorScale::fitted_to_quantile(&image.photometric_values(), FALSE_COLOUR_QUANTILE).maximum
}
