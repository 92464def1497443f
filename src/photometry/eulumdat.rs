//! EULUMDAT photometric files (`.ldt`, `.eul`).
//!
//! A line-based format: 26 header lines (company, type Ityp, symmetry
//! Isym, the number Mc of C planes, the number Ng of γ angles, names,
//! luminaire and luminous-area dimensions in mm, the downward flux
//! fraction, light output ratio, the conversion factor for intensities,
//! the number n of lamp sets), six fields of n lines each (the sets'
//! numbers of lamps, types, total fluxes in lm, colour temperatures,
//! colour rendering, watts), ten
//! direct ratios, the Mc C angles, the Ng γ angles, and the intensities in
//! cd/klm, Ng per stored plane. Isym says which planes are stored:
//!
//! | Isym | planes stored | symmetry |
//! |---|---|---|
//! | 0 | all Mc | none |
//! | 1 | one | about the vertical axis |
//! | 2 | C0 … C180 (Mc/2 + 1) | about the C0–C180 plane |
//! | 3 | C270 … C90 through C0 (Mc/2 + 1) | about the C90–C270 plane |
//! | 4 | C0 … C90 (Mc/4 + 1) | about both |
//!
//! I(C, γ) = value × Φ_lamps / 1000 × conversion factor, Φ_lamps the first
//! lamp set's total flux (further sets are alternative equipment).
//!
//! # References
//! A. Stockmar, "EULUMDAT/2 — Extended Version of a Well Established
//! Luminaire Data Format", CIBSE National Lighting Conference 1998; the
//! format's description by LIGHTTOOLS/Relux (1990).

use super::distribution::{IntensityDistribution, LuminousOpening, Symmetry};
use super::problem::{
    MAX_ANGLES, MAX_CANDELA, MAX_VALUES, ParseProblem, push_increasing, scaled_intensity,
};

/// The most lamp sets a file may give (EULUMDAT allows 20).
const MAX_LAMP_SETS: usize = 1000;
/// Millimetres per metre.
const MM: f64 = 1e-3;

/// A parsed EULUMDAT file: its distribution and what a designer reads.
#[derive(Clone, Debug, PartialEq)]
pub struct EulumdatFile {
    /// The intensity distribution, candela, and the luminous opening.
    pub distribution: IntensityDistribution,
    /// Company identification (line 1).
    pub company: String,
    /// Luminaire name (line 9).
    pub luminaire: String,
    /// Total flux of the first lamp set, lm: what the intensities in cd/klm
    /// are relative to.
    pub lamp_flux: f64,
    /// Light output ratio of the luminaire, % (line 23).
    pub light_output_ratio: f64,
}

/// Reads an EULUMDAT file's text (see the module docs).
///
/// # Errors
/// A [`ParseProblem`] naming the line: too few lines, a field that is not
/// a number, Ityp or Isym out of range, Mc not divisible as Isym needs,
/// angles not increasing or out of range, negative or non-finite
/// intensities, no lamp flux.
pub fn parse_eulumdat(text: &str) -> Result<EulumdatFile, ParseProblem> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = Lines::new(text);
    let header = Header::read(&mut lines)?;
    let (mc, ng, isym) = (header.mc, header.ng, header.isym);
    let lamp_flux = lamp_flux(&mut lines, header.sets)?;
    // Ten direct ratios follow the lamp sets, then the angles.
    let c_start = 27 + 6 * header.sets + 10;
    let c_angles = lines.angles(c_start, mc, "C", 0.0, 360.0)?;
    let g_start = c_start + mc;
    let g_angles = lines.angles(g_start, ng, "γ", 0.0, 180.0)?;
    let stored = StoredPlanes::of(isym, mc)?;
    check_stored_angles(isym, mc, &c_angles, c_start)?;
    let conversion = header.conversion;
    let scale = lamp_flux / 1000.0 * conversion;
    if !(scale.is_finite() && scale <= MAX_CANDELA) {
        return Err(ParseProblem::at(
            24,
            format!("lamp flux {lamp_flux} lm × conversion factor {conversion}: out of range"),
        ));
    }
    let table = IntensityTable {
        start: g_start + ng,
        planes: stored.indices.len(),
        ng,
    };
    let mut planes = table.read(&mut lines, scale)?;
    for (plane, &index) in planes.iter_mut().zip(&stored.indices) {
        plane.0 = if isym == 1 { 0.0 } else { c_angles[index] };
    }
    if stored.symmetry == Symmetry::AboutC90C270 {
        // Stored C270 … C90; their mirror images across the C90–C270 plane,
        // C ↦ 180° − C, are the same planes on the C90 … C270 side.
        for plane in &mut planes {
            plane.0 = (180.0 - plane.0).rem_euclid(360.0);
        }
        planes.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    let angles: Vec<f64> = planes.iter().map(|p| p.0).collect();
    let values: Vec<Vec<f64>> = planes.into_iter().map(|p| p.1).collect();
    Ok(EulumdatFile {
        distribution: IntensityDistribution::from_planes(
            stored.symmetry,
            &angles,
            &g_angles,
            &values,
            header.opening(),
        ),
        company: header.company,
        luminaire: header.luminaire,
        lamp_flux,
        light_output_ratio: header.light_output_ratio,
    })
}

