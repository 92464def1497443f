//! MTL material libraries: a line-by-line check with line numbers, parsing
//! through tobj, and conversion to [`Material`].
//!
//! Only `Kd` (diffuse reflectance ρ, 0 ≤ ρ < 1 per channel), `Ke` (emitted
//! radiance L_e ≥ 0) and `Tf` (glazing: transmittance at normal incidence,
//! its luminance read as τ_n, 0 ≤ τ_n < 1) matter to isorad; other
//! statements are checked only as far as tobj needs them to be well formed. Blanks and tabs may
//! stand anywhere between tokens (see [`super::statement`]).

use std::path::Path;

use crate::error::{Error, Result};

use super::statement::{canonical_line, canonical_text, split_statement};
use crate::daylight::pane_diffuse_reflectance;
use crate::rgb::Rgb;
use crate::scene::material::{Material, NOT_FINITE, emitted_radiance_problem, reflectance_problem};

/// Checks an MTL text before tobj parses it, so that errors carry a line
/// number and out-of-range colours are caught (tobj itself would panic on a
/// colour with fewer than three numbers).
pub(crate) fn check_mtl(path: &Path, text: &str) -> Result<()> {
    let mut material = String::new();
    for (index, line) in text.lines().enumerate() {
        let number = index + 1;
        let Some((keyword, rest)) = split_statement(line) else {
            continue;
        };
        let mut words = rest.split_whitespace();
        let parse_error = |message: String| Error::MtlParse {
            path: path.to_path_buf(),
            line: Some(number),
            message,
        };
        match keyword {
            "newmtl" => {
                rest.clone_into(&mut material);
                if material.is_empty() {
                    return Err(parse_error("`newmtl` without a material name".into()));
                }
            }
            "Ka" | "Kd" | "Ks" | "Ke" => {
                let Some(rgb) = parse_rgb(&mut words) else {
                    return Err(parse_error(format!(
                        "`{keyword}` needs three numbers (r g b)"
                    )));
                };
                check_colour(keyword, rgb).map_err(|message| Error::InvalidMaterial {
                    path: path.to_path_buf(),
                    line: Some(number),
                    material: material.clone(),
                    message,
                })?;
            }
            "Tf" => {
                let transmittance = parse_transmission_filter(rest).map_err(parse_error)?;
                check_transmittance(transmittance).map_err(|message| Error::InvalidMaterial {
                    path: path.to_path_buf(),
                    line: Some(number),
                    material: material.clone(),
                    message,
                })?;
            }
            "Ns" | "Ni" | "d" if words.next().and_then(|w| w.parse::<f32>().ok()).is_none() => {
                return Err(parse_error(format!("`{keyword}` needs a number")));
            }
            "illum" if words.next().and_then(|w| w.parse::<u8>().ok()).is_none() => {
                return Err(parse_error("`illum` needs an integer in 0..=255".into()));
            }
            _ if (keyword.starts_with("map_") || keyword == "bump") && words.next().is_none() => {
                return Err(parse_error(format!("`{keyword}` needs a file name")));
            }
            _ => {}
        }
    }
    Ok(())
}

/// The first three words as numbers, read as tobj reads them (f32).
fn parse_rgb(words: &mut std::str::SplitWhitespace) -> Option<[f32; 3]> {
    let mut rgb = [0.0; 3];
    for c in &mut rgb {
        *c = words.next()?.parse().ok()?;
    }
    Some(rgb)
}

/// The visible transmittance of a `Tf` statement's text: `r g b` (or one
/// number for all three), read as its Rec. 709 luminance. The `spectral`
/// and `xyz` forms are refused: isorad reads colours as RGB.
fn parse_transmission_filter(rest: &str) -> Result<f64, String> {
    let words: Vec<&str> = rest.split_whitespace().collect();
    let numbers: Option<Vec<f64>> = words.iter().map(|w| w.parse::<f64>().ok()).collect();
    match numbers.as_deref() {
        Some([t]) => Ok(*t),
        Some([r, g, b]) => Ok(Rgb::new(*r, *g, *b).luminance()),
        _ if words
            .first()
            .is_some_and(|w| *w == "spectral" || *w == "xyz") =>
        {
            Err(format!(
                "`Tf {}` is not supported: give the transmittance as `Tf r g b`",
                words[0]
            ))
        }
        _ => Err("`Tf` needs three numbers (r g b) or one".into()),
    }
}

