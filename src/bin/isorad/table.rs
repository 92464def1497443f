//! Aligned text tables on stdout.

use std::io::Write;

/// A number to six significant digits, without an exponent.
pub fn significant(x: f64) -> String {
    let digits = if x == 0.0 || !x.is_finite() {
        0
    } else {
        (5 - x.abs().log10().floor() as i32).clamp(0, 12) as usize
    };
    format!("{x:.digits$}")
}

/// Writes rows under a header, each column as wide as its widest cell; the
/// first column and numbers are right-aligned, names left-aligned.
pub fn write_table(
    out: &mut impl Write,
    header: &[&str],
    rows: &[Vec<String>],
) -> std::io::Result<()> {
    let mut widths: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for row in rows {
        for (width, cell) in widths.iter_mut().zip(row) {
            *width = (*width).max(cell.chars().count());
        }
    }
    // Whether each column holds numbers only, decided once per column (a
    // table of thousands of receivers would otherwise parse every column
    // again for each row).
    let numeric: Vec<bool> = (0..widths.len())
        .map(|column| {
            rows.iter().all(|row| {
                row.get(column)
                    .is_some_and(|c| c == "-" || c.parse::<f64>().is_ok())
            })
        })
        .collect();
    let line = |cells: Vec<&str>| {
        let padded: Vec<String> = cells
            .iter()
            .enumerate()
            .map(|(column, cell)| {
                let pad = " ".repeat(widths[column].saturating_sub(cell.chars().count()));
                if numeric[column] {
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
