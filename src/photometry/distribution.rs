//! A luminaire's luminous intensity distribution I(C, γ), in candela, on the
//! full sphere of the C-γ system (CIE 121, LM-63 type C).
//!
//! γ is the angle from the nadir (the luminaire's aim), 0° to 180°; C is the
//! azimuth of the half-plane, 0° to 360°. Files tabulate I on a web of C
//! planes and γ angles, often for part of the sphere only, and imply the
//! rest by symmetry; [`IntensityDistribution::from_planes`] expands what a
//! file gives to all C in [0°, 360°], and [`IntensityDistribution::intensity`]
//! interpolates bilinearly in (C, γ) between the tabulated values.

/// Which part of the C range a file tabulates, and so how the rest follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Symmetry {
    /// One plane: the same in every C (rotational symmetry about the aim).
    Rotational,
    /// C 0°–90°: symmetric about the C0–C180 and C90–C270 planes.
    Quadrant,
    /// C 0°–180°: symmetric about the C0–C180 plane, I(C) = I(360° − C).
    AboutC0C180,
    /// C 90°–270°: symmetric about the C90–C270 plane, I(C) = I(180° − C).
    /// (EULUMDAT's Isym 3 stores the other half, C270 … C90; its reader
    /// mirrors those planes onto 90°–270° first.)
    AboutC90C270,
    /// C 0°–360°: no symmetry.
    None,
}

/// The luminous opening: the emitting shape's size, metres (LM-63's width,
/// length and height; EULUMDAT's luminous area). Zero where the file gives
/// a point source.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LuminousOpening {
    /// Along the C90–C270 axis, metres (LM-63 width; negative: circular,
    /// of diameter −width, as LM-63 says it and as EULUMDAT's zero width
    /// with a length is read).
    pub width: f64,
    /// Along the C0–C180 axis, metres.
    pub length: f64,
    /// Along the aim, metres.
    pub height: f64,
}

/// An intensity I(C, γ) with its partial derivatives, as
/// [`IntensityDistribution::intensity_with_derivatives`] gives them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntensityWithDerivatives {
    /// I(C, γ), candela.
    pub intensity: f64,
    /// ∂I/∂C, candela per degree.
    pub d_c: f64,
    /// ∂I/∂γ, candela per degree.
    pub d_gamma: f64,
}

impl IntensityWithDerivatives {
    /// No intensity and no slope: outside the tabulated range.
    const ZERO: IntensityWithDerivatives = IntensityWithDerivatives {
        intensity: 0.0,
        d_c: 0.0,
        d_gamma: 0.0,
    };
}

/// An intensity distribution on the full C-γ sphere: `c_angles` from 0° to
/// 360° ascending (the last plane equal to the first), `gamma_angles`
/// ascending within [0°, 180°], and the intensities in candela, plane after
/// plane. Zero outside the tabulated γ range.
#[derive(Clone, Debug, PartialEq)]
pub struct IntensityDistribution {
    c_angles: Vec<f64>,
    gamma_angles: Vec<f64>,
    candela: Vec<f64>,
    /// The luminous opening, metres.
    pub opening: LuminousOpening,
}

impl IntensityDistribution {
    /// Expands planes `c_angles` (degrees, strictly increasing, within the
    /// range `symmetry` names: 0°–90°, 0°–180°, 90°–270° or 0°–360°) with
    /// `candela[plane][γ]` at `gamma_angles` (strictly increasing, in
    /// [0°, 180°]) to the full sphere. The caller has checked the angles.
    #[must_use]
    pub fn from_planes(
        symmetry: Symmetry,
        c_angles: &[f64],
        gamma_angles: &[f64],
        candela: &[Vec<f64>],
        opening: LuminousOpening,
    ) -> IntensityDistribution {
        if c_angles.is_empty() || candela.is_empty() {
            return IntensityDistribution {
                c_angles: vec![0.0, 360.0],
                gamma_angles: vec![0.0],
                candela: vec![0.0, 0.0],
                opening,
            };
        }
        // The planes the file defines: the stored ones and their mirror
        // images, each a copy of the stored plane it mirrors.
        let mut angles = defined_angles(symmetry, c_angles);
        let mut planes: Vec<Vec<f64>> = angles
            .iter()
            .map(|&c| {
                if symmetry == Symmetry::Rotational {
                    candela[0].clone()
                } else {
                    plane_at(c_angles, candela, mirror(symmetry, c))
                }
            })
            .collect();
        close_the_circle(&mut angles, &mut planes);
        IntensityDistribution {
            c_angles: angles,
            gamma_angles: gamma_angles.to_vec(),
            candela: planes.concat(),
            opening,
        }
    }