/// Where the intensities stand: Ng values, one a line, for each stored
/// plane, from line `start`; the file ends after them.
struct IntensityTable {
    /// The line of the first value.
    start: usize,
    /// The number of stored planes.
    planes: usize,
    /// Values per plane, Ng.
    ng: usize,
}

impl IntensityTable {
    /// The planes' intensities in cd/klm × `scale` (their C angles left 0
    /// for the caller); an error for a bad value, a table larger than
    /// [`MAX_VALUES`], or anything but blank lines after it: the counts
    /// must match the data, as LM-63's reader asks.
    fn read(&self, lines: &mut Lines, scale: f64) -> Result<Vec<(f64, Vec<f64>)>, ParseProblem> {
        let (planes, ng) = (self.planes, self.ng);
        if planes * ng > MAX_VALUES {
            return Err(ParseProblem::at(
                4,
                format!("{planes} stored planes × Ng {ng} intensities: more than {MAX_VALUES}"),
            ));
        }
        let mut table = Vec::with_capacity(planes);
        let mut line = self.start;
        for _ in 0..planes {
            let mut values = Vec::with_capacity(ng);
            for _ in 0..ng {
                let value = lines.number(line, "luminous intensity")?;
                let what = || format!("intensity {value} cd/klm");
                values.push(scaled_intensity(value, scale, line, &what)?);
                line += 1;
            }
            table.push((0.0, values));
        }
        if let Some((extra, text)) = lines.next_non_blank() {
            return Err(ParseProblem::at(
                extra,
                format!(
                    "`{text}` after the intensity table, which ends at line {}: \
                     {planes} stored plane(s) × Ng {ng} values; the counts do not match the data",
                    line - 1
                ),
            ));
        }
        Ok(table)
    }
}

/// The 26 header lines' fields that isorad uses.
struct Header {
    /// Company identification (line 1).
    company: String,
    /// The symmetry indicator Isym (line 3).
    isym: usize,
    /// The number of C planes Mc (line 4).
    mc: usize,
    /// The number of γ angles Ng (line 6).
    ng: usize,
    /// Luminaire name (line 9).
    luminaire: String,
    /// The luminous area's length or diameter, width and height, mm
    /// (lines 16–18).
    area_length: f64,
    area_width: f64,
    area_height: f64,
    /// Light output ratio, % (line 23).
    light_output_ratio: f64,
    /// Conversion factor for intensities (line 24), positive.
    conversion: f64,
    /// The number of lamp sets (line 26).
    sets: usize,
}

impl Header {
    /// Reads the header; an error when a field is missing, not a number or
    /// out of range.
    fn read(lines: &mut Lines) -> Result<Header, ParseProblem> {
        let company = lines.text(1)?.to_owned();
        let _ityp = lines.integer(2, "type indicator Ityp", 0, 3)?;
        let isym = lines.integer(3, "symmetry indicator Isym", 0, 4)?;
        let mc = lines.integer(4, "number of C planes Mc", 1, MAX_ANGLES)?;
        let ng = lines.integer(6, "number of intensities per C plane Ng", 1, MAX_ANGLES)?;
        let luminaire = lines.text(9)?.to_owned();
        let area_length = lines.number(16, "length or diameter of the luminous area")?;
        let area_width = lines.number(17, "width of the luminous area")?;
        let area_height = lines.number(18, "height of the luminous area")?;
        let light_output_ratio = lines.number(23, "light output ratio")?;
        let conversion = lines.number(24, "conversion factor for luminous intensities")?;
        if conversion <= 0.0 {
            return Err(ParseProblem::at(
                24,
                format!("conversion factor {conversion}: must be positive"),
            ));
        }
        let sets = lines.integer(26, "number of lamp sets", 1, MAX_LAMP_SETS)?;
        Ok(Header {
            company,
            isym,
            mc,
            ng,
            luminaire,
            area_length,
            area_width,
            area_height,
            light_output_ratio,
            conversion,
            sets,
        })
    }

