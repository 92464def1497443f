//! IES LM-63 photometric files (1986, 1991, 1995, 2002, 2019), type C.
//!
//! The layout: an optional format line (`IESNA:LM-63-2002`,
//! `IES:LM-63-2019`, `IESNA91`), keyword lines (`[LUMINAIRE] …`), a
//! `TILT=` line, then numbers separated by blanks, tabs, commas or line
//! breaks anywhere:
//!
//! ```text
//! lamps  lumens_per_lamp  candela_multiplier  n_vertical  n_horizontal
//! photometric_type  units_type  width  length  height
//! ballast_factor  future_use  input_watts
//! vertical angles (n_vertical)   horizontal angles (n_horizontal)
//! candela: n_vertical values for each horizontal angle
//! ```
//!
//! I(C, γ) = candela × candela multiplier × ballast factor (absolute
//! photometry, lumens −1, and relative alike: the tabulated candela are
//! those of the rated lamps). The horizontal angles imply the symmetry: a
//! single plane (0), 0–90, 0–180, 90–270 or 0–360. Type A and B photometry
//! and tilt data (`TILT=INCLUDE`, `TILT=<file>`) are refused with an error
//! saying so, never ignored.
//!
//! # References
//! ANSI/IES LM-63-19, "Approved Method: IES Standard File Format for the
//! Electronic Transfer of Photometric Data and Related Information" (2019),
//! and LM-63-02 (2002).

use super::distribution::{IntensityDistribution, LuminousOpening, Symmetry};
use super::ies_numbers::Numbers;
use super::problem::{MAX_CANDELA, MAX_VALUES, ParseProblem, scaled_intensity};

/// Feet per metre's inverse: LM-63 units type 1 is feet.
const FOOT: f64 = 0.3048;

/// A parsed LM-63 file: its distribution, format line and keywords.
#[derive(Clone, Debug, PartialEq)]
pub struct IesFile {
    /// The intensity distribution, candela, and the luminous opening.
    pub distribution: IntensityDistribution,
    /// The format line (`IESNA:LM-63-2002`), or `LM-63-1986` when absent.
    pub format: String,
    /// Keyword lines, `[KEY] value`, in order (`[MORE]` lines joined to the
    /// one before).
    pub keywords: Vec<(String, String)>,
    /// Lumens per lamp, −1 for absolute photometry.
    pub lumens_per_lamp: f64,
    /// Number of lamps.
    pub lamps: f64,
    /// Input watts.
    pub input_watts: f64,
}

/// Reads an LM-63 file's text (see the module docs).
///
/// # Errors
/// A [`ParseProblem`] naming the line: no `TILT=` line, tilt data, a value
/// that is not a number, too few values, counts or angles out of range or
/// not increasing, negative or non-finite candela, photometric type A or B.
pub fn parse_ies(text: &str) -> Result<IesFile, ParseProblem> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let header = Header::read(text)?;
    let mut numbers = Numbers::new(text, header.tilt_line + 1);
    let parameters = Parameters::read(&mut numbers)?;
    let scale = parameters.check(&mut numbers)?;
    let web = Web::read(&mut numbers, &parameters)?;
    let factor = parameters.candela_factor(header.tilt_line)?;
    let planes = read_candela(&mut numbers, &web, parameters.n_vertical, factor)?;
    if let Some(line) = numbers.remaining_line() {
        return Err(ParseProblem::at(
            line,
            "values after the candela table: the counts do not match the data",
        ));
    }
    let opening = LuminousOpening {
        width: parameters.width * scale,
        length: parameters.length * scale,
        height: parameters.height * scale,
    };
    Ok(IesFile {
        distribution: IntensityDistribution::from_planes(
            web.symmetry,
            &web.horizontal,
            &web.vertical,
            &planes,
            opening,
        ),
        format: header.format,
        keywords: header.keywords,
        lumens_per_lamp: parameters.lumens_per_lamp,
        lamps: parameters.lamps,
        input_watts: parameters.input_watts,
    })
}

/// The lines before the numbers: the format line, the keywords and the
/// `TILT=` line.
struct Header {
    /// The format line, or `LM-63-1986` when absent.
    format: String,
    /// Keyword lines, `[MORE]` lines joined to the one before.
    keywords: Vec<(String, String)>,
    /// The 0-based index of the `TILT=NONE` line.
    tilt_line: usize,
}

