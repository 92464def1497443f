//! The `isorad` command-line program: a thin layer over the library.

use anyhow::Context;
use clap::{Args, Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use isorad::{
    Length, MeshKind, MeshSettings, ProbeMode, Progress, RenderSettings, Scene, Settings, Solver,
    StopReason, SurfaceId, ToneMap, Until,
    export::ExportFormat,
    export_solution,
    lighting::{DominanceSettings, Luminaire, ReceiverAnalysis, analyse_receivers, luminaires},
    load_scene,
    render::auto_exposure,
    scene::{LoadSettings, SceneOptions, Visibility, load_probe_points, load_scene_with},
    study::{
        CompareSettings, compare_receiver, panels_for_figure, write_json, write_loglog_plot,
        write_mesh_panels,
    },
    write_exr, write_png,
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
    /// Solve a scene and read irradiance and radiosity at points (CSV on stdout).
    Probe(ProbeArgs),
    /// List a scene's luminaires and, per receiver, its dominant luminaire
    /// and the mesher it would get.
    Info(InfoArgs),
    /// Compare contour meshes against square meshes on the receivers lit by
    /// a dominant small emitter: vertices and interpolation error.
    Compare(CompareArgs),
}

/// What to solve, and how: shared by every command.
#[derive(Args)]
struct SolveArgs {
    /// A scene file (.toml), an OBJ file, or a built-in scene name.
    #[arg(default_value = "cornell")]
    scene: String,
    /// Stop when unshot power < TOLERANCE × emitted power.
    #[arg(long)]
    tolerance: Option<f64>,
    /// Form-factor kernel: mixed (default), wallace or exact.
    #[arg(long, value_name = "KERNEL")]
    form_factor: Option<String>,
    /// Mesher: square, contour (the radial contour-level mesher on
    /// receivers lit by a dominant small emitter, square elsewhere), or
    /// adaptive (a coarser grid whose elements split while solving where the
    /// light changes).
    #[arg(long)]
    mesh: Option<String>,
    /// Adaptive mesher: split an element when its vertices' radiosities
    /// span more than this fraction of its mean.
    #[arg(long, value_name = "FRACTION")]
    refine_threshold: Option<f64>,
    /// Adaptive mesher: how many times an element may be halved.
    #[arg(long, value_name = "N")]
    refine_levels: Option<u32>,
    /// Contour mesher: D, rays from the light's maximum.
    #[arg(long)]
    directions: Option<usize>,
    /// Contour mesher: K, contour levels.
    #[arg(long)]
    levels: Option<usize>,
    /// Longest element edge, in scene units.
    #[arg(long)]
    max_edge: Option<f64>,
    /// N × N elements on every quad instead of --max-edge.
    #[arg(long)]
    elements_per_side: Option<usize>,
    /// Refuse to mesh when the mesh would have more elements than this
    /// (counted before meshing, so absurd settings fail at once).
    #[arg(long, default_value_t = MeshSettings::DEFAULT_MAX_ELEMENTS)]
    max_elements: usize,
    /// No progress bar.
    #[arg(long, short)]
    quiet: bool,
    /// Keep adjacent coplanar faces apart (by default they are merged into
    /// polygons when loading).
    #[arg(long)]
    no_merge: bool,
}

#[derive(Args)]
struct RenderArgs {
    #[command(flatten)]
    solve: SolveArgs,
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
    /// PNG exposure in stops; automatic when left out.
    #[arg(long, allow_hyphen_values = true)]
    exposure: Option<f64>,
    /// Anti-aliasing: S × S samples per pixel.
    #[arg(long, default_value_t = 3)]
    supersampling: u32,
    /// Write the images (ambient term added) every N shots while solving.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    preview_every: Option<u64>,
    /// Also export the solved mesh with baked light: .ply or .glb (repeatable).
    #[arg(long, value_name = "FILE")]
    export: Vec<PathBuf>,
}

#[derive(Args)]
struct ProbeArgs {
    #[command(flatten)]
    solve: SolveArgs,
    /// CSV of points, one per line: x,y,z or x,y,z,nx,ny,nz.
    #[arg(long)]
    points: PathBuf,
    /// gather: final gather at the exact point; mesh: the rendered mesh's value.
    #[arg(long, value_enum, default_value_t = Mode::Gather)]
    mode: Mode,
    /// Also print the in-plane radiosity gradient of each channel.
    #[arg(long)]
    gradient: bool,
}

#[derive(Args)]
struct InfoArgs {
    /// A scene file (.toml), an OBJ file, or a built-in scene name.
    #[arg(default_value = "cornell")]
    scene: String,
    /// A luminaire dominates a receiver from this share of its direct light.
    #[arg(long, default_value_t = DominanceSettings::default().min_share)]
    min_share: f64,
    /// A dominant luminaire is small under this radius / distance.
    #[arg(long, default_value_t = DominanceSettings::default().max_size_ratio)]
    max_size_ratio: f64,
}

#[derive(Clone, Copy, ValueEnum)]
enum Mode {
    Gather,
    Mesh,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render(&args),
        Command::Probe(args) => probe(&args),
        Command::Info(args) => info(&args),
        Command::Compare(args) => compare(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) if error.is::<Interrupted>() => {
            eprintln!("{error}");
            ExitCode::from(130)
        }
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::FAILURE
        }
    }
}