    /// The luminous opening, metres. EULUMDAT gives a circular area as its
    /// diameter with zero width; the opening says circular as LM-63 does,
    /// by a negative width.
    fn opening(&self) -> LuminousOpening {
        let (area_length, area_width) = (self.area_length, self.area_width);
        let circular = area_width == 0.0 && area_length > 0.0;
        LuminousOpening {
            width: if circular { -area_length } else { area_width } * MM,
            length: if circular { 0.0 } else { area_length } * MM,
            height: self.area_height * MM,
        }
    }
}

/// The total flux of the `sets` lamp sets, lm (the third of each set's six
/// lines); an error when one is negative or the total is 0.
fn lamp_flux(lines: &mut Lines, sets: usize) -> Result<f64, ParseProblem> {
    let mut lamp_flux = 0.0;
    for set in 0..sets {
        let line = 27 + 6 * set + 2;
        let flux = lines.number(line, "total luminous flux of the lamps")?;
        if flux < 0.0 {
            return Err(ParseProblem::at(
                line,
                format!("lamp flux {flux}: negative"),
            ));
        }
        lamp_flux += flux;
    }
    if lamp_flux <= 0.0 {
        return Err(ParseProblem::at(
            27 + 2,
            "the lamps' total flux is 0: intensities in cd/klm cannot be scaled",
        ));
    }
    Ok(lamp_flux)
}

/// The C planes a file stores, as Isym says (see the module docs).
struct StoredPlanes {
    /// Indices of the stored planes into the Mc C angles, in the file's
    /// order.
    indices: Vec<usize>,
    /// The symmetry that gives the other planes.
    symmetry: Symmetry,
}

impl StoredPlanes {
    /// The planes Isym `isym` stores of `mc`; an error (on line 4) when Mc
    /// does not divide as Isym needs.
    fn of(isym: usize, mc: usize) -> Result<StoredPlanes, ParseProblem> {
        let (indices, symmetry) = match isym {
            0 => ((0..mc).collect::<Vec<_>>(), Symmetry::None),
            1 => (vec![0], Symmetry::Rotational),
            2 | 3 if !mc.is_multiple_of(2) => {
                return Err(ParseProblem::at(
                    4,
                    format!("Mc {mc} is odd: Isym {isym} stores half of the planes"),
                ));
            }
            2 => ((0..=mc / 2).collect(), Symmetry::AboutC0C180),
            3 => (
                (0..=mc / 2).map(|k| (3 * mc / 4 + k) % mc).collect(),
                Symmetry::AboutC90C270,
            ),
            _ if !mc.is_multiple_of(4) => {
                return Err(ParseProblem::at(
                    4,
                    format!(
                        "Mc {mc} is not a multiple of 4: Isym 4 stores a quarter of the planes"
                    ),
                ));
            }
            _ => ((0..=mc / 4).collect(), Symmetry::Quadrant),
        };
        Ok(StoredPlanes { indices, symmetry })
    }
}

/// Checks that the planes at the ends of the stored range lie at the
/// angles Isym `isym` names; `c_angles` were read from line `c_start` on.
fn check_stored_angles(
    isym: usize,
    mc: usize,
    c_angles: &[f64],
    c_start: usize,
) -> Result<(), ParseProblem> {
    let check_plane = |index: usize, angle: f64| {
        if (c_angles[index] - angle).abs() > 1e-6 {
            return Err(ParseProblem::at(
                c_start + index,
                format!(
                    "Isym {isym} stores planes up to C{angle}, but this plane is at C{}",
                    c_angles[index]
                ),
            ));
        }
        Ok(())
    };
    match isym {
        2 => {
            check_plane(0, 0.0)?;
            check_plane(mc / 2, 180.0)?;
        }
        3 => {
            check_plane(0, 0.0)?;
            check_plane(3 * mc / 4, 270.0)?;
            check_plane(mc / 4, 90.0)?;
        }
        4 => {
            check_plane(0, 0.0)?;
            check_plane(mc / 4, 90.0)?;
        }
        _ => {}
    }
    Ok(())
}

