//! The numbers of an LM-63 file after its `TILT=` line, read one at a
//! time with the line each stands on: separated by blanks, tabs, commas or
//! line breaks anywhere, as LM-63 allows.
//!
//! Read lazily, so that a file's size, not its number of values, bounds
//! what reading it holds.

use std::iter::Peekable;

use super::problem::{MAX_ANGLES, ParseProblem, push_increasing};

/// A token of the file and its 1-based line.
type Token<'a> = (&'a str, usize);

/// The numbers after the `TILT=` line, each with its line.
pub(super) struct Numbers<'a> {
    tokens: Peekable<Box<dyn Iterator<Item = Token<'a>> + 'a>>,
    /// The file's last line, for errors at its end.
    last_line: usize,
}

impl<'a> Numbers<'a> {
    /// The numbers of `text` from its 0-based line `from` on.
    pub(super) fn new(text: &'a str, from: usize) -> Numbers<'a> {
        let tokens: Box<dyn Iterator<Item = Token<'a>> + 'a> = Box::new(
            text.lines()
                .enumerate()
                .skip(from)
                .flat_map(|(index, line)| {
                    line.split(|c: char| c.is_whitespace() || c == ',')
                        .filter(|t| !t.is_empty())
                        .map(move |t| (t, index + 1))
                }),
        );
        Numbers {
            tokens: tokens.peekable(),
            last_line: text.lines().count().max(1),
        }
    }

    /// The line of the next value (or the last line at the end).
    pub(super) fn line(&mut self) -> usize {
        self.tokens.peek().map_or(self.last_line, |&(_, line)| line)
    }

    /// The next value, finite, and its line; `what` names it in errors.
    pub(super) fn next_with_line(&mut self, what: &str) -> Result<(f64, usize), ParseProblem> {
        let Some((token, line)) = self.tokens.next() else {
            return Err(ParseProblem::at(
                self.last_line,
                format!("the file ends before the {what}"),
            ));
        };
        let value: f64 = token
            .parse()
            .map_err(|_| ParseProblem::at(line, format!("{what}: `{token}` is not a number")))?;
        if !value.is_finite() {
            return Err(ParseProblem::at(
                line,
                format!("{what}: {token} is not finite"),
            ));
        }
        Ok((value, line))
    }

    /// The next value.
    pub(super) fn next(&mut self, what: &str) -> Result<f64, ParseProblem> {
        self.next_with_line(what).map(|(v, _)| v)
    }

    /// The next value, which must be positive.
    pub(super) fn positive(&mut self, what: &str) -> Result<f64, ParseProblem> {
        let (value, line) = self.next_with_line(what)?;
        if value <= 0.0 {
            return Err(ParseProblem::at(
                line,
                format!("{what} {value}: must be positive"),
            ));
        }
        Ok(value)
    }

    /// The next value, a count of angles from 1 to [`MAX_ANGLES`].
    pub(super) fn count(&mut self, what: &str) -> Result<usize, ParseProblem> {
        let (value, line) = self.next_with_line(what)?;
        if value < 1.0 || value.fract() != 0.0 || value > MAX_ANGLES as f64 {
            return Err(ParseProblem::at(
                line,
                format!("{what} {value}: must be a whole number from 1 to {MAX_ANGLES}"),
            ));
        }
        Ok(value as usize)
    }

    /// `n` angles, strictly increasing, with the line of the first.
    pub(super) fn angles(
        &mut self,
        n: usize,
        what: &str,
    ) -> Result<(Vec<f64>, usize), ParseProblem> {
        let first_line = self.line();
        let mut angles = Vec::with_capacity(n);
        for _ in 0..n {
            let (angle, line) = self.next_with_line(&format!("{what} angle"))?;
            push_increasing(&mut angles, angle, line, what)?;
        }
        Ok((angles, first_line))
    }

    /// The line of the first value left unread, if any.
    pub(super) fn remaining_line(&mut self) -> Option<usize> {
        self.tokens.peek().map(|&(_, line)| line)
    }
}