impl Header {
    /// Reads the lines up to `TILT=`; an error when there is none or it
    /// names tilt data.
    fn read(text: &str) -> Result<Header, ParseProblem> {
        let mut format = "LM-63-1986".to_owned();
        let mut keywords: Vec<(String, String)> = Vec::new();
        for (index, raw) in text.lines().enumerate() {
            let line = raw.trim();
            if index == 0 && (line.starts_with("IESNA") || line.starts_with("IES:")) {
                format = line.to_owned();
                continue;
            }
            if let Some(value) = line
                .strip_prefix("TILT")
                .and_then(|rest| rest.trim_start().strip_prefix('='))
            {
                check_tilt(value.trim(), index + 1)?;
                return Ok(Header {
                    format,
                    keywords,
                    tilt_line: index,
                });
            }
            if let Some((key, value)) = line.strip_prefix('[').and_then(|r| r.split_once(']')) {
                let (key, value) = (key.trim().to_ascii_uppercase(), value.trim().to_owned());
                match (key.as_str(), keywords.last_mut()) {
                    ("MORE", Some(last)) => {
                        last.1.push('\n');
                        last.1.push_str(&value);
                    }
                    _ => keywords.push((key, value)),
                }
            }
        }
        Err(ParseProblem::anywhere(
            "no TILT= line: not an IES LM-63 file",
        ))
    }
}

/// Accepts `TILT=NONE` (the value at 1-based `line`); refuses tilt data,
/// included or in another file, and an empty value.
fn check_tilt(value: &str, line: usize) -> Result<(), ParseProblem> {
    match value.to_ascii_uppercase().as_str() {
        "NONE" => Ok(()),
        "INCLUDE" => Err(ParseProblem::at(
            line,
            "TILT=INCLUDE: tilt factors (output against the lamp's burning angle) \
             are not supported; give the file with TILT=NONE",
        )),
        "" => Err(ParseProblem::at(line, "TILT= without a value")),
        _ => Err(ParseProblem::at(
            line,
            format!(
                "TILT={value}: tilt data in another file is not supported; \
                 give the file with TILT=NONE"
            ),
        )),
    }
}

/// The thirteen numbers after the `TILT=` line, in the file's order.
struct Parameters {
    lamps: f64,
    lumens_per_lamp: f64,
    multiplier: f64,
    n_vertical: usize,
    n_horizontal: usize,
    photometric_type: f64,
    /// The line of the photometric type.
    type_line: usize,
    units: f64,
    /// The line of the units type.
    units_line: usize,
    width: f64,
    length: f64,
    height: f64,
    ballast: f64,
    input_watts: f64,
}

impl Parameters {
    /// Reads the thirteen numbers; an error when one is missing, not a
    /// number, or (multiplier, ballast factor, counts) out of range.
    fn read(numbers: &mut Numbers) -> Result<Parameters, ParseProblem> {
        let lamps = numbers.next("number of lamps")?;
        let lumens_per_lamp = numbers.next("lumens per lamp")?;
        let multiplier = numbers.positive("candela multiplier")?;
        let n_vertical = numbers.count("number of vertical angles")?;
        let n_horizontal = numbers.count("number of horizontal angles")?;
        let (photometric_type, type_line) = numbers.next_with_line("photometric type")?;
        let (units, units_line) = numbers.next_with_line("units type")?;
        let width = numbers.next("luminous width")?;
        let length = numbers.next("luminous length")?;
        let height = numbers.next("luminous height")?;
        let ballast = numbers.positive("ballast factor")?;
        let _future_use = numbers.next("future use (ballast-lamp photometric factor)")?;
        let input_watts = numbers.next("input watts")?;
        Ok(Parameters {
            lamps,
            lumens_per_lamp,
            multiplier,
            n_vertical,
            n_horizontal,
            photometric_type,
            type_line,
            units,
            units_line,
            width,
            length,
            height,
            ballast,
            input_watts,
        })
    }

    /// Checks the photometric type (C only), the units type and the size
    /// of the candela table (the error at the next value's line); returns
    /// metres per unit of the luminous opening.
    fn check(&self, numbers: &mut Numbers) -> Result<f64, ParseProblem> {
        match self.photometric_type {
            1.0 => {}
            t if t == 2.0 || t == 3.0 => {
                let kind = if t == 2.0 { "B" } else { "A" };
                return Err(ParseProblem::at(
                    self.type_line,
                    format!(
                        "photometric type {kind} ({t}) is not supported: isorad reads type C \
                         (1), the photometry of architectural luminaires"
                    ),
                ));
            }
            t => {
                return Err(ParseProblem::at(
                    self.type_line,
                    format!("photometric type {t}: must be 1 (C), 2 (B) or 3 (A)"),
                ));
            }
        }
        let units = self.units;
        let scale = if units == 1.0 {
            FOOT
        } else if units == 2.0 {
            1.0
        } else {
            return Err(ParseProblem::at(
                self.units_line,
                format!("units type {units}: must be 1 (feet) or 2 (metres)"),
            ));
        };
        let (n_vertical, n_horizontal) = (self.n_vertical, self.n_horizontal);
        if n_vertical.saturating_mul(n_horizontal) > MAX_VALUES {
            return Err(ParseProblem::at(
                numbers.line(),
                format!("{n_vertical} × {n_horizontal} candela values: more than {MAX_VALUES}"),
            ));
        }
        Ok(scale)
    }

