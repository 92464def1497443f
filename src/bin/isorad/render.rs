//! `isorad render`: solve a scene and write EXR and PNG images, previews
//! and exports.

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::time::Instant;

use anyhow::Context;
use clap::{Args, ValueEnum};
use isorad::{
    Camera, RenderSettings, Rgb, Scene, Solution, Solver, StopReason, ToneMap,
    calculation::{FalseColorScale, write_falsecolor_image},
    export::ExportFormat,
    export_solution,
    lighting::area_lights,
    photometry::LUMENS_PER_WATT,
    render::auto_exposure,
    solver::ReadingPlace,
    write_exr, write_png,
};

use crate::args::{Prepared, SolveArgs, ensure_directory_exists, prepare};
use crate::daylight_report::daylight_lines;
use crate::progress::{INTERRUPTED, Interrupted, phase_times, solve_with_progress};
use crate::stop::report_time_limit;
use crate::table::significant;

#[derive(Args)]
pub struct RenderArgs {
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
    /// Anti-aliasing where a pixel's samples disagree (outlines, sharp
    /// shadows): E × E samples there; at most S turns it off.
    #[arg(long, value_name = "E", default_value_t = 16,
          value_parser = clap::value_parser!(u32).range(1..=16))]
    edge_supersampling: u32,
    /// Write the images (ambient term added) every N shots while solving.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    preview_every: Option<u64>,
    /// Also export the solved mesh with baked light: .ply or .glb (repeatable).
    #[arg(long, value_name = "FILE")]
    export: Vec<PathBuf>,
    /// Also write the view in false colour with a legend (.png), as
    /// Radiance's falsecolor: luminance in cd/m², or illuminance in lx.
    #[arg(long, value_name = "FILE")]
    falsecolor: Option<PathBuf>,
    /// What the false-colour picture shows.
    #[arg(long, value_enum, default_value_t = FalseColorQuantity::Luminance)]
    falsecolor_quantity: FalseColorQuantity,
    /// The false-colour scale's top [default: the 99th percentile of the
    /// view, rounded up].
    #[arg(long, value_name = "VALUE")]
    falsecolor_max: Option<f64>,
    /// A logarithmic false-colour scale (three decades below the top).
    #[arg(long)]
    falsecolor_log: bool,
}

/// The quantity a false-colour picture shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FalseColorQuantity {
    /// Luminance of what the camera sees, cd/m² (179 lm/W × Y(L)).
    Luminance,
    /// Illuminance on the surfaces the camera sees, lx (179 lm/W × Y(H)).
    Illuminance,
}