/// A loaded and meshed scene, ready to solve.
struct Prepared {
    solver: Solver,
    /// Where the scene came from, for messages.
    source: String,
}

/// Loads and meshes a scene: the scene file's settings, then the flags.
fn prepare(args: &SolveArgs) -> anyhow::Result<Prepared> {
    let mut load_settings = LoadSettings::default();
    load_settings.merge_coplanar = !args.no_merge;
    let loaded = load_scene_with(&args.scene, &load_settings)?;
    for warning in &loaded.scene.warnings {
        eprintln!("warning: {}", warning.message);
    }
    let settings = settings_from(args, &loaded.options)?;
    let contour = settings.mesh.kind == MeshKind::Contour;
    let solver = Solver::new(loaded.scene, settings)?;
    let analysis = solver.mesh_analysis();
    if contour {
        eprintln!(
            "contour mesher on {} of {} receivers ({} vertices placed in {} Newton iterations)",
            analysis.contour_surfaces.len(),
            analysis.receivers.len(),
            analysis.newton_solves,
            analysis.newton_iterations
        );
    }
    Ok(Prepared {
        solver,
        source: loaded.source,
    })
}

/// The library's settings: its defaults, then the scene file's, then the flags.
fn settings_from(args: &SolveArgs, options: &SceneOptions) -> anyhow::Result<Settings> {
    let mut settings = Settings::default();
    let mesh = &mut settings.mesh;
    mesh.kind = args
        .mesh
        .as_deref()
        .or(options.mesh_kind.as_deref())
        .unwrap_or("square")
        .parse()?;
    if let Some(max_edge) = args.max_edge.or(options.max_edge) {
        mesh.max_edge = Length::Absolute(max_edge);
    }
    mesh.elements_per_side = args.elements_per_side.or(options.elements_per_side);
    mesh.contour.directions = args.directions.unwrap_or(mesh.contour.directions);
    mesh.contour.levels = args.levels.unwrap_or(mesh.contour.levels);
    if let Some(threshold) = args.refine_threshold {
        mesh.refinement.threshold = threshold;
    }
    if let Some(levels) = args.refine_levels {
        mesh.refinement.max_levels = levels;
    }
    mesh.max_elements = args.max_elements;
    if let Some(tolerance) = args.tolerance.or(options.tolerance) {
        settings.solver.tolerance = tolerance;
    }
    if let Some(kernel) = &args.form_factor {
        settings.solver.kernel = kernel.parse()?;
    }
    settings.validate()?;
    Ok(settings)
}

/// Set by Ctrl-C: the solve stops between two shots and the solution so far
/// is written.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// The error `render` ends with after Ctrl-C, once the images are written.
#[derive(Debug)]
struct Interrupted(String);

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Interrupted {}

