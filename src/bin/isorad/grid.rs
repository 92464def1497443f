//! `isorad grid`: illuminance on a calculation grid over a named surface or
//! the work plane above it, as CSV with EN 12464-1's statistics.

use std::path::{Path, PathBuf};

use clap::Args;
use isorad::calculation::{
    CalculationGrid, DEFAULT_CLEARANCE, DEFAULT_DF_TARGET, FalseColorScale, GridQuantity,
    IlluminanceStatistics, ObstructionRule, write_falsecolor_grid, write_isolux_plot,
};

use crate::args::{Prepared, SolveArgs, ensure_directory_exists, prepare_adjusted};
use crate::progress::solve_to_tolerance;

#[derive(Args)]
pub struct GridArgs {
    #[command(flatten)]
    solve: SolveArgs,
    /// The surface (OBJ object or group name) the grid lies on.
    #[arg(long, value_name = "NAME")]
    surface: String,
    /// Height of the work plane above the surface, along its normal (0:
    /// on the surface itself; 0.8 for desks).
    #[arg(
        long,
        default_value_t = 0.0,
        value_name = "H",
        allow_hyphen_values = true
    )]
    height: f64,
    /// Largest spacing between points [default: EN 12464-1's
    /// p = 0.2 · 5^log10(d), d the longer side in metres].
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    spacing: Option<f64>,
    /// Points closer than D to another surface (a contact shadow) are
    /// left out of the statistics, as are points inside objects; 0: only
    /// those inside.
    #[arg(
        long,
        default_value_t = DEFAULT_CLEARANCE,
        value_name = "D",
        allow_hyphen_values = true
    )]
    clearance: f64,
    /// Read and count the points inside objects or near a surface too.
    #[arg(long)]
    keep_obstructed_points: bool,
    /// The CSV to write: x,y,z,illuminance_lux,status, statistics in `#`
    /// lines.
    #[arg(long, value_name = "FILE")]
    csv: PathBuf,
    /// Also draw labelled iso-lux lines over the outline, luminaires
    /// marked: .png or .svg.
    #[arg(long, value_name = "FILE")]
    isolux: Option<PathBuf>,
    /// Also draw the grid in false colour with a legend in lux (.png).
    #[arg(long, value_name = "FILE")]
    falsecolor: Option<PathBuf>,
    /// Report the daylight factor DF = 100 E / E_h, %, under the CIE
    /// standard overcast sky of the file's horizontal illuminance, whatever
    /// sky the file names (its sun left out), with its mean, median,
    /// minimum, uniformity and the share reaching --df-target. Needs a [sky].
    #[arg(long)]
    daylight_factor: bool,
    /// The daylight factor a point should reach, % (BREEAM Hea 01: 2).
    #[arg(long, default_value_t = DEFAULT_DF_TARGET, value_name = "PERCENT")]
    df_target: f64,
}