/// Why a glazing transmittance is out of range (finite, at least 0 and
/// below 1), or `Ok`.
fn check_transmittance(transmittance: f64) -> Result<(), String> {
    if !transmittance.is_finite() || !(0.0..1.0).contains(&transmittance) {
        return Err(format!(
            "Tf = {transmittance}: the transmittance (Tf's luminance) must be at least 0 and below 1"
        ));
    }
    Ok(())
}

/// Range checks: `Kd` finite and in [0, 1), `Ke` finite and ≥ 0, the others
/// finite (the checks [`Material::problem`] makes).
fn check_colour(keyword: &str, rgb: [f32; 3]) -> Result<(), String> {
    let colour = Rgb::new(f64::from(rgb[0]), f64::from(rgb[1]), f64::from(rgb[2]));
    let problem = match keyword {
        "Kd" => reflectance_problem(colour),
        "Ke" => emitted_radiance_problem(colour),
        _ => (!colour.is_finite()).then_some(NOT_FINITE),
    };
    match problem {
        Some(problem) => Err(format!(
            "{keyword} = ({} {} {}): {problem}",
            rgb[0], rgb[1], rgb[2]
        )),
        None => Ok(()),
    }
}

/// Checks an MTL text, then parses it with tobj, in canonical form as the
/// OBJ loader hands tobj its text. The result is tobj's (always `Ok` here),
/// ready to hand back to tobj's OBJ loader.
pub(crate) fn parse_mtl(path: &Path, text: &str) -> Result<tobj::MTLLoadResult> {
    check_mtl(path, text)?;
    let text = canonical_text(text, canonical_line);
    let parsed = tobj::load_mtl_buf(&mut text.as_bytes());
    if let Err(e) = &parsed {
        return Err(Error::MtlParse {
            path: path.to_path_buf(),
            line: None,
            message: e.to_string(),
        });
    }
    Ok(parsed)
}