    /// Candela multiplier × ballast factor, what each tabulated value is
    /// multiplied by; an error (on the line after `TILT=`, 0-based
    /// `tilt_line`) when it is out of range.
    fn candela_factor(&self, tilt_line: usize) -> Result<f64, ParseProblem> {
        let (multiplier, ballast) = (self.multiplier, self.ballast);
        let factor = multiplier * ballast;
        if !(factor.is_finite() && factor <= MAX_CANDELA) {
            return Err(ParseProblem::at(
                tilt_line + 2,
                format!("candela multiplier {multiplier} × ballast factor {ballast}: out of range"),
            ));
        }
        Ok(factor)
    }
}

/// The web of angles a file tabulates: its vertical (γ) and horizontal
/// (C) angles, and the symmetry the horizontal ones imply.
struct Web {
    vertical: Vec<f64>,
    horizontal: Vec<f64>,
    symmetry: Symmetry,
}

impl Web {
    /// Reads the vertical, then the horizontal angles; an error when they
    /// do not increase or their range is not one of type C's.
    fn read(numbers: &mut Numbers, parameters: &Parameters) -> Result<Web, ParseProblem> {
        let (n_vertical, n_horizontal) = (parameters.n_vertical, parameters.n_horizontal);
        let (vertical, vertical_line) = numbers.angles(n_vertical, "vertical")?;
        let (horizontal, horizontal_line) = numbers.angles(n_horizontal, "horizontal")?;
        let (first_v, last_v) = (vertical[0], vertical[n_vertical - 1]);
        if !(first_v == 0.0 || first_v == 90.0) || !(last_v == 90.0 || last_v == 180.0) {
            return Err(ParseProblem::at(
                vertical_line,
                format!(
                    "vertical angles run from {first_v}° to {last_v}°: type C files start at 0° or \
                     90° and end at 90° or 180°"
                ),
            ));
        }
        let (first_h, last_h) = (horizontal[0], horizontal[n_horizontal - 1]);
        let symmetry = match (first_h, last_h) {
            (f, l) if f == 0.0 && l == 0.0 => Symmetry::Rotational,
            (f, l) if f == 0.0 && l == 90.0 => Symmetry::Quadrant,
            (f, l) if f == 0.0 && l == 180.0 => Symmetry::AboutC0C180,
            (f, l) if f == 90.0 && l == 270.0 => Symmetry::AboutC90C270,
            (f, l) if f == 0.0 && l == 360.0 => Symmetry::None,
            (f, l) => {
                return Err(ParseProblem::at(
                    horizontal_line,
                    format!(
                        "horizontal angles run from {f}° to {l}°: type C files give 0, 0–90, \
                         0–180, 90–270 or 0–360"
                    ),
                ));
            }
        };
        Ok(Web {
            vertical,
            horizontal,
            symmetry,
        })
    }
}

