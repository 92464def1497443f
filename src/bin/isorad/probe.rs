//! `isorad probe`: irradiance and radiosity at points, with illuminance
//! (lx) and luminance (cd/m²), as CSV on stdout.

use std::io::Write;
use std::path::{Path, PathBuf};

use clap::Args;
use isorad::{
    Rgb, calculation::illuminance_lux, photometry::LUMENS_PER_WATT, scene::ProbePoint,
    scene::load_probe_points, solver::ReadingPlace,
};
use rayon::prelude::*;

use crate::args::{Prepared, ProbeModeArg, SolveArgs, prepare};
use crate::progress::solve_to_tolerance;

#[derive(Args)]
pub struct ProbeArgs {
    #[command(flatten)]
    solve: SolveArgs,
    /// CSV of points, one per line: x,y,z or x,y,z,nx,ny,nz.
    #[arg(long)]
    points: PathBuf,
    /// gather: final gather at the exact point; mesh: the rendered mesh's value.
    #[arg(long, value_enum, default_value_t = ProbeModeArg::Gather)]
    mode: ProbeModeArg,
    /// Also print the in-plane radiosity gradient of each channel.
    #[arg(long)]
    gradient: bool,
    /// Read the points in free space (a work plane, another program's
    /// calculation points): each needs its normal, x,y,z,nx,ny,nz, and
    /// gets the irradiance on a small receiver there facing it, as
    /// `isorad grid` reads a raised work plane. Columns:
    /// x,y,z,nx,ny,nz,irradiance_r,irradiance_g,irradiance_b,illuminance_lux.
    #[arg(long, conflicts_with_all = ["mode", "gradient"])]
    in_space: bool,
}

pub fn probe(args: &ProbeArgs) -> anyhow::Result<()> {
    let points = load_probe_points(&args.points)?;
    let Prepared {
        mut solver,
        phases,
        started,
        ..
    } = prepare(&args.solve)?;
    if args.in_space
        && let Some(point) = points.iter().find(|p| p.normal.is_none())
    {
        anyhow::bail!(
            "{}:{}: --in-space needs each point's normal: x,y,z,nx,ny,nz",
            args.points.display(),
            point.line
        );
    }
    let until = args.solve.until(started);
    solve_to_tolerance(&mut solver, &until, args.solve.quiet)?;
    if args.in_space {
        let places: Vec<ReadingPlace> = points
            .iter()
            .map(|p| ReadingPlace::InSpace(p.position))
            .collect();
        let solution = phases.solution_for(&solver, &places);
        return write_in_space(&solution, &points);
    }
    // The ambient term of the closed rooms the probes lie in alone (a
    // point on no surface fails below, whatever the term).
    let places: Vec<ReadingPlace> = points
        .par_iter()
        .filter_map(|point| ReadingPlace::of_probe(solver.scene(), point))
        .collect();
    let solution = phases.solution_for(&solver, &places);
    let mode = args.mode.into();
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
    header.push_str(",irradiance_se_r,irradiance_se_g,irradiance_se_b");
    header.push_str(",illuminance_lux,luminance_cd_m2");
    writeln!(out, "{header}")?;
    // Probes in parallel (each is deterministic, keyed by its point), rows in order.
    let probes: Vec<_> = points
        .par_iter()
        .map(|point| solution.probe(point, mode))
        .collect();
    for probe in probes {
        let probe = probe.map_err(|error| with_points_path(error, &args.points))?;
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
        let se = probe.standard_error;
        row.push_str(&format!(",{},{},{}", se.r, se.g, se.b));
        row.push_str(&format!(
            ",{},{}",
            illuminance_lux(probe.irradiance),
            luminance_cd_m2(probe.radiosity)
        ));
        writeln!(out, "{row}")?;
    }
    out.flush()?;
    Ok(())
}

/// Each point's irradiance in free space, facing its normal, as CSV rows.
fn write_in_space(solution: &isorad::Solution<'_>, points: &[ProbePoint]) -> anyhow::Result<()> {
    let read: Vec<Rgb> = points
        .par_iter()
        .map(|p| {
            solution
                .irradiance_in_space(p.position, p.normal.unwrap_or_default())
                .0
        })
        .collect();
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    writeln!(
        out,
        "x,y,z,nx,ny,nz,irradiance_r,irradiance_g,irradiance_b,illuminance_lux"
    )?;
    for (p, h) in points.iter().zip(read) {
        let (x, n) = (p.position, p.normal.unwrap_or_default());
        writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{}",
            x.x,
            x.y,
            x.z,
            n.x,
            n.y,
            n.z,
            h.r,
            h.g,
            h.b,
            illuminance_lux(h)
        )?;
    }
    out.flush()?;
    Ok(())
}

/// Luminance of a Lambertian surface, cd/m²: 179 lm/W × Y(B) / π.
fn luminance_cd_m2(radiosity: Rgb) -> f64 {
    radiosity.luminance() * LUMENS_PER_WATT / std::f64::consts::PI
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
