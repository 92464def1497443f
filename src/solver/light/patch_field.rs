//! A shooting patch's unshot field: ΔB over its elements, read where a
//! shot's strata and samples fall, and the scale that makes them carry the
//! patch's unshot power.

use glam::{DVec2, DVec3};

use crate::mesh::Cell;
use crate::rgb::Rgb;
use crate::solver::light::cell_coordinates::{cell_coordinates, interpolated};
use crate::solver::light::element_index::{ElementIndex, padded_box};

/// One element of a shooting patch: its shape, bounding box and ΔB at its corners.
#[derive(Clone, Debug)]
pub(crate) struct FieldElement {
    cell: Cell,
    min: DVec3,
    max: DVec3,
    corners: [Rgb; 4],
}

impl FieldElement {
    /// An element of shape `cell` with ΔB `corners` at its corners.
    pub(crate) fn new(cell: Cell, corners: [Rgb; 4]) -> FieldElement {
        let (min, max) = padded_box(cell.polygon());
        FieldElement {
            cell,
            min,
            max,
            corners,
        }
    }

    /// The mean of ΔB at its corners (three for a triangle).
    fn corner_mean(&self) -> Rgb {
        if self.cell.is_triangle {
            (self.corners[0] + self.corners[1] + self.corners[2]) / 3.0
        } else {
            self.corners.iter().copied().sum::<Rgb>() * 0.25
        }
    }

    /// ΔB at point y, linear over a triangle and bilinear over a quad (the
    /// parametrisation of [`Cell::point`]); `None` when y is outside.
    fn at(&self, y: DVec3) -> Option<Rgb> {
        let st = self.coordinates(y)?;
        Some(interpolated(
            self.corners,
            self.cell.is_triangle,
            DVec2::from(st),
        ))
    }

    /// The coordinates (s, t) of point y in the element; `None` when y is
    /// outside.
    fn coordinates(&self, y: DVec3) -> Option<(f64, f64)> {
        if y.cmplt(self.min).any() || y.cmpgt(self.max).any() {
            return None;
        }
        cell_coordinates(&self.cell, y)
    }
}

/// A shooting patch's unshot radiosity over its elements and the power it
/// shoots.
#[derive(Clone, Debug)]
pub struct PatchField {
    elements: Vec<FieldElement>,
    /// Σ_e A_e mean_corners(ΔB): the patch's unshot power (W).
    power: Rgb,
    /// The normal of the patch's plane.
    normal: DVec3,
    /// Which elements lie where, to find the one under a point; made when
    /// a point first misses the element found last.
    index: std::sync::OnceLock<ElementIndex>,
}

impl PatchField {
    /// A field of elements shooting `power` in all, on a patch facing the
    /// unit `normal`.
    pub(crate) fn new(elements: Vec<FieldElement>, power: Rgb, normal: DVec3) -> PatchField {
        PatchField {
            elements,
            power,
            normal,
            index: std::sync::OnceLock::new(),
        }
    }

    /// The index of the elements, made on first use.
    fn index(&self) -> &ElementIndex {
        self.index.get_or_init(|| {
            let boxes: Vec<(DVec3, DVec3)> = self.elements.iter().map(|e| (e.min, e.max)).collect();
            ElementIndex::new(&boxes, self.normal)
        })
    }

    /// The scale that turns ΔB read at a point ([`PatchField::unshot_at`])
    /// into W: the shot's power over the elements' Σ_e A_e mean_corners(ΔB)
    /// (1 when the ledger and the corners agree), so that the field read
    /// point by point carries the patch's power, as the sampled cells do.
    pub(crate) fn exact_scale(&self) -> FieldScale {
        let sum = self
            .elements
            .iter()
            .map(|e| e.corner_mean() * e.cell.area)
            .sum::<Rgb>()
            .to_array();
        let total_area: f64 = self.elements.iter().map(|e| e.cell.area).sum();
        FieldScale::to_carry(self.power, sum, total_area)
    }