/// The file's lines, addressed 1-based and read forwards only: every field
/// lies after the one read before it, so reading holds one line at a time.
struct Lines<'a> {
    rest: std::str::Lines<'a>,
    /// How many lines have been taken from `rest`; the last is `current`.
    taken: usize,
    current: &'a str,
}

impl<'a> Lines<'a> {
    fn new(text: &'a str) -> Lines<'a> {
        Lines {
            rest: text.lines(),
            taken: 0,
            current: "",
        }
    }

    /// Line `line`, trimmed: the one read last or one after it.
    fn text(&mut self, line: usize) -> Result<&'a str, ParseProblem> {
        if line < self.taken.max(1) {
            return Err(ParseProblem::at(
                line,
                "isorad's EULUMDAT reader read this line out of order (a bug)",
            ));
        }
        while self.taken < line {
            let Some(next) = self.rest.next() else {
                return Err(ParseProblem::at(
                    self.taken.max(1),
                    format!("the file ends before line {line}: not a whole EULUMDAT file"),
                ));
            };
            self.taken += 1;
            self.current = next;
        }
        Ok(self.current.trim())
    }

    /// The first line after those read that is not blank, with its number,
    /// shortened for a message.
    fn next_non_blank(&mut self) -> Option<(usize, String)> {
        for next in self.rest.by_ref() {
            self.taken += 1;
            let text = next.trim();
            if !text.is_empty() {
                let short: String = text.chars().take(40).collect();
                let more = if short.len() < text.len() { "…" } else { "" };
                return Some((self.taken, format!("{short}{more}")));
            }
        }
        None
    }

    fn number(&mut self, line: usize, what: &str) -> Result<f64, ParseProblem> {
        let text = self.text(line)?;
        // Some writers use a decimal comma.
        let value: f64 = text
            .replace(',', ".")
            .parse()
            .map_err(|_| ParseProblem::at(line, format!("{what}: `{text}` is not a number")))?;
        if !value.is_finite() {
            return Err(ParseProblem::at(
                line,
                format!("{what}: {text} is not finite"),
            ));
        }
        Ok(value)
    }

    fn integer(
        &mut self,
        line: usize,
        what: &str,
        min: usize,
        max: usize,
    ) -> Result<usize, ParseProblem> {
        let value = self.number(line, what)?;
        if value.fract() != 0.0 || value < min as f64 || value > max as f64 {
            return Err(ParseProblem::at(
                line,
                format!("{what} {value}: must be a whole number from {min} to {max}"),
            ));
        }
        Ok(value as usize)
    }

