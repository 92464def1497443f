//! What the solve thread tells the pages, and when: the status after every
//! run of shots, the mesh and its light when a page is there to see them,
//! and the exposure and false-colour tops the scene camera's view gets.
//!
//! **Pacing.** Publishing a 100,000-vertex state takes tens of
//! milliseconds on the solve thread. The interval between publications is
//! therefore at least [`MIN_INTERVAL`] and at least [`COST_RATIO`] times
//! what the last one cost, so that publishing takes at most
//! 1 / (1 + [`COST_RATIO`]) = 10 % of the solve's time.

use std::time::{Duration, Instant};

use isorad::{
    Camera, RenderSettings, Rgb, Scene, Solution, Solver,
    calculation::FalseColorScale,
    photometry::LUMENS_PER_WATT,
    render::{Image, auto_exposure},
};
use serde::Serialize;
use serde_json::json;

use super::broadcast::{Broadcast, light_message, mesh_message};

/// The shortest interval between two publications.
pub const MIN_INTERVAL: Duration = Duration::from_millis(250);

/// Publications wait this many times their own cost.
const COST_RATIO: u32 = 9;

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
    /// When the exposure was last fitted.
    last_fit: Option<Instant>,
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
        MIN_INTERVAL.max(self.cost * COST_RATIO)
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
        let triangles = solution.triangle_indices();
        let vertices = &solver.mesh().vertices;
        if triangles != self.triangles || vertices.len() != self.vertex_count {
            self.mesh_version += 1;
            let positions: Vec<glam::DVec3> = vertices.iter().map(|v| v.position).collect();
            let message = mesh_message(self.mesh_version, &positions, &triangles);
            self.broadcast.set_mesh(self.mesh_version, message);
            self.status.triangles = triangles.len();
            self.triangles = triangles;
            self.vertex_count = vertices.len();
        }
        let light = light_message(
            self.mesh_version,
            &solution.radiosity(),
            &solution.irradiance(),
        );
        self.broadcast.set_light(light);
        let fit_due = self
            .last_fit
            .is_none_or(|at| at.elapsed() >= 8 * self.interval());
        if final_view || fit_due {
            self.fit_view(solution, final_view);
        }
        self.last = Instant::now();
        self.cost = self.last - begin;
    }

    /// Fits the exposure and the false-colour tops to the scene camera's
    /// view, as `isorad render` chooses them for its PNG and its
    /// `--falsecolor` picture: from a small preview while solving, from
    /// the full image at the end.
    fn fit_view(&mut self, solution: &Solution<'_>, full: bool) {
        let (camera, settings) = if full {
            (self.camera.clone(), RenderSettings::default())
        } else {
            (preview_camera(&self.camera), RenderSettings::preview())
        };
        let image = solution.render(&camera, &settings);
        self.status.exposure = auto_exposure(&image);
        self.status.luminance_max = false_colour_top(&image);
        self.status.illuminance_max =
            false_colour_top(&solution.render_irradiance(&camera, &settings));
        self.last_fit = Some(Instant::now());
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
    let values: Vec<f64> = image
        .pixels()
        .iter()
        .map(|&[r, g, b]| {
            let rgb = Rgb::new(f64::from(r), f64::from(g), f64::from(b));
            rgb.luminance() * LUMENS_PER_WATT
        })
        .collect();
    FalseColorScale::fitted_to_quantile(&values, FALSE_COLOUR_QUANTILE).maximum
}
