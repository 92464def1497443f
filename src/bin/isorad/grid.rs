//! `isorad grid`: illuminance on a calculation grid over a named surface or
//! the work plane above it, as CSV with EN 12464-1's statistics.

use std::path::PathBuf;

use clap::Args;
use isorad::{
    Solver, Until,
    calculation::{CalculationGrid, IlluminanceStatistics},
};

use crate::args::{SolveArgs, ensure_directory_exists, prepare};
use crate::progress::solve_with_progress;

#[derive(Args)]
pub struct GridArgs {
    #[command(flatten)]
    solve: SolveArgs,
    /// The surface (OBJ object or group name) the grid lies on.
    #[arg(long, value_name = "NAME")]
    surface: String,
    /// Height of the work plane above the surface, along its normal (0:
    /// on the surface itself; 0.8 for desks).
    #[arg(long, default_value_t = 0.0, value_name = "H")]
    height: f64,
    /// Largest spacing between points [default: EN 12464-1's
    /// p = 0.2 · 5^log10(d), d the longer side in metres].
    #[arg(long, value_name = "S")]
    spacing: Option<f64>,
    /// The CSV to write: x,y,z,illuminance_lux, statistics in `#` lines.
    #[arg(long, value_name = "FILE")]
    csv: PathBuf,
}

pub fn grid(args: &GridArgs) -> anyhow::Result<()> {
    ensure_directory_exists(&args.csv)?;
    let mut solver = prepare(&args.solve)?.solver;
    // The grid is checked before solving, so that a wrong name costs no solve.
    let grid =
        CalculationGrid::on_surface(solver.scene(), &args.surface, args.height, args.spacing)?;
    let no_previews = |_: &Solver| Ok(());
    solve_with_progress(
        &mut solver,
        &Until::default(),
        args.solve.quiet,
        None,
        no_previews,
    )?;
    let solution = solver.solution_with_ambient();
    let lux = grid.illuminance(&solution);
    grid.write_csv(&args.csv, &lux)?;
    for line in grid.header_lines(&lux) {
        println!("{line}");
    }
    if IlluminanceStatistics::of(&lux).is_none() {
        anyhow::bail!(
            "no grid point lies inside `{}`: try a smaller --spacing",
            args.surface
        );
    }
    eprintln!("wrote {}", args.csv.display());
    Ok(())
}
