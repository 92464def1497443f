//! Solve a scene once, then render it from many cameras: radiosity is
//! view-independent, so every new view is only a rasterization.
//!
//! ```sh
//! cargo run --release --example walkthrough -- SCENE [--views 60] [--width 256]
//!     [--height H] [--tolerance T] [--out-dir DIR] [--write-views] [--json timings.json]
//! ```
//!
//! Meshes and solves as `isorad render` does with the scene file's settings,
//! renders the scene's own camera to `DIR/view_main.exr`, then `--views`
//! cameras along a walkthrough path (see [`walkthrough_cameras`]), timing each
//! stage. `--write-views` also writes every view as `DIR/view_NNN.exr`
//! (outside the timing). The JSON record holds the timings and the cameras, so
//! that `bench/pathtracer_comparison.py` renders the same views with Mitsuba.

use std::f64::consts::TAU;
use std::path::PathBuf;
use std::time::Instant;

use isorad::{
    Ambient, Camera, RenderSettings, Settings, Solver, load_scene, phase::silent, write_exr,
};
use serde_json::json;

type Report = Result<(), Box<dyn std::error::Error>>;

/// Command-line options.
struct Options {
    scene: String,
    views: usize,
    width: u32,
    height: Option<u32>,
    out_dir: PathBuf,
    write_views: bool,
    json: Option<PathBuf>,
    tolerance: Option<f64>,
}

fn parse_options() -> Result<Options, String> {
    let mut args = std::env::args().skip(1);
    let mut options = Options {
        scene: String::new(),
        views: 60,
        width: 256,
        height: None,
        out_dir: PathBuf::from("."),
        write_views: false,
        json: None,
        tolerance: None,
    };
    while let Some(arg) = args.next() {
        let mut value = |name: &str| args.next().ok_or(format!("{name} needs a value"));
        match arg.as_str() {
            "--views" => options.views = parse(&value("--views")?)?,
            "--width" => options.width = parse(&value("--width")?)?,
            "--height" => options.height = Some(parse(&value("--height")?)?),
            "--out-dir" => options.out_dir = PathBuf::from(value("--out-dir")?),
            "--json" => options.json = Some(PathBuf::from(value("--json")?)),
            "--tolerance" => options.tolerance = Some(parse(&value("--tolerance")?)?),
            "--write-views" => options.write_views = true,
            _ if arg.starts_with("--") => return Err(format!("unknown option {arg}")),
            _ => options.scene = arg,
        }
    }
    if options.scene.is_empty() {
        return Err(
            "usage: walkthrough SCENE [--views N] [--width W] [--height H] \
                    [--tolerance T] [--out-dir DIR] [--write-views] [--json FILE]"
                .into(),
        );
    }
    Ok(options)
}

fn parse<T: std::str::FromStr>(text: &str) -> Result<T, String> {
    text.parse()
        .map_err(|_| format!("`{text}` is not a valid number"))
}

/// `count` cameras along a walkthrough: the eye dollies from the scene's
/// camera half way to its look-at point while swaying sideways by ±10 % of
/// that distance (one full sine period), always looking at the same point.
/// The first camera is the scene's own.
fn walkthrough_cameras(camera: &Camera, count: usize) -> Vec<Camera> {
    let towards = camera.look_at - camera.position;
    let sway = 0.1 * towards.length() * camera.frame().right;
    (0..count)
        .map(|k| {
            let s = if count > 1 {
                k as f64 / (count - 1) as f64
            } else {
                0.0
            };
            Camera {
                position: camera.position + 0.5 * s * towards + (TAU * s).sin() * sway,
                ..camera.clone()
            }
        })
        .collect()
}

fn camera_json(camera: &Camera) -> serde_json::Value {
    json!({
        "position": camera.position.to_array(),
        "look_at": camera.look_at.to_array(),
        "up": camera.up.to_array(),
        "vfov_deg": camera.vfov_deg,
        "width": camera.width,
        "height": camera.height,
    })
}

fn main() -> Report {
    let options = parse_options()?;
    std::fs::create_dir_all(&options.out_dir)?;
    let start = Instant::now();

    // Load; build the BVH and mesh with the scene file's settings, as `isorad render`.
    let loaded = load_scene(&options.scene)?;
    let load_seconds = start.elapsed().as_secs_f64();
    let mut settings = Settings::from_scene_options(&loaded.options)?;
    if let Some(tolerance) = options.tolerance {
        settings.solver.tolerance = tolerance;
    }
    let mesh_start = Instant::now();
    let mut solver = Solver::new(loaded.scene, settings)?;
    let mesh_seconds = mesh_start.elapsed().as_secs_f64();

    // Solve once.
    let solve_start = Instant::now();
    solver.run();
    let solve_seconds = solve_start.elapsed().as_secs_f64();
    let (scene, mesh) = (solver.scene(), solver.mesh());
    let solution = solver.solution(Ambient::Everywhere, &silent);

    // The scene's own view: the image compared with the reference.
    let mut camera = scene.camera_or_default();
    camera.height = options.height.unwrap_or_else(|| {
        (f64::from(options.width) * f64::from(camera.height) / f64::from(camera.width)).round()
            as u32
    });
    camera.width = options.width;
    camera.validate()?;
    let render_settings = RenderSettings::default();
    let render_start = Instant::now();
    let image = solution.render(&camera, &render_settings);
    let render_seconds = render_start.elapsed().as_secs_f64();
    let converged_seconds = start.elapsed().as_secs_f64();
    write_exr(&image, &options.out_dir.join("view_main.exr"))?;

    // The walkthrough: every view a rasterization of the same solution's
    // triangles, those of the room the camera stands in where it stands in
    // a closed one (`Solution::triangles_seen_from`).
    let cameras = walkthrough_cameras(&camera, options.views);
    let mut view_seconds = Vec::with_capacity(cameras.len());
    for (k, view) in cameras.iter().enumerate() {
        let view_start = Instant::now();
        let image = solution.render(view, &render_settings);
        view_seconds.push(view_start.elapsed().as_secs_f64());
        if options.write_views {
            write_exr(&image, &options.out_dir.join(format!("view_{k:03}.exr")))?;
        }
    }
    let views_seconds = view_seconds.iter().fold(0.0, |sum, t| sum + t);

    let record = json!({
        "scene": options.scene,
        "vertices": mesh.vertices.len(),
        "elements": mesh.elements.len(),
        "shots": solver.stats().shots,
        "rays": solver.stats().rays,
        "threads": rayon::current_num_threads(),
        "supersampling": render_settings.supersampling,
        "load_seconds": load_seconds,
        "mesh_seconds": mesh_seconds,
        "solve_seconds": solve_seconds,
        "render_seconds": render_seconds,
        "converged_seconds": converged_seconds,
        "views": cameras.len(),
        "views_seconds": views_seconds,
        "view_seconds": view_seconds,
        "main_camera": camera_json(&camera),
        "cameras": cameras.iter().map(camera_json).collect::<Vec<_>>(),
    });
    let text = serde_json::to_string_pretty(&record)?;
    match &options.json {
        Some(path) => std::fs::write(path, text)?,
        None => println!("{text}"),
    }
    eprintln!(
        "{}: {} vertices, {} shots; load {load_seconds:.3} s, mesh {mesh_seconds:.3} s, \
         solve {solve_seconds:.3} s, render {render_seconds:.3} s; {} views in {views_seconds:.3} s",
        options.scene,
        mesh.vertices.len(),
        solver.stats().shots,
        cameras.len()
    );
    Ok(())
}