pub fn grid(args: &GridArgs) -> anyhow::Result<()> {
    check_outputs(args)?;
    anyhow::ensure!(
        args.df_target.is_finite() && args.df_target >= 0.0,
        "--df-target {}: must be a percentage of at least 0",
        args.df_target
    );
    let Prepared {
        mut solver,
        phases,
        started,
        ..
    } = prepare_adjusted(&args.solve, |scene| {
        daylight_factor_sky(scene, args.daylight_factor)
    })?;
    // The grid and its points' obstructions are found before solving, so
    // that a wrong name costs no solve.
    let rule = ObstructionRule {
        clearance: args.clearance,
        keep_obstructed: args.keep_obstructed_points,
    };
    let (grid, selection) =
        CalculationGrid::on_surface(solver.scene(), &args.surface, args.height, args.spacing)
            .and_then(|grid| {
                let selection = grid.select(solver.scene(), solver.visibility(), &rule)?;
                Ok((grid, selection))
            })
            .map_err(|error| match error {
                // The library names the field; the user gave a flag.
                isorad::Error::InvalidSetting { name, message } => {
                    anyhow::anyhow!("--{name}: {message}")
                }
                other => other.into(),
            })?;
    let inside = grid.points.iter().flatten().count();
    let obstructed = selection.obstructions.iter().flatten().count();
    anyhow::ensure!(
        inside == 0 || obstructed < inside || args.keep_obstructed_points,
        "all {inside} grid points on `{}` lie inside objects or within \
         --clearance {} of another surface; --keep-obstructed-points counts them",
        args.surface,
        args.clearance
    );
    let until = args.solve.until(started);
    solve_to_tolerance(&mut solver, &until, args.solve.quiet)?;
    // The ambient term of the closed rooms the grid lies in alone.
    let places = grid.reading_places(solver.scene(), &selection);
    let solution = phases.solution_for(&solver, &places);
    let lux = grid.illuminance_of(&solution, &selection);
    let daylight = solver.scene().daylight.as_ref();
    let (values, quantity) = match daylight.filter(|_| args.daylight_factor) {
        Some(daylight) => {
            let sky_illuminance = daylight.sky_horizontal_illuminance();
            let df: Vec<f64> = lux.iter().map(|e| 100.0 * e / sky_illuminance).collect();
            let target = args.df_target;
            (
                df,
                GridQuantity::DaylightFactor {
                    sky_illuminance,
                    target,
                },
            )
        }
        None => (
            lux,
            GridQuantity::Illuminance {
                daylight: daylight.is_some(),
            },
        ),
    };
    grid.write_csv_as(&args.csv, &values, &selection, quantity)?;
    for line in grid.header_lines_as(&values, &selection, quantity) {
        println!("{line}");
    }
    if IlluminanceStatistics::of(&values).is_none() {
        anyhow::bail!(
            "no grid point lies inside `{}`: try a smaller --spacing",
            args.surface
        );
    }
    let marks = grid.luminaire_marks(solution.scene);
    let title = match quantity {
        GridQuantity::DaylightFactor { .. } => grid.daylight_factor_title(&values),
        GridQuantity::Illuminance { .. } => grid.title(&values),
    };
    let mut picture = grid.picture(&values, &marks, &title);
    picture.unit = quantity.unit();
    let mut written = vec![args.csv.display().to_string()];
    if let Some(path) = &args.isolux {
        write_isolux_plot(path, &picture, &[])?;
        written.push(path.display().to_string());
    }
    if let Some(path) = &args.falsecolor {
        write_falsecolor_grid(path, &picture, &FalseColorScale::fitted(&values))?;
        written.push(path.display().to_string());
    }
    eprintln!("wrote {}", written.join(", "));
    Ok(())
}

/// Under --daylight-factor, the scene's sky made the CIE standard overcast
/// sky of the same horizontal illuminance, without the sun; an error for a
/// scene without daylight.
fn daylight_factor_sky(scene: &mut isorad::Scene, daylight_factor: bool) -> anyhow::Result<()> {
    if !daylight_factor {
        return Ok(());
    }
    let Some(daylight) = &scene.daylight else {
        anyhow::bail!(
            "--daylight-factor needs daylight: give the scene file a [sky] table (model = \"cie_overcast\")"
        );
    };
    scene.daylight = Some(daylight.overcast());
    Ok(())
}

/// Refuses, before any solving, outputs that cannot be written: a missing
/// directory, or a picture format the writers do not make.
fn check_outputs(args: &GridArgs) -> anyhow::Result<()> {
    let extension = |path: &Path| {
        path.extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default()
    };
    ensure_directory_exists(&args.csv)?;
    if let Some(path) = &args.isolux {
        ensure_directory_exists(path)?;
        anyhow::ensure!(
            matches!(extension(path).as_str(), "png" | "svg"),
            "--isolux {}: the plot is written as .png or .svg",
            path.display()
        );
    }
    if let Some(path) = &args.falsecolor {
        ensure_directory_exists(path)?;
        anyhow::ensure!(
            extension(path) == "png",
            "--falsecolor {}: the picture is written as .png",
            path.display()
        );
    }
    Ok(())
}