/// Converts a (checked) tobj material: `Kd` → reflectance, `Ke` → emitted
/// radiance, `Tf` → glazing transmittance, a missing one taken as zero.
/// Also returns a warning when `Kd` is missing from an opaque material, or
/// when a material is transparent by `d` or `Tr` but has no `Tf`.
#[must_use]
pub(crate) fn to_material(m: &tobj::Material) -> (Material, Option<String>) {
    let rgb = |c: [f32; 3]| Rgb::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2]));
    let transmittance = m
        .unknown_param
        .get("Tf")
        .and_then(|text| parse_transmission_filter(text).ok())
        .unwrap_or(0.0);
    let dissolved = m.dissolve.is_some_and(|d| d < 1.0)
        || m.unknown_param
            .get("Tr")
            .and_then(|t| t.trim().parse::<f64>().ok())
            .is_some_and(|t| t > 0.0);
    let warning = if transmittance > 0.0 {
        None
    } else if dissolved {
        Some(format!(
            "material `{}` is transparent (`d` or `Tr`) but has no `Tf`: it is taken as opaque; give glazing its transmittance with `Tf`",
            m.name
        ))
    } else {
        m.diffuse
            .is_none()
            .then(|| format!("material `{}` has no `Kd`: it reflects nothing", m.name))
    };
    // Glazing reflects as a clear pane does under diffuse light (its `Kd`,
    // often a tint for a viewer, is not a reflectance).
    let reflectance = if transmittance > 0.0 {
        Rgb::splat(pane_diffuse_reflectance(transmittance))
    } else {
        m.diffuse.map_or(Rgb::ZERO, rgb)
    };
    let material = Material {
        name: m.name.clone(),
        reflectance,
        emitted_radiance: m.emissive.map_or(Rgb::ZERO, rgb),
        transmittance,
    };
    (material, warning)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(text: &str) -> Result<()> {
        check_mtl(Path::new("t.mtl"), text)
    }

    #[test]
    fn good_library_passes() {
        let text = "# comment\nnewmtl white\nKd 0.7 0.7 0.7\nKe 0 0 0\nNs 10\nillum 1\n";
        assert!(check(text).is_ok());
        let (m, _) = parse_mtl(Path::new("t.mtl"), text).unwrap().unwrap();
        let (material, warning) = to_material(&m[0]);
        assert!((material.reflectance.r - 0.7).abs() < 1e-6);
        assert!(warning.is_none());
    }

    /// Blanks and tabs around and between tokens change nothing.
    #[test]
    fn indented_library_reads_as_the_plain_one() {
        let plain = "newmtl white\nKd 0.7 0.7 0.7\nnewmtl lamp\nKe 1 2 3\nmap_Kd a b.png\n";
        let indented = "\t newmtl\twhite \n  Kd\t0.7 \t0.7 0.7\t\n\tnewmtl lamp\r\n \tKe 1\t2 3 \n\tmap_Kd\t a b.png \n";
        let read = |text| parse_mtl(Path::new("t.mtl"), text).unwrap().unwrap().0;
        // tobj's materials compare by their debug form (no unknown
        // parameters here, whose map would print in any order).
        assert_eq!(
            format!("{:?}", read(indented)),
            format!("{:?}", read(plain))
        );
        assert_eq!(
            read(indented)[1].diffuse_texture.as_deref(),
            Some("a b.png")
        );
        let e = check("\tnewmtl\t wall \n  Kd 1 0.5 0.5\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("t.mtl:2") && e.contains("`wall`"), "{e}");
    }

    /// `Tf`'s luminance is the glazing's transmittance; one number stands
    /// for all three; `d` without `Tf` is opaque, with a warning.
    #[test]
    fn tf_is_glazing() {
        let text = "newmtl pane\nKd 0.1 0.1 0.1\nTf 0.7 0.8 0.9\nnewmtl grey\nTf 0.6\nnewmtl veil\nKd 0.5 0.5 0.5\nd 0.3\n";
        let (m, _) = parse_mtl(Path::new("t.mtl"), text).unwrap().unwrap();
        let (pane, warning) = to_material(&m[0]);
        let expected = 0.2126 * 0.7 + 0.7152 * 0.8 + 0.0722 * 0.9;
        assert!((pane.transmittance - expected).abs() < 1e-12 && warning.is_none());
        assert!((to_material(&m[1]).0.transmittance - 0.6).abs() < 1e-12);
        let (veil, warning) = to_material(&m[2]);
        assert_eq!(veil.transmittance, 0.0);
        assert!(warning.is_some_and(|w| w.contains("`veil`") && w.contains("Tf")));
    }

    #[test]
    fn errors_carry_line_and_material() {
        let e = check("newmtl a\n\nKd 0.5 0.5\n").unwrap_err().to_string();
        assert!(e.contains("t.mtl:3") && e.contains("three numbers"), "{e}");
        let e = check("newmtl wall\nKd 1 0.5 0.5\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("t.mtl:2") && e.contains("`wall`"), "{e}");
        let e = check("newmtl lamp\nKe 1 -1 1\n").unwrap_err().to_string();
        assert!(e.contains("`lamp`") && e.contains("negative"), "{e}");
        let e = check("newmtl x\nKd nan 0 0\n").unwrap_err().to_string();
        assert!(e.contains("finite"), "{e}");
        assert!(check("newmtl\n").is_err());
        let e = check("newmtl glass\nTf 1 1 1\n").unwrap_err().to_string();
        assert!(
            e.contains("t.mtl:2") && e.contains("`glass`") && e.contains("below 1"),
            "{e}"
        );
        let e = check("newmtl glass\nTf spectral a.rfl\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("t.mtl:2") && e.contains("not supported"), "{e}");
        assert!(check("newmtl glass\nTf 0.5 0.5\n").is_err());
        assert!(check("newmtl x\nillum\n").is_err());
    }
}