    /// The intensity I(C, γ) in candela, C and γ in degrees: bilinear
    /// between the tabulated planes and angles, C taken modulo 360°, zero
    /// for γ outside the tabulated range (a downlight tabulated to 90°
    /// sends nothing upwards).
    #[must_use]
    pub fn intensity(&self, c: f64, gamma: f64) -> f64 {
        self.intensity_with_derivatives(c, gamma).intensity
    }

    /// I(C, γ) (see [`IntensityDistribution::intensity`]) and its partial
    /// derivatives ∂I/∂C and ∂I/∂γ, candela per degree, of the bilinear
    /// interpolant in the cell holding (C, γ):
    ///
    /// ```text
    ///   I = (1 − t_C) I_γ(C_i) + t_C I_γ(C_i+1),   I_γ(C) = (1 − t_γ) I(C, γ_j) + t_γ I(C, γ_j+1)
    ///   ∂I/∂C = (I_γ(C_i+1) − I_γ(C_i)) / (C_i+1 − C_i)
    ///   ∂I/∂γ = [(1 − t_C) ΔI(C_i) + t_C ΔI(C_i+1)] / (γ_j+1 − γ_j)
    /// ```
    ///
    /// On a tabulated angle the cell above it is used (the interpolant has a
    /// kink there); zero derivatives outside the tabulated range.
    #[must_use]
    pub fn intensity_with_derivatives(&self, c: f64, gamma: f64) -> IntensityWithDerivatives {
        let n = self.gamma_angles.len();
        let (Some(&g0), Some(&g1)) = (self.gamma_angles.first(), self.gamma_angles.last()) else {
            return IntensityWithDerivatives::ZERO;
        };
        if !(c.is_finite() && gamma.is_finite()) || gamma < g0 - 1e-9 || gamma > g1 + 1e-9 {
            return IntensityWithDerivatives::ZERO;
        }
        let (j, tg) = bracket(&self.gamma_angles, gamma.clamp(g0, g1));
        let (i, tc) = bracket(&self.c_angles, c.rem_euclid(360.0));
        let at = |plane: usize, k: usize| self.candela[plane * n + k];
        let gamma_span = if n == 1 {
            0.0
        } else {
            self.gamma_angles[j + 1] - self.gamma_angles[j]
        };
        // I along γ in a plane, and its step over the cell.
        let along = |plane: usize| {
            if n == 1 {
                (at(plane, 0), 0.0)
            } else {
                let step = at(plane, j + 1) - at(plane, j);
                (at(plane, j) + step * tg, step)
            }
        };
        let per_gamma = |step: f64| {
            if gamma_span > 0.0 {
                step / gamma_span
            } else {
                0.0
            }
        };
        let (a, step_a) = along(i);
        if self.c_angles.len() == 1 {
            return IntensityWithDerivatives {
                intensity: a,
                d_c: 0.0,
                d_gamma: per_gamma(step_a),
            };
        }
        let (b, step_b) = along(i + 1);
        let c_span = self.c_angles[i + 1] - self.c_angles[i];
        let d_c = if c_span > 0.0 { (b - a) / c_span } else { 0.0 };
        let d_gamma = per_gamma(step_a + (step_b - step_a) * tc);
        IntensityWithDerivatives {
            intensity: a + (b - a) * tc,
            d_c,
            d_gamma,
        }
    }

    /// The tabulated γ angles, degrees.
    #[must_use]
    pub fn gamma_angles(&self) -> &[f64] {
        &self.gamma_angles
    }

    /// The C planes after expansion, degrees from 0 to 360.
    #[must_use]
    pub fn c_angles(&self) -> &[f64] {
        &self.c_angles
    }

    /// The largest tabulated intensity, candela.
    #[must_use]
    pub fn peak(&self) -> f64 {
        self.candela.iter().copied().fold(0.0, f64::max)
    }