    /// `n` angles from line `start`, strictly increasing within [lo, hi].
    fn angles(
        &mut self,
        start: usize,
        n: usize,
        what: &str,
        lo: f64,
        hi: f64,
    ) -> Result<Vec<f64>, ParseProblem> {
        let mut angles: Vec<f64> = Vec::with_capacity(n);
        for k in 0..n {
            let line = start + k;
            let angle = self.number(line, &format!("{what} angle"))?;
            if !(lo..=hi).contains(&angle) {
                return Err(ParseProblem::at(
                    line,
                    format!("{what} angle {angle}°: outside {lo}°–{hi}°"),
                ));
            }
            push_increasing(&mut angles, angle, line, what)?;
        }
        Ok(angles)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An EULUMDAT file: Isym `isym`, Mc planes 0, 90, 180, 270 (every
    /// 90°), γ 0, 90, 180, intensity (cd/klm) given per stored plane.
    fn ldt(isym: usize, planes: &[[f64; 3]]) -> String {
        let mut lines: Vec<String> = vec![
            "isorad test".into(),
            "1".into(),
            isym.to_string(),
            "4".into(),
            "90".into(),
            "3".into(),
            "90".into(),
            "report".into(),
            "Test luminaire".into(),
            "T-1".into(),
            "test.ldt".into(),
            "date/user".into(),
            "600".into(),
            "600".into(),
            "80".into(),
            "500".into(),
            "400".into(),
            "0".into(),
            "0".into(),
            "0".into(),
            "0".into(),
            "100".into(),
            "85".into(),
            "1.0".into(),
            "0".into(),
            "1".into(),
            "2".into(),
            "LED".into(),
            "2000".into(),
            "4000".into(),
            "1B".into(),
            "30".into(),
        ];
        lines.extend((0..10).map(|_| "0.5".to_owned()));
        lines.extend(["0", "90", "180", "270"].map(String::from));
        lines.extend(["0", "90", "180"].map(String::from));
        for plane in planes {
            lines.extend(plane.iter().map(|v| v.to_string()));
        }
        lines.join("\r\n")
    }

    #[test]
    fn intensities_scale_by_the_lamp_flux_and_follow_each_symmetry() {
        // 2000 lm: 100 cd/klm is 200 cd.
        let one = parse_eulumdat(&ldt(1, &[[100.0, 50.0, 0.0]])).unwrap();
        assert_eq!(one.luminaire, "Test luminaire");
        assert!((one.distribution.intensity(123.0, 0.0) - 200.0).abs() < 1e-9);
        assert!((one.distribution.intensity(123.0, 45.0) - 150.0).abs() < 1e-9);
        assert!((one.distribution.opening.length - 0.5).abs() < 1e-12);
        // Isym 2: C0, C90, C180 stored; C270 mirrors C90.
        let two = parse_eulumdat(&ldt(2, &[[1.0; 3], [2.0; 3], [3.0; 3]])).unwrap();
        assert!((two.distribution.intensity(270.0, 10.0) - 4.0).abs() < 1e-9);
        // Isym 3: C270, C0, C90 stored (in that order); C180 mirrors C0.
        let three = parse_eulumdat(&ldt(3, &[[7.0; 3], [1.0; 3], [2.0; 3]])).unwrap();
        let d = &three.distribution;
        assert!((d.intensity(270.0, 10.0) - 14.0).abs() < 1e-9);
        assert!((d.intensity(0.0, 10.0) - 2.0).abs() < 1e-9);
        assert!((d.intensity(90.0, 10.0) - 4.0).abs() < 1e-9);
        assert!((d.intensity(180.0, 10.0) - 2.0).abs() < 1e-9);
        // Isym 4: C0 and C90 stored; C180 mirrors C0, C270 C90.
        let four = parse_eulumdat(&ldt(4, &[[1.0; 3], [2.0; 3]])).unwrap();
        assert!((four.distribution.intensity(180.0, 10.0) - 2.0).abs() < 1e-9);
        assert!((four.distribution.intensity(270.0, 10.0) - 4.0).abs() < 1e-9);
        // Isym 0: all four.
        let zero = parse_eulumdat(&ldt(0, &[[1.0; 3], [2.0; 3], [3.0; 3], [4.0; 3]])).unwrap();
        assert!((zero.distribution.intensity(315.0, 10.0) - 5.0).abs() < 1e-9);
    }

    #[test]
    fn bad_files_name_their_line_and_fault() {
        let good = ldt(1, &[[100.0, 50.0, 0.0]]);
        let with = |line: usize, value: &str| {
            let mut lines: Vec<&str> = good.lines().collect();
            lines[line - 1] = value;
            lines.join("\n")
        };
        let truncated: String = good.lines().take(30).collect::<Vec<_>>().join("\n");
        let cases = [
            (truncated, 30, "ends before"),
            (with(3, "5"), 3, "Isym"),
            (with(4, "x"), 4, "not a number"),
            (with(29, "0"), 29, "flux is 0"),
            (with(43, "400"), 43, "outside"),
            (with(48, "0"), 48, "increase"),
            (with(50, "-3"), 50, "negative"),
            (with(51, "NaN"), 51, "not finite"),
            (with(24, "0"), 24, "conversion factor"),
            (format!("{good}\r\n7"), 53, "after the intensity table"),
            (format!("{good}\r\n\r\nx"), 54, "`x` after"),
        ];
        for (text, line, fault) in cases {
            let problem = parse_eulumdat(&text).unwrap_err();
            assert_eq!(problem.line, Some(line), "{fault}: {problem:?}");
            assert!(
                problem.message.contains(fault),
                "{fault}: {}",
                problem.message
            );
        }
    }
}
