//! The `isorad` command-line program: a thin layer over the library.

use anyhow::Context;
use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use isorad::{
    LoadedScene, RenderSettings, Solver, SolverSettings, SquareMeshSettings, ToneMap, Visibility,
    auto_exposure, load_scene, mesh_square, mesh_triangles, rasterize, write_exr, write_png,
};

/// Global illumination by progressive radiosity.
#[derive(Parser)]
#[command(name = "isorad", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Solve a scene and render it to EXR (linear radiance) and PNG.
    Render(RenderArgs),
}

#[derive(Args)]
struct RenderArgs {
    /// A scene file (.toml), an OBJ file, or a built-in scene name.
    #[arg(default_value = "cornell")]
    scene: String,
    /// Output EXR of linear radiance, W/(m²·sr).
    #[arg(short, long, default_value = "isorad.exr")]
    output: PathBuf,
    /// Output PNG, tone-mapped with the sRGB curve.
    #[arg(long, default_value = "isorad.png")]
    png: PathBuf,
    /// Image width in pixels (overrides the scene's camera).
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels (overrides the scene's camera).
    #[arg(long)]
    height: Option<u32>,
    /// Stop when unshot power < TOLERANCE × emitted power.
    #[arg(long)]
    tolerance: Option<f64>,
    /// Form-factor kernel: mixed (default), wallace or exact.
    #[arg(long, value_name = "KERNEL")]
    form_factor: Option<String>,
    /// Mesher: only "square" so far.
    #[arg(long)]
    mesh: Option<String>,
    /// Longest element edge, in scene units.
    #[arg(long)]
    max_edge: Option<f64>,
    /// N × N elements on every quad instead of --max-edge.
    #[arg(long)]
    elements_per_side: Option<usize>,
    /// PNG exposure in stops; automatic when left out.
    #[arg(long, allow_hyphen_values = true)]
    exposure: Option<f64>,
    /// Anti-aliasing: S × S samples per pixel.
    #[arg(long, default_value_t = 3)]
    supersampling: u32,
    /// No progress bar.
    #[arg(long, short)]
    quiet: bool,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::FAILURE
        }
    }
}

fn render(args: &RenderArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    // Outputs are checked first, so that a typo costs no solve.
    for path in [&args.output, &args.png] {
        ensure_directory_exists(path)?;
    }
    let LoadedScene {
        scene,
        options,
        source,
    } = load_scene(&args.scene)?;
    for warning in &scene.warnings {
        eprintln!("warning: {}", warning.message);
    }
    // Mesh: the scene file's settings, then the flags.
    let mesh_kind = args
        .mesh
        .as_deref()
        .or(options.mesh_kind.as_deref())
        .unwrap_or("square");
    anyhow::ensure!(
        mesh_kind == "square",
        "--mesh {mesh_kind}: only \"square\" is available"
    );
    let mut mesh_settings = SquareMeshSettings::for_scene(&scene);
    if let Some(max_edge) = args.max_edge.or(options.max_edge) {
        anyhow::ensure!(
            max_edge > 0.0 && max_edge.is_finite(),
            "--max-edge {max_edge} is not positive"
        );
        mesh_settings.max_edge = max_edge;
        mesh_settings.patch_max_edge = mesh_settings.patch_max_edge.max(max_edge);
    }
    mesh_settings.elements_per_side = args.elements_per_side.or(options.elements_per_side);
    let mesh = mesh_square(&scene, &mesh_settings);
    let visibility = Visibility::new(&scene);
    // Solve.
    let mut solver_settings = SolverSettings::default();
    if let Some(tolerance) = args.tolerance.or(options.tolerance) {
        solver_settings.tolerance = tolerance;
    }
    if let Some(kernel) = &args.form_factor {
        solver_settings.kernel = kernel.parse()?;
    }
    let mut solver = Solver::new(&scene, &mesh, &visibility, solver_settings)?;
    let solve_start = Instant::now();
    solve_with_progress(&mut solver, args.quiet);
    let solve_seconds = solve_start.elapsed().as_secs_f64();
    // Render.
    let mut camera = scene.camera_or_default();
    camera.width = args.width.unwrap_or(camera.width);
    camera.height = args.height.unwrap_or(camera.height);
    camera
        .validate()
        .map_err(anyhow::Error::msg)
        .context("camera")?;
    let triangles = mesh_triangles(&mesh, &solver.radiosity_with_ambient());
    let mut render_settings = RenderSettings::default();
    render_settings.supersampling = args.supersampling.clamp(1, 16);
    let image = rasterize(&triangles, &camera, &render_settings);
    write_exr(&image, &args.output)?;
    let exposure = args.exposure.unwrap_or_else(|| auto_exposure(&image));
    write_png(&image, &ToneMap { exposure }, &args.png)?;
    // Summary.
    let rays = solver.rays();
    println!(
        "{source}: {} surfaces, {} patches, {} elements, {} vertices",
        scene.surfaces.len(),
        mesh.patches.len(),
        mesh.elements.len(),
        mesh.vertices.len()
    );
    println!(
        "solved: {} shots, {} shadow rays in {solve_seconds:.2} s ({:.2} M rays/s), unshot {:.3} %",
        solver.shots(),
        rays,
        rays as f64 / solve_seconds.max(1e-9) / 1e6,
        100.0 * solver.unshot_fraction()
    );
    println!(
        "wrote {} and {} (exposure {exposure:+.2}) in {:.2} s total",
        args.output.display(),
        args.png.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Fails unless the directory that would hold `path` exists.
fn ensure_directory_exists(path: &std::path::Path) -> anyhow::Result<()> {
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => std::path::Path::new("."),
    };
    anyhow::ensure!(
        parent.is_dir(),
        "{}: cannot write: directory {} does not exist",
        path.display(),
        parent.display()
    );
    Ok(())
}

/// Runs the solver with a progress bar of the unshot fraction, on a log
/// scale from 100 % down to the tolerance.
fn solve_with_progress(solver: &mut Solver, quiet: bool) {
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
    solver.run(|solver| {
        let unshot = solver.unshot_fraction().max(1e-12);
        let done = (unshot.ln() / tolerance.ln()).clamp(0.0, 1.0);
        bar.set_position((1000.0 * done) as u64);
        bar.set_message(format!(
            "unshot {:.2} %, {} shots",
            100.0 * unshot,
            solver.shots()
        ));
    });
    bar.finish_and_clear();
}