pub fn render(args: &RenderArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    // Outputs are checked first, so that a typo costs no solve.
    check_outputs(args)?;
    ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::Relaxed))
        .context("cannot install the Ctrl-C handler")?;
    let Prepared {
        mut solver,
        phases,
        source,
        started,
    } = prepare(&args.solve)?;
    let mut camera = solver.scene().camera_or_default();
    camera.width = args.width.unwrap_or(camera.width);
    camera.height = args.height.unwrap_or(camera.height);
    camera
        .validate()
        .map_err(anyhow::Error::msg)
        .context("camera")?;
    let mut render_settings = RenderSettings::default();
    render_settings.supersampling = args.supersampling.clamp(1, 16);
    render_settings.edge_supersampling = args.edge_supersampling;
    // Intermediate and final images add the ambient term for the light not yet shot.
    let write_images = |solution: &Solution| -> anyhow::Result<f64> {
        let image = solution.render(&camera, &render_settings);
        write_exr(&image, &args.output)?;
        let exposure = args.exposure.unwrap_or_else(|| auto_exposure(&image));
        write_png(&image, &ToneMap { exposure }, &args.png)?;
        Ok(exposure)
    };
    // The camera reads the solution where it stands.
    let seen_from = [ReadingPlace::InSpace(camera.position)];
    let until = args.solve.until(started);
    let (stop, solve_seconds) = solve_with_progress(
        &mut solver,
        &until,
        args.solve.quiet,
        args.preview_every,
        |solver| write_images(&phases.solution_for(solver, &seen_from)).map(|_| ()),
    )?;
    report_time_limit(&solver, stop);
    // The images, exports and false colour read one solution: the ambient
    // term is gathered once, in the room the camera stands in unless the
    // whole mesh is exported.
    let solution = if args.export.is_empty() {
        phases.solution_for(&solver, &seen_from)
    } else {
        phases.solution_everywhere(&solver)
    };
    let exposure = write_images(&solution)?;
    // Exports (final only, not at previews) take the PNG's exposure.
    for path in &args.export {
        export_solution(&solution, &ToneMap { exposure }, path)?;
    }
    if let Some(path) = &args.falsecolor {
        write_false_colour(args, &solution, &camera, &render_settings, path)?;
    }
    print_summary(&source, &solver, solve_seconds);
    eprintln!("time: {}", phase_times(&phases.seconds(), solve_seconds));
    let mut written: Vec<String> = [&args.output, &args.png]
        .into_iter()
        .chain(&args.export)
        .chain(&args.falsecolor)
        .map(|path| path.display().to_string())
        .collect();
    let last = written.pop().unwrap_or_default();
    let outputs = format!("{} and {last}", written.join(", "));
    if stop == StopReason::Cancelled {
        return Err(Interrupted(format!(
            "interrupted: wrote the solution after {} shots (unshot {:.3} %, ambient term added) to {outputs}",
            solver.stats().shots,
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

/// The view in false colour of luminance (cd/m²) or illuminance (lx),
/// with its legend.
fn write_false_colour(
    args: &RenderArgs,
    solution: &Solution<'_>,
    camera: &Camera,
    settings: &RenderSettings,
    path: &Path,
) -> anyhow::Result<()> {
    let (image, unit, title) = match args.falsecolor_quantity {
        FalseColorQuantity::Luminance => (solution.render(camera, settings), "cd/m²", "luminance"),
        FalseColorQuantity::Illuminance => (
            solution.render_irradiance(camera, settings),
            "lx",
            "illuminance",
        ),
    };
    let values = image.photometric_values();
    let mut scale = FalseColorScale::fitted_to_quantile(&values, 0.99);
    if let Some(maximum) = args.falsecolor_max {
        scale.maximum = maximum;
    }
    scale.logarithmic = args.falsecolor_log;
    write_falsecolor_image(
        path,
        &values,
        image.width(),
        image.height(),
        &scale,
        unit,
        title,
    )?;
    Ok(())
}

fn print_summary(source: &str, solver: &Solver, solve_seconds: f64) {
    let (scene, mesh) = (solver.scene(), solver.mesh());
    let rays = solver.stats().rays;
    eprintln!(
        "{source}: {} surfaces, {} patches, {} elements, {} vertices",
        scene.surfaces.len(),
        mesh.patches.len(),
        mesh.elements.len(),
        mesh.vertices.len()
    );
    // The vertices' shots' own unshot fraction: patch shots may follow.
    let patch_shots = solver.patch_shot_summary();
    let unshot = patch_shots.map_or(solver.unshot_fraction(), |s| s.unshot_before);
    let counted = solver.convergence_fraction();
    let counted = if (unshot - counted).abs() > 1e-9 {
        format!(
            " ({:.3} % as the tolerance counts it, closed rooms' at --closed-zone-weight)",
            100.0 * counted
        )
    } else {
        String::new()
    };
    eprintln!(
        "solved: {} shots, {} shadow rays in {solve_seconds:.2} s ({:.2} M rays/s), unshot {:.3} %{counted}",
        solver.stats().shots,
        rays,
        rays as f64 / solve_seconds.max(1e-9) / 1e6,
        100.0 * unshot
    );
    if let Some(shots) = patch_shots {
        eprintln!(
            "patch shots: unshot {:.3} % after {} sweeps over the patches along {} rays ({} clusters of {} small patches shot as one)",
            100.0 * shots.unshot_after,
            shots.sweeps,
            shots.rays,
            shots.clusters,
            shots.clustered_patches
        );
    }
    let stats = solver.stats();
    let (interpolated, receptions) = (stats.interpolated_receptions, stats.receptions);
    if interpolated > 0 {
        eprintln!(
            "coarse reception: {:.1} % of the vertices reflected shots visited took them interpolated from patch samples",
            100.0 * interpolated as f64 / receptions as f64
        );
    }
    let stats = solver.stats();
    let (shafts, clear, unblocked) = (stats.shafts_tested, stats.shafts_clear, stats.known_visible);
    let recalled = solver.stats().recalled_views;
    if shafts > 0 || recalled > 0 {
        eprintln!(
            "known visibility: {clear} of {shafts} shafts clear, {recalled} vertices' views of a shooter recalled from its last shot; {unblocked} visibility samples taken without a ray ({:.1} % of all), {} rays tested against their shafts' few triangles",
            100.0 * unblocked as f64 / (unblocked + rays).max(1) as f64,
            solver.stats().listed_rays
        );
    }
    if !area_lights(scene).is_empty() || !scene.luminaires.is_empty() {
        eprintln!("{}", emitted_flux(scene));
    }
    if let Some(source) = solver.daylight() {
        for line in daylight_lines(scene, source.portals()) {
            eprintln!("{line}");
        }
    }
    if let Some(mib) = peak_memory_mib() {
        eprintln!("peak memory: {mib:.0} MiB (resident)");
    }
}

/// The luminous flux emitted, lm (the radiant power's luminance at
/// 179 lm/W): the total, and each lamp's (the first few, when there are
/// many).
fn emitted_flux(scene: &Scene) -> String {
    const LISTED: usize = 8;
    let lumens = |power: Rgb| power.luminance() * LUMENS_PER_WATT;
    let mut each: Vec<(String, f64)> = area_lights(scene)
        .iter()
        .map(|lamp| {
            let name = &scene.surface(lamp.surfaces[0]).name;
            (name.clone(), lumens(lamp.exitance * lamp.area))
        })
        .collect();
    each.extend(
        scene
            .luminaires
            .iter()
            .map(|luminaire| (luminaire.name.clone(), lumens(luminaire.power()))),
    );
    let total: f64 = each.iter().map(|(_, flux)| flux).sum();
    let mut listed: Vec<String> = each
        .iter()
        .take(LISTED)
        .map(|(name, flux)| format!("{name} {}", significant(*flux)))
        .collect();
    if each.len() > LISTED {
        listed.push(format!("{} more", each.len() - LISTED));
    }
    format!(
        "emitted: {} lm from {} lamps ({})",
        significant(total),
        each.len(),
        listed.join(", ")
    )
}

/// The process's peak resident memory (VmHWM in /proc/self/status), MiB;
/// `None` where the system does not report it.
fn peak_memory_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// Refuses, before any solving, outputs that cannot be written: a missing
/// directory, an export format no extension names, a non-finite exposure,
/// and a PNG name given to `-o` (or an EXR name to `--png`).
fn check_outputs(args: &RenderArgs) -> anyhow::Result<()> {
    for path in [&args.output, &args.png].into_iter().chain(&args.export) {
        ensure_directory_exists(path)?;
    }
    if let Some(path) = &args.falsecolor {
        ensure_directory_exists(path)?;
        let png = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        anyhow::ensure!(
            png,
            "--falsecolor {}: the picture is written as .png",
            path.display()
        );
    }
    if let Some(maximum) = args.falsecolor_max {
        anyhow::ensure!(
            maximum.is_finite() && maximum > 0.0,
            "--falsecolor-max {maximum} must be a positive number"
        );
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
    Ok(())
}
