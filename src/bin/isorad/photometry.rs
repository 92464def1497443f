//! `isorad photometry`: what isorad reads from a luminaire's photometric
//! file (IES LM-63 or EULUMDAT): its own description, the symmetry and
//! opening, the peak intensity and flux, and I(C, γ) in the main planes.

use std::io::Write;
use std::path::PathBuf;

use clap::Args;
use isorad::photometry::{FLUX_REFINEMENT, read_photometric_file};

use crate::table::{significant, write_table};

#[derive(Args)]
pub struct PhotometryArgs {
    /// An IES LM-63 file (.ies) or an EULUMDAT file (.ldt, .eul).
    file: PathBuf,
    /// γ step of the intensity table, degrees.
    #[arg(long, default_value_t = 10.0)]
    step: f64,
}

/// Prints the file's description, then I(C, γ) in candela for C 0°, 90°,
/// 180° and 270° every `--step` degrees of γ, as aligned text on stdout.
pub fn photometry(args: &PhotometryArgs) -> anyhow::Result<()> {
    anyhow::ensure!(
        args.step.is_finite() && (0.1..=90.0).contains(&args.step),
        "--step {}: give a γ step from 0.1° to 90°",
        args.step
    );
    let file = read_photometric_file(&args.file)?;
    let distribution = file.distribution();
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    writeln!(out, "{}:", args.file.display())?;
    for (field, value) in file.description() {
        writeln!(out, "  {field}: {}", value.replace('\n', " / "))?;
    }
    let opening = distribution.opening;
    writeln!(
        out,
        "  luminous opening: width {} m, length {} m, height {} m",
        significant(opening.width),
        significant(opening.length),
        significant(opening.height)
    )?;
    writeln!(
        out,
        "  {} C planes and {} γ angles after symmetry; peak {} cd; flux {} lm\n",
        distribution.c_angles().len(),
        distribution.gamma_angles().len(),
        significant(distribution.peak()),
        significant(distribution.flux(FLUX_REFINEMENT))
    )?;
    let header = ["γ (°)", "C 0° (cd)", "C 90°", "C 180°", "C 270°"];
    let steps = (180.0 / args.step).floor() as usize;
    let rows: Vec<Vec<String>> = (0..=steps)
        .map(|k| {
            let gamma = k as f64 * args.step;
            let mut row = vec![format!("{gamma:.1}")];
            row.extend(
                [0.0, 90.0, 180.0, 270.0]
                    .iter()
                    .map(|&c| significant(distribution.intensity(c, gamma))),
            );
            row
        })
        .collect();
    write_table(&mut out, &header, &rows)?;
    out.flush()?;
    Ok(())
}