/// The candela table: `n_vertical` values for each horizontal angle of
/// `web`, each times `factor`.
fn read_candela(
    numbers: &mut Numbers,
    web: &Web,
    n_vertical: usize,
    factor: f64,
) -> Result<Vec<Vec<f64>>, ParseProblem> {
    let mut planes = Vec::with_capacity(web.horizontal.len());
    for &angle in &web.horizontal {
        let mut plane = Vec::with_capacity(n_vertical);
        for _ in 0..n_vertical {
            let (value, line) = numbers.next_with_line("candela value")?;
            let what = || format!("candela {value} at horizontal angle {angle}°");
            plane.push(scaled_intensity(value, factor, line, &what)?);
        }
        planes.push(plane);
    }
    Ok(planes)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A downlight: 0–90° in 5 vertical angles, one plane, I = 1000 cos γ
    /// cd × multiplier 2 × ballast 0.5.
    const DOWNLIGHT: &str = "IESNA:LM-63-2002\r\n[TEST] T1\r\n[LUMINAIRE] Downlight\r\n\
        [MORE] second line\r\nTILT=NONE\r\n1 -1 2.0 5 1 1 2 -0.2 0.0 0.05\r\n0.5 1.0 20\r\n\
        0 22.5 45 67.5 90\r\n0\r\n1000 923.88 707.11\r\n382.68 0\r\n";

    #[test]
    fn a_downlight_reads_with_its_keywords_and_factors() {
        let file = parse_ies(DOWNLIGHT).unwrap();
        assert_eq!(file.format, "IESNA:LM-63-2002");
        assert_eq!(file.keywords[1].0, "LUMINAIRE");
        assert_eq!(file.keywords[1].1, "Downlight\nsecond line");
        let d = &file.distribution;
        // candela × 2 × 0.5, every C.
        assert!((d.intensity(0.0, 0.0) - 1000.0).abs() < 1e-9);
        assert!((d.intensity(217.0, 45.0) - 707.11).abs() < 1e-9);
        assert_eq!(d.intensity(0.0, 95.0), 0.0);
        assert!((d.opening.width + 0.2).abs() < 1e-12);
        // Φ = 2π Σ ∫ I(γ) sin γ dγ of the interpolant, linear on each
        // interval: ∫ (a + b γ) sin γ dγ = [b sin γ − (a + b γ) cos γ].
        let table = [1000.0, 923.88, 707.11, 382.68, 0.0];
        let mut expected = 0.0;
        for k in 0..4 {
            let (g0, g1) = (
                (22.5 * k as f64).to_radians(),
                (22.5 * (k + 1) as f64).to_radians(),
            );
            let b = (table[k + 1] - table[k]) / (g1 - g0);
            let a = table[k] - b * g0;
            let primitive = |g: f64| b * g.sin() - (a + b * g) * g.cos();
            expected += 2.0 * std::f64::consts::PI * (primitive(g1) - primitive(g0));
        }
        let flux = d.flux(64);
        assert!((flux / expected - 1.0).abs() < 1e-4, "{flux} vs {expected}");
    }

    #[test]
    fn feet_are_converted_and_1986_files_need_no_format_line() {
        let text = "Some free text\nTILT=NONE\n1 1000 1 2 1 1 1 1 2 0\n1 0 10\n0 90\n0\n10 5\n";
        let file = parse_ies(text).unwrap();
        assert_eq!(file.format, "LM-63-1986");
        assert!((file.distribution.opening.length - 2.0 * FOOT).abs() < 1e-12);
    }

    #[test]
    fn bad_files_name_their_line_and_fault() {
        let cases = [
            ("[TEST] x\n1 2 3\n", None, "no TILT= line"),
            (
                "IESNA:LM-63-2002\nTILT=INCLUDE\n1\n",
                Some(2),
                "TILT=INCLUDE",
            ),
            ("TILT=lamp.tlt\n", Some(1), "another file"),
            (
                "TILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 0\n0 45\n",
                Some(4),
                "ends before",
            ),
            (
                "TILT=NONE\n1 -1 1 2 1 2 2 0 0 0\n1 1 0\n0 90\n0\n1 1\n",
                Some(2),
                "type B",
            ),
            (
                "TILT=NONE\n1 -1 1 2 1 3 2 0 0 0\n1 1 0\n0 90\n0\n1 1\n",
                Some(2),
                "type A",
            ),
            (
                "TILT=NONE\n1 -1 1 2 1 1 2 0 0 0\n1 1 0\n0 90\n0\n1 -5\n",
                Some(6),
                "negative",
            ),
            (
                "TILT=NONE\n1 -1 1 2 1 1 2 0 0 0\n1 1 0\n0 90\n0\n1 NaN\n",
                Some(6),
                "not finite",
            ),
            (
                "TILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 0\n0 50 40\n0\n1 1 1\n",
                Some(4),
                "increase",
            ),
            (
                "TILT=NONE\n1 -1 1 2 1 1 2 0 0 0\n1 1 0\n0 90\n0\n1 1 7\n",
                Some(6),
                "after the",
            ),
            (
                "TILT=NONE\n1 -1 1 2 1 1 2 0 0 0\n1 1 0\n10 90\n0\n1 1\n",
                Some(4),
                "vertical",
            ),
            (
                "TILT=NONE\n1 -1 1 2 2 1 2 0 0 0\n1 1 0\n0 90\n0 45\n1 1 1 1\n",
                Some(5),
                "horizontal",
            ),
            (
                "TILT=NONE\n1 -1 0 2 1 1 2 0 0 0\n1 1 0\n0 90\n0\n1 1\n",
                Some(2),
                "multiplier",
            ),
            (
                "TILT=NONE\n1 -1 1 2.5 1 1 2 0 0 0\n",
                Some(2),
                "whole number",
            ),
            (
                "TILT=NONE\n1 -1 1 2 1 1 7 0 0 0\n1 1 0\n0 90\n0\n1 1\n",
                Some(2),
                "units",
            ),
            ("TILT=NONE\n1 -1 1 x\n", Some(2), "not a number"),
        ];
        for (text, line, fault) in cases {
            let problem = parse_ies(text).unwrap_err();
            assert_eq!(problem.line, line, "{text:?}: {problem:?}");
            assert!(
                problem.message.contains(fault),
                "{text:?}: {}",
                problem.message
            );
        }
    }
}
