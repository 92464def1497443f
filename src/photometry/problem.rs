//! What both photometric readers share: the [`ParseProblem`] they report,
//! with its line, and their checks on what a file tabulates (angles that
//! increase, intensities within a luminaire's range).

/// The largest intensity a file may give, candela (a lighthouse gives
/// about 10⁷).
pub(super) const MAX_CANDELA: f64 = 1e12;

/// The most angles of either kind a file may give (every 0.05° of γ or
/// 0.1° of C; real files give at most a few hundred).
pub(super) const MAX_ANGLES: usize = 3600;

/// The most intensities a file may tabulate: a web of every 0.1° in γ and
/// 1° in C holds 650,000; real files hold at most some 65,000 (every 1°).
/// Symmetry expands a stored web at most fivefold, so a distribution stays
/// under 40 MB.
pub(super) const MAX_VALUES: usize = 1_000_000;

/// A problem in a photometric file, with its 1-based line where known.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseProblem {
    /// 1-based line.
    pub line: Option<usize>,
    /// What is wrong.
    pub message: String,
}

impl ParseProblem {
    /// A problem at 1-based `line`.
    pub(super) fn at(line: usize, message: impl Into<String>) -> ParseProblem {
        ParseProblem {
            line: Some(line),
            message: message.into(),
        }
    }

    /// A problem with the file as a whole.
    pub(super) fn anywhere(message: impl Into<String>) -> ParseProblem {
        ParseProblem {
            line: None,
            message: message.into(),
        }
    }
}

/// `value` × `scale` in candela, or an error at `line` when the value is
/// negative or the product above [`MAX_CANDELA`]; `what` names the value.
pub(super) fn scaled_intensity(
    value: f64,
    scale: f64,
    line: usize,
    what: &dyn Fn() -> String,
) -> Result<f64, ParseProblem> {
    if value < 0.0 {
        return Err(ParseProblem::at(line, format!("{}: negative", what())));
    }
    let candela = value * scale;
    if candela > MAX_CANDELA {
        return Err(ParseProblem::at(
            line,
            format!(
                "{} × {scale} = {candela:e} cd: above {MAX_CANDELA:e} cd, not a luminaire's",
                what()
            ),
        ));
    }
    Ok(candela)
}

/// Appends `angle` (read at `line`) to `angles`, or fails unless it is
/// larger than the last; `what` names the kind of angle.
pub(super) fn push_increasing(
    angles: &mut Vec<f64>,
    angle: f64,
    line: usize,
    what: &str,
) -> Result<(), ParseProblem> {
    if let Some(&before) = angles.last()
        && angle <= before
    {
        return Err(ParseProblem::at(
            line,
            format!("{what} angles must increase: {angle}° after {before}°"),
        ));
    }
    angles.push(angle);
    Ok(())
}