fn render(args: &RenderArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    // Outputs are checked first, so that a typo costs no solve.
    for path in [&args.output, &args.png].into_iter().chain(&args.export) {
        ensure_directory_exists(path)?;
    }
    if let Some(exposure) = args.exposure {
        anyhow::ensure!(
            exposure.is_finite(),
            "--exposure {exposure} is not a number of stops"
        );
    }
    for path in &args.export {
        ExportFormat::from_path(path)?;
    }
    // `-o` is the OpenEXR image; a PNG name there is a mistake worth a word.
    let extension = |path: &Path| {
        path.extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
    };
    anyhow::ensure!(
        extension(&args.output).as_deref() != Some("png"),
        "-o {} would be an OpenEXR image under a .png name: give the EXR path to -o \
         (e.g. -o out.exr) and the PNG path to --png (e.g. --png out.png)",
        args.output.display()
    );
    anyhow::ensure!(
        extension(&args.png).as_deref() != Some("exr"),
        "--png {} would be a PNG under an .exr name: give the PNG path to --png \
         (e.g. --png out.png) and the EXR path to -o (e.g. -o out.exr)",
        args.png.display()
    );
    ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::Relaxed))
        .context("cannot install the Ctrl-C handler")?;
    let Prepared { mut solver, source } = prepare(&args.solve)?;
    let mut camera = solver.scene().camera_or_default();
    camera.width = args.width.unwrap_or(camera.width);
    camera.height = args.height.unwrap_or(camera.height);
    camera
        .validate()
        .map_err(anyhow::Error::msg)
        .context("camera")?;
    let mut render_settings = RenderSettings::default();
    render_settings.supersampling = args.supersampling.clamp(1, 16);
    // Intermediate and final images add the ambient term for the light not yet shot.
    let write_images = |solver: &Solver| -> anyhow::Result<f64> {
        let image = solver
            .solution_with_ambient()
            .render(&camera, &render_settings);
        write_exr(&image, &args.output)?;
        let exposure = args.exposure.unwrap_or_else(|| auto_exposure(&image));
        write_png(&image, &ToneMap { exposure }, &args.png)?;
        Ok(exposure)
    };
    let until = Until::default().cancelled_by(&INTERRUPTED);
    let (stop, solve_seconds) = solve_with_progress(
        &mut solver,
        &until,
        args.solve.quiet,
        args.preview_every,
        |solver| write_images(solver).map(|_| ()),
    )?;
    let exposure = write_images(&solver)?;
    // Exports (final only, not at previews) take the PNG's exposure.
    let solution = solver.solution_with_ambient();
    for path in &args.export {
        export_solution(&solution, &ToneMap { exposure }, path)?;
    }
    print_summary(&source, &solver, solve_seconds);
    let mut written: Vec<String> = [&args.output, &args.png]
        .into_iter()
        .chain(&args.export)
        .map(|path| path.display().to_string())
        .collect();
    let last = written.pop().unwrap_or_default();
    let outputs = format!("{} and {last}", written.join(", "));
    if stop == StopReason::Cancelled {
        return Err(Interrupted(format!(
            "interrupted: wrote the solution after {} shots (unshot {:.3} %, ambient term added) to {outputs}",
            solver.shots(),
            100.0 * solver.unshot_fraction()
        ))
        .into());
    }
    eprintln!(
        "wrote {outputs} (exposure {exposure:+.2}) in {:.2} s total",
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

fn probe(args: &ProbeArgs) -> anyhow::Result<()> {
    let points = load_probe_points(&args.points)?;
    let mut solver = prepare(&args.solve)?.solver;
    let no_previews = |_: &Solver| Ok(());
    solve_with_progress(
        &mut solver,
        &Until::default(),
        args.solve.quiet,
        None,
        no_previews,
    )?;
    let solution = solver.solution_with_ambient();
    let mode = match args.mode {
        Mode::Gather => ProbeMode::Gather,
        Mode::Mesh => ProbeMode::Mesh,
    };
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    let mut header = String::from(
        "x,y,z,irradiance_r,irradiance_g,irradiance_b,radiosity_r,radiosity_g,radiosity_b",
    );
    if args.gradient {
        for channel in ["r", "g", "b"] {
            for axis in ["x", "y", "z"] {
                header.push_str(&format!(",grad_{channel}_{axis}"));
            }
        }
    }
    writeln!(out, "{header}")?;
    for point in &points {
        let probe = solution
            .probe(point, mode)
            .map_err(|error| with_points_path(error, &args.points))?;
        let p = probe.position;
        let (h, b) = (probe.irradiance, probe.radiosity);
        let mut row = format!(
            "{},{},{},{},{},{},{},{},{}",
            p.x, p.y, p.z, h.r, h.g, h.b, b.r, b.g, b.b
        );
        if args.gradient {
            for g in probe.gradient {
                row.push_str(&format!(",{},{},{}", g.x, g.y, g.z));
            }
        }
        writeln!(out, "{row}")?;
    }
    out.flush()?;
    Ok(())
}

/// Prints the scene's luminaires and the dominant-emitter analysis of each
/// receiver, as aligned text tables on stdout.
fn info(args: &InfoArgs) -> anyhow::Result<()> {
    let mut settings = DominanceSettings::default();
    settings.min_share = args.min_share;
    settings.max_size_ratio = args.max_size_ratio;
    settings.validate()?;
    let loaded = load_scene(&args.scene)?;
    let scene = &loaded.scene;
    for warning in &scene.warnings {
        eprintln!("warning: {}", warning.message);
    }
    let visibility = Visibility::new(scene);
    let lights = luminaires(scene);
    let analyses = analyse_receivers(scene, &visibility, &lights, &settings);
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    writeln!(
        out,
        "{}: {} surfaces, {} luminaire(s), {} receivers\n",
        loaded.source,
        scene.surfaces.len(),
        lights.len(),
        analyses.len()
    )?;
    let header = ["luminaire", "surfaces", "area", "radius", "exitance (W/m²)"];
    write_table(&mut out, &header, &luminaire_rows(&lights))?;
    writeln!(out)?;
    let header = [
        "receiver",
        "name",
        "area",
        "dominant",
        "share %",
        "size ratio",
        "mesher",
    ];
    write_table(&mut out, &header, &receiver_rows(scene, &analyses))?;
    out.flush()?;
    Ok(())
}

/// One row per luminaire: index, surfaces, area, radius, exitance.
fn luminaire_rows(lights: &[Luminaire]) -> Vec<Vec<String>> {
    lights
        .iter()
        .enumerate()
        .map(|(index, light)| {
            let surfaces: Vec<String> = light.surfaces.iter().map(SurfaceId::to_string).collect();
            let e = light.exitance;
            vec![
                index.to_string(),
                surfaces.join(","),
                significant(light.area),
                significant(light.radius),
                format!("{:.3} {:.3} {:.3}", e.r, e.g, e.b),
            ]
        })
        .collect()
}

/// One row per receiver: index, name, area, dominant luminaire, share,
/// size ratio, mesher.
fn receiver_rows(scene: &Scene, analyses: &[ReceiverAnalysis]) -> Vec<Vec<String>> {
    analyses
        .iter()
        .map(|analysis| {
            let surface = scene.surface(analysis.receiver);
            let ratio = if analysis.size_ratio.is_finite() {
                format!("{:.3}", analysis.size_ratio)
            } else {
                "-".to_owned()
            };
            let mesher = if analysis.qualifies {
                "contour"
            } else {
                "square"
            };
            vec![
                analysis.receiver.to_string(),
                surface.name.clone(),
                significant(surface.area()),
                analysis.dominant.map_or("-".to_owned(), |d| d.to_string()),
                format!("{:.1}", 100.0 * analysis.share),
                ratio,
                mesher.to_owned(),
            ]
        })
        .collect()
}

/// A number to six significant digits, without an exponent.
fn significant(x: f64) -> String {
    let digits = if x == 0.0 || !x.is_finite() {
        0
    } else {
        (5 - x.abs().log10().floor() as i32).clamp(0, 12) as usize
    };
    format!("{x:.digits$}")
}

/// Writes rows under a header, each column as wide as its widest cell; the
/// first column and numbers are right-aligned, names left-aligned.
fn write_table(out: &mut impl Write, header: &[&str], rows: &[Vec<String>]) -> std::io::Result<()> {
    let mut widths: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for row in rows {
        for (width, cell) in widths.iter_mut().zip(row) {
            *width = (*width).max(cell.chars().count());
        }
    }
    let numeric = |column: usize| {
        rows.iter().all(|row| {
            row.get(column)
                .is_some_and(|c| c == "-" || c.parse::<f64>().is_ok())
        })
    };
    let line = |cells: Vec<&str>| {
        let padded: Vec<String> = cells
            .iter()
            .enumerate()
            .map(|(column, cell)| {
                let pad = " ".repeat(widths[column].saturating_sub(cell.chars().count()));
                if numeric(column) {
                    format!("{pad}{cell}")
                } else {
                    format!("{cell}{pad}")
                }
            })
            .collect();
        padded.join("  ").trim_end().to_owned()
    };
    writeln!(out, "{}", line(header.to_vec()))?;
    for row in rows {
        writeln!(out, "{}", line(row.iter().map(String::as_str).collect()))?;
    }
    Ok(())
}

/// A probe error names the points file the user gave.
fn with_points_path(error: isorad::Error, path: &Path) -> anyhow::Error {
    match error {
        isorad::Error::ProbePoint { line, message, .. } => {
            anyhow::anyhow!("{}:{line}: {message}", path.display())
        }
        other => other.into(),
    }
}

fn print_summary(source: &str, solver: &Solver, solve_seconds: f64) {
    let (scene, mesh) = (solver.scene(), solver.mesh());
    let rays = solver.rays();
    eprintln!(
        "{source}: {} surfaces, {} patches, {} elements, {} vertices",
        scene.surfaces.len(),
        mesh.patches.len(),
        mesh.elements.len(),
        mesh.vertices.len()
    );
    eprintln!(
        "solved: {} shots, {} shadow rays in {solve_seconds:.2} s ({:.2} M rays/s), unshot {:.3} %",
        solver.shots(),
        rays,
        rays as f64 / solve_seconds.max(1e-9) / 1e6,
        100.0 * solver.unshot_fraction()
    );
}

/// Fails unless the directory that would hold `path` exists.
fn ensure_directory_exists(path: &Path) -> anyhow::Result<()> {
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    anyhow::ensure!(
        parent.is_dir(),
        "{}: cannot write: directory {} does not exist",
        path.display(),
        parent.display()
    );
    Ok(())
}

/// Runs the solver until `until` stops it, with a progress bar of the
/// unshot fraction on a log scale from 100 % down to the tolerance, and
/// calls `preview` every `preview_every` shots. Returns why it stopped and
/// the seconds spent solving (previews not counted).
fn solve_with_progress(
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
        let done = (unshot.ln() / tolerance.ln()).clamp(0.0, 1.0);
        bar.set_position((1000.0 * done) as u64);
        bar.set_message(format!(
            "unshot {:.2} %, {} shots",
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

#[derive(Args)]
struct CompareArgs {
    /// A scene file (.toml), an OBJ file, or a built-in scene name.
    scene: String,
    /// Only this receiver (its OBJ object name), even if it does not qualify.
    #[arg(long)]
    receiver: Option<String>,
    /// Write one JSON record per mesh.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write the meshes side by side: square 10×10 | contour 20×5 | square 30×30.
    #[arg(long)]
    image: Option<PathBuf>,
    /// Write a log–log plot of RMS error against vertices (.png or .svg).
    #[arg(long)]
    plot: Option<PathBuf>,
    /// Error grid: N × N points over the receiver (at least 200).
    #[arg(long, default_value_t = 400)]
    grid: usize,
}

fn compare(args: &CompareArgs) -> anyhow::Result<()> {
    for path in [&args.json, &args.image, &args.plot].into_iter().flatten() {
        ensure_directory_exists(path)?;
    }
    let loaded = load_scene(&args.scene)?;
    let scene = &loaded.scene;
    let visibility = Visibility::new(scene);
    let lamps = luminaires(scene);
    let analyses = analyse_receivers(scene, &visibility, &lamps, &DominanceSettings::default());
    // The receivers to compare, each with the luminaire to mesh for.
    let mut chosen: Vec<(SurfaceId, usize)> = Vec::new();
    for analysis in &analyses {
        let name = &scene.surface(analysis.receiver).name;
        let wanted = match &args.receiver {
            Some(only) => only == name,
            None => analysis.qualifies,
        };
        if let (true, Some(lamp)) = (wanted, analysis.dominant) {
            chosen.push((analysis.receiver, lamp));
        }
    }
    if chosen.is_empty() {
        anyhow::bail!(
            "{}: no receiver {}",
            loaded.source,
            match &args.receiver {
                Some(name) => format!("named `{name}` is lit by a luminaire"),
                None => "is lit by a dominant small luminaire (see `isorad info`)".into(),
            }
        );
    }
    let mut settings = CompareSettings::default();
    settings.grid = args.grid.max(200);
    let mut comparisons = Vec::new();
    for (receiver, lamp) in chosen {
        if let Some(comparison) =
            compare_receiver(scene, &visibility, receiver, &lamps[lamp], &settings)
        {
            print_comparison(&comparison);
            comparisons.push(comparison);
        }
    }
    if let Some(path) = &args.json {
        write_json(&comparisons, path)?;
    }
    for comparison in &comparisons {
        let several = comparisons.len() > 1;
        if let Some(path) = &args.image {
            write_mesh_panels(
                &per_receiver(path, &comparison.receiver, several),
                &panels_for_figure(comparison),
                480,
            )?;
        }
        if let Some(path) = &args.plot {
            let series = comparison.plot_series();
            let title = format!(
                "{}: RMS error of Gouraud interpolation",
                comparison.receiver
            );
            write_loglog_plot(
                &per_receiver(path, &comparison.receiver, several),
                &title,
                "vertices",
                "RMS relative error",
                &series,
            )?;
        }
    }
    Ok(())
}

/// `out.png` → `out_floor.png` when several receivers are written.
fn per_receiver(path: &Path, receiver: &str, several: bool) -> PathBuf {
    if !several {
        return path.to_path_buf();
    }
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let extension = path
        .extension()
        .map(|e| format!(".{}", e.to_string_lossy()))
        .unwrap_or_default();
    let safe: String = receiver
        .chars()
        .map(|c| {
            if c.is_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    path.with_file_name(format!("{stem}_{safe}{extension}"))
}

/// A table of the records, and the vertex ratio at equal error.
fn print_comparison(comparison: &isorad::study::ReceiverComparison) {
    println!("receiver {}:", comparison.receiver);
    println!(
        "  {:<8} {:>7} {:>9} {:>10} {:>12} {:>12} {:>9}",
        "mesher", "params", "vertices", "triangles", "rms_rel_err", "max_rel_err", "seconds"
    );
    for (record, mesh) in comparison.records.iter().zip(&comparison.meshes) {
        println!(
            "  {:<8} {:>7} {:>9} {:>10} {:>12.5} {:>12.5} {:>9.4}",
            record.mesher,
            mesh.params,
            record.vertices,
            record.triangles,
            record.rms_rel_error,
            record.max_rel_error,
            record.seconds
        );
    }
    // For each contour mesh, the square mesh vertices the same error needs.
    let ratios: Vec<f64> = comparison
        .records
        .iter()
        .filter(|r| r.mesher == "contour")
        .filter_map(|r| {
            comparison
                .vertices_for_error("square", r.rms_rel_error)
                .map(|v| v / r.vertices as f64)
        })
        .collect();
    if ratios.is_empty() {
        println!("  (no contour mesh falls within the square meshes' error range)");
    } else {
        let mut sorted = ratios.clone();
        sorted.sort_by(f64::total_cmp);
        println!(
            "  square meshes need {:.1}× (median; {:.1}× to {:.1}×) the contour meshes' vertices for the same RMS error",
            sorted[sorted.len() / 2],
            sorted[0],
            sorted[sorted.len() - 1]
        );
    }
}