    /// The luminous flux Φ = ∫∫ I(C, γ) sin γ dγ dC, lumens, by the
    /// midpoint rule on a grid `refine` times finer than the γ web and of
    /// 360 × `refine` steps in C (the integral of the bilinear interpolant
    /// as that grows).
    #[must_use]
    pub fn flux(&self, refine: usize) -> f64 {
        let refine = refine.max(1);
        let (Some(&g0), Some(&g1)) = (self.gamma_angles.first(), self.gamma_angles.last()) else {
            return 0.0;
        };
        let steps_g = (self.gamma_angles.len().max(2) - 1) * refine;
        let steps_c = 360 * refine;
        let (dg, dc) = ((g1 - g0) / steps_g as f64, 360.0 / steps_c as f64);
        let mut total = 0.0;
        for a in 0..steps_c {
            let c = (a as f64 + 0.5) * dc;
            for b in 0..steps_g {
                let gamma = g0 + (b as f64 + 0.5) * dg;
                total += self.intensity(c, gamma) * gamma.to_radians().sin();
            }
        }
        total * dg.to_radians() * dc.to_radians()
    }
}

/// The index i and weight t with xs[i] ≤ x ≤ xs[i + 1], x = xs[i] + t
/// (xs[i + 1] − xs[i]); xs ascending, at least one entry, x within range.
fn bracket(xs: &[f64], x: f64) -> (usize, f64) {
    if xs.len() < 2 {
        return (0, 0.0);
    }
    let i = xs.partition_point(|&v| v <= x).clamp(1, xs.len() - 1) - 1;
    let span = xs[i + 1] - xs[i];
    let t = if span > 0.0 {
        ((x - xs[i]) / span).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (i, t)
}

/// The stored angle whose plane `symmetry` mirrors to C = `c`: C modulo
/// 360° folded onto the stored range (0° for one rotational plane).
fn mirror(symmetry: Symmetry, c: f64) -> f64 {
    match symmetry {
        Symmetry::Rotational => 0.0,
        Symmetry::Quadrant => {
            let c = c.rem_euclid(360.0);
            let c = if c > 180.0 { 360.0 - c } else { c };
            if c > 90.0 { 180.0 - c } else { c }
        }
        Symmetry::AboutC0C180 => {
            let c = c.rem_euclid(360.0);
            if c > 180.0 { 360.0 - c } else { c }
        }
        Symmetry::AboutC90C270 => {
            // Fold onto [90°, 270°] across the C90–C270 plane.
            let c = c.rem_euclid(360.0);
            if (90.0..=270.0).contains(&c) {
                c
            } else {
                (540.0 - c).rem_euclid(360.0)
            }
        }
        Symmetry::None => c.rem_euclid(360.0),
    }
}

/// The C angles the file defines, modulo 360° and ascending: the stored
/// `c_angles` and their mirror images across the C0–C180 and C90–C270
/// planes, those whose mirror is a stored plane (0° alone for a
/// rotational web).
fn defined_angles(symmetry: Symmetry, c_angles: &[f64]) -> Vec<f64> {
    let mut angles: Vec<f64> = match symmetry {
        Symmetry::Rotational => vec![0.0],
        _ => {
            let mut all = Vec::new();
            for &c in c_angles {
                let c = c.rem_euclid(360.0);
                all.extend([c, 360.0 - c, 180.0 - c, 180.0 + c]);
            }
            all.into_iter()
                .map(|c| c.rem_euclid(360.0))
                .filter(|&c| mirror(symmetry, c).is_finite())
                .collect()
        }
    };
    angles.sort_by(f64::total_cmp);
    angles.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    // Keep only the angles whose mirror is a stored plane (or the whole
    // range for a full web): the planes the file defines.
    let defined = |c: f64| {
        let m = mirror(symmetry, c);
        symmetry == Symmetry::Rotational
            || c_angles
                .iter()
                .any(|&s| (s.rem_euclid(360.0) - m).abs() < 1e-9)
    };
    angles.retain(|&c| defined(c));
    angles
}

/// Closes the circle of `planes` at `angles`: the plane at 360° is the one
/// at 0°. Without a plane at 0° (a full web starting later), the plane
/// there is interpolated between the last and the first across 360°.
fn close_the_circle(angles: &mut Vec<f64>, planes: &mut Vec<Vec<f64>>) {
    if angles.first().is_none_or(|&c| c > 1e-9) {
        let (first, last) = (angles[0], angles[angles.len() - 1]);
        let span = first + 360.0 - last;
        let w = if span > 0.0 {
            (360.0 - last) / span
        } else {
            0.0
        };
        let at_zero: Vec<f64> = planes[planes.len() - 1]
            .iter()
            .zip(&planes[0])
            .map(|(a, b)| a + (b - a) * w)
            .collect();
        angles.insert(0, 0.0);
        planes.insert(0, at_zero);
    }
    if angles.last().is_some_and(|&c| c < 360.0 - 1e-9) {
        angles.push(360.0);
        planes.push(planes[0].clone());
    } else if let Some(last) = angles.last_mut() {
        *last = 360.0;
    }
}

/// The stored plane at angle `c` (one of `c_angles` modulo 360°).
fn plane_at(c_angles: &[f64], candela: &[Vec<f64>], c: f64) -> Vec<f64> {
    let index = c_angles
        .iter()
        .position(|&s| (s.rem_euclid(360.0) - c).abs() < 1e-9)
        .unwrap_or(0);
    candela[index].clone()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opening() -> LuminousOpening {
        LuminousOpening::default()
    }

    #[test]
    fn an_isotropic_source_of_one_candela_emits_four_pi_lumens() {
        let d = IntensityDistribution::from_planes(
            Symmetry::Rotational,
            &[0.0],
            &[0.0, 90.0, 180.0],
            &[vec![1.0, 1.0, 1.0]],
            opening(),
        );
        assert_eq!(d.intensity(123.0, 45.0), 1.0);
        let flux = d.flux(64);
        assert!(
            (flux / (4.0 * std::f64::consts::PI) - 1.0).abs() < 1e-4,
            "{flux}"
        );
    }

    #[test]
    fn a_quadrant_web_mirrors_into_every_quadrant() {
        // I = 1 + C/90 in C0–C90 at every γ: C = 120 mirrors to 60, 200 to
        // 20, 300 to 60.
        let planes: Vec<Vec<f64>> = [0.0, 30.0, 60.0, 90.0]
            .iter()
            .map(|c| vec![1.0 + c / 90.0; 2])
            .collect();
        let d = IntensityDistribution::from_planes(
            Symmetry::Quadrant,
            &[0.0, 30.0, 60.0, 90.0],
            &[0.0, 90.0],
            &planes,
            opening(),
        );
        for (c, mirrored) in [(120.0, 60.0), (200.0, 20.0), (300.0, 60.0), (345.0, 15.0)] {
            let expected = 1.0 + mirrored / 90.0;
            assert!((d.intensity(c, 10.0) - expected).abs() < 1e-12, "C = {c}");
        }
        // Nothing above the tabulated 90°.
        assert_eq!(d.intensity(0.0, 120.0), 0.0);
    }

    #[test]
    fn a_web_symmetric_about_c90_c270_mirrors_across_that_plane() {
        // Planes C90, C180, C270 with I = C / 90: C0 mirrors to 180 (2),
        // C45 to 135 (1.5), C315 to 225 (2.5).
        let cs = [90.0, 180.0, 270.0];
        let planes: Vec<Vec<f64>> = cs.iter().map(|c| vec![c / 90.0; 2]).collect();
        let d = IntensityDistribution::from_planes(
            Symmetry::AboutC90C270,
            &cs,
            &[0.0, 180.0],
            &planes,
            opening(),
        );
        for (c, expected) in [(0.0, 2.0), (45.0, 1.5), (315.0, 2.5), (180.0, 2.0)] {
            assert!((d.intensity(c, 30.0) - expected).abs() < 1e-12, "C = {c}");
        }
    }

    #[test]
    fn intensities_interpolate_bilinearly() {
        let d = IntensityDistribution::from_planes(
            Symmetry::None,
            &[0.0, 90.0, 180.0, 270.0, 360.0],
            &[0.0, 90.0],
            &[
                vec![0.0, 10.0],
                vec![20.0, 30.0],
                vec![0.0, 0.0],
                vec![0.0, 0.0],
                vec![0.0, 10.0],
            ],
            opening(),
        );
        // Halfway between C0 and C90, a third of the way to γ 90:
        // (0 + 20)/2 + ((10 + 30)/2 − 10) / 3.
        let expected = 10.0 + 10.0 / 3.0;
        assert!((d.intensity(45.0, 30.0) - expected).abs() < 1e-12);
        assert!((d.intensity(405.0, 30.0) - expected).abs() < 1e-12);
    }
}