    /// The radiosity each stratum shoots: ΔB at its centre, interpolated
    /// from the element under it (zero where no element is, as under an
    /// object standing on the patch), then scaled channel by channel so that
    /// the strata carry exactly the patch's unshot power,
    ///
    /// ```text
    ///   W_k = ΔB(c_k) · P / Σ_i ΔB(c_i) A_i,   Σ_k W_k A_k = P = Σ_e A_e ΔB̄_e,
    /// ```
    ///
    /// (uniform P / Σ A_i for a channel whose raw sum is not positive).
    ///
    /// Here the values are read at the centres of `sub` × `sub` cells of
    /// each stratum's parameter square, stratum by stratum and row by row
    /// (cell (i, j) of stratum k at k·sub² + j·sub + i), scaled together so
    /// that Σ_k Σ_ij W_kij A_k / sub² = P (`sub` = 1: one value per stratum,
    /// at its centre). A shot reads W where its jittered sample falls: a
    /// stratum partly under an object standing on the patch then shoots
    /// nothing along the rays that start under the object, and its power
    /// leaves from the rest, instead of being lost on the object.
    ///
    /// # References
    /// M. F. Cohen, S. E. Chen, J. R. Wallace, D. P. Greenberg, "A Progressive
    /// Refinement Approach to Fast Radiosity Image Generation", SIGGRAPH 1988;
    /// J. R. Wallace, K. A. Elmquist, E. A. Haines, "A Ray Tracing Algorithm
    /// for Progressive Radiosity", SIGGRAPH 1989.
    ///
    /// Returned with which cells' centres found an element.
    pub(crate) fn sampled(&self, strata: &[Cell], sub: usize) -> SampledField {
        let sub = sub.max(1);
        let share = 1.0 / (sub * sub) as f64;
        let mut raw = Vec::with_capacity(strata.len() * sub * sub);
        let mut areas = Vec::with_capacity(raw.capacity());
        let mut last = 0;
        for stratum in strata {
            for j in 0..sub {
                for i in 0..sub {
                    let centre =
                        stratum.point((i as f64 + 0.5) / sub as f64, (j as f64 + 0.5) / sub as f64);
                    raw.push(self.unshot_at(centre, &mut last));
                    areas.push(stratum.area * share);
                }
            }
        }
        let total_area: f64 = areas.iter().sum();
        let sum = raw
            .iter()
            .zip(&areas)
            .map(|(w, a)| w.unwrap_or(Rgb::ZERO) * *a)
            .sum::<Rgb>()
            .to_array();
        let scale = FieldScale::to_carry(self.power, sum, total_area);
        let found = raw.iter().map(Option::is_some).collect();
        let sampled = raw
            .into_iter()
            .map(|w| scale.apply(w.unwrap_or(Rgb::ZERO)))
            .collect();
        SampledField { sampled, found }
    }

    /// ΔB at a point of the patch, interpolated from the element under it;
    /// `None` where none is, as under an object standing on the patch.
    /// `hint` is the element found last: neighbouring points mostly fall in
    /// the same element, so it is tried first.
    pub(crate) fn unshot_at(&self, y: DVec3, hint: &mut usize) -> Option<Rgb> {
        self.elements.get(*hint).and_then(|e| e.at(y)).or_else(|| {
            self.index().near(y).iter().find_map(|&k| {
                let k = k as usize;
                self.elements[k].at(y).inspect(|_| *hint = k)
            })
        })
    }

    /// The element under a point of the patch (its index among the
    /// patch's elements) and the point's coordinates in it, as
    /// [`PatchField::unshot_at`] finds them.
    pub(crate) fn locate(&self, y: DVec3, hint: &mut usize) -> Option<(usize, (f64, f64))> {
        let inside = |k: usize| self.elements.get(k)?.coordinates(y);
        if let Some(st) = inside(*hint) {
            return Some((*hint, st));
        }
        self.index().near(y).iter().find_map(|&k| {
            let k = k as usize;
            inside(k).map(|st| {
                *hint = k;
                (k, st)
            })
        })
    }
}

/// The radiosity a patch's sampled cells shoot
/// ([`PatchField::sampled`]), and whether each cell's centre
/// found an element: one that found none (under an object standing on the
/// patch) reads nothing, though part of it may be lit.
#[derive(Clone, Debug)]
pub(crate) struct SampledField {
    pub(crate) sampled: Vec<Rgb>,
    pub(crate) found: Vec<bool>,
}

/// How a shot turns a patch's unshot radiosity ΔB into the radiosity W its
/// strata shoot, channel by channel: W = ΔB · factor + uniform, where
/// `factor` makes the strata carry exactly the patch's unshot power (and
/// `uniform` spreads a channel evenly whose ΔB was read nowhere positive).
#[derive(Clone, Copy, Debug)]
pub(crate) struct FieldScale {
    factor: [f64; 3],
    uniform: [f64; 3],
}

impl FieldScale {
    /// The scale that makes values summing to `sum` (ΔB times area, per
    /// channel) carry `power`; a channel whose sum is not positive spreads
    /// its power evenly over `area`.
    fn to_carry(power: Rgb, sum: [f64; 3], area: f64) -> FieldScale {
        let target = power.to_array();
        let mut scale = FieldScale {
            factor: [0.0; 3],
            uniform: [0.0; 3],
        };
        for c in 0..3 {
            if sum[c] > 0.0 {
                scale.factor[c] = target[c] / sum[c];
            } else if area > 0.0 {
                scale.uniform[c] = target[c] / area;
            }
        }
        scale
    }

    /// W for the unshot radiosity `unshot`.
    pub(crate) fn apply(&self, unshot: Rgb) -> Rgb {
        let w = unshot.to_array();
        let channel = |c: usize| w[c] * self.factor[c] + self.uniform[c];
        Rgb::new(channel(0), channel(1), channel(2))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strata_carry_the_patch_power_where_the_light_is() {
        // A unit square, lit on its left edge only.
        let cell = Cell::quad(DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y);
        let (lit, dark) = (Rgb::splat(2.0), Rgb::ZERO);
        let field = PatchField::new(
            vec![FieldElement::new(cell, [lit, dark, dark, lit])],
            Rgb::splat(1.0),
            DVec3::Z,
        );
        let mut strata = Vec::new();
        cell.subdivide(4, &mut strata);
        let w = field.sampled(&strata, 1).sampled;
        let power: Rgb = w.iter().zip(&strata).map(|(w, s)| *w * s.area).sum();
        assert!((power.r - 1.0).abs() < 1e-12);
        // Column 0 (x = 1/8) shoots 7 times what column 3 (x = 7/8) does.
        assert!((w[0].r / w[3].r - 7.0).abs() < 1e-9);
    }
}
