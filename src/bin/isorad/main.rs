//! The `isorad` command-line program: a thin layer over the library. This
//! file parses the command line, dispatches to one file per command and maps
//! errors to exit codes; `args.rs` holds the flags shared by commands.

mod args;
mod compare;
mod daylight_report;
mod grid;
mod info;
mod photometry;
mod probe;
mod progress;
mod progress_lines;
mod render;
mod stop;
mod table;
#[cfg(feature = "view")]
mod view;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use compare::{CompareArgs, compare};
use grid::{GridArgs, grid};
use info::{InfoArgs, info};
use photometry::{PhotometryArgs, photometry};
use probe::{ProbeArgs, probe};
use progress::Interrupted;
use render::{RenderArgs, render};
#[cfg(feature = "view")]
use view::{ViewArgs, view};

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
    /// Read a luminaire's photometric file (IES LM-63 or EULUMDAT): its
    /// description, symmetry, peak intensity, flux, and I(C, γ).
    Photometry(PhotometryArgs),
    /// Solve a scene and compute illuminance (lx) on a calculation grid over
    /// a surface or a work plane: CSV with Emin, Eavg, Emax and U0.
    Grid(GridArgs),
    /// Solve a scene and show it converge in a web browser: serves a page
    /// on 127.0.0.1 to orbit and walk through the light, read lux where you
    /// click, and export it.
    #[cfg(feature = "view")]
    View(ViewArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render(&args),
        Command::Probe(args) => probe(&args),
        Command::Info(args) => info(&args),
        Command::Compare(args) => compare(&args),
        Command::Photometry(args) => photometry(&args),
        Command::Grid(args) => grid(&args),
        #[cfg(feature = "view")]
        Command::View(args) => view(args),
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
