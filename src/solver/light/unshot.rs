//! Where on a patch its unshot light lies: unshot radiosity ΔB at every
//! element's corners, the field a patch's strata shoot from.
//!
//! Each element keeps its own copy of ΔB at its corners rather than one
//! value per vertex: a vertex on the border of two patches of one surface
//! then carries each patch's share separately, and a patch that shoots
//! clears its own elements' copies without touching its neighbour's. Within
//! a patch the copies agree (the elements receive the same light at a shared
//! vertex and are cleared together), so the field is continuous over the
//! patch and the interpolation the renderer would draw.

use rayon::prelude::*;

use crate::mesh::{Element, Mesh, Patch};
use crate::rgb::Rgb;
use crate::solver::light::indexed_update::par_update_at;
use crate::solver::light::patch_field::{FieldElement, PatchField};
use crate::solver::light::vertex_irradiance::VertexIrradiance;

/// Unshot radiosity ΔB_v (W/m²) at the corners of every element of a mesh,
/// by element index (a triangle's fourth entry is unused).
///
/// The solver's per-patch totals stay the ledger's: a patch's unshot power
/// is Σ_e A_e · mean_corners(ΔB), and every change to the corners here is
/// matched by that change to the total, up to rounding. The corners give the
/// shape of the light over the patch; a shot scales its strata to the total
/// (see [`PatchField::sampled`]).
///
/// The corners are kept as 16-bit fractions of the element's largest,
/// 28 bytes an element where `f32` took 48 and `f64` 96: with one element
/// per vertex or more, this array was the largest of a building's solve
/// (1.07 of the 6.8 GB at the peak of a million quads' view). The corners
/// only shape the field: a shot scales its strata to the patch's total,
/// kept in `f64` ([`FieldScale`]), so their rounding moves no power. Each
/// store rounds by at most 1.5 · 10⁻⁵ of the element's largest corner
/// value, and a shot that adds less than that to a dim corner adds nothing,
/// so over many shots the dim corners may lag. Solved to 0.2 % unshot
/// (734 shots on the Cornell box, 1,087 on `scenes/room`), the images are
/// those of corners in `f32` to 0.000 % per pixel.
#[derive(Clone, Debug, Default)]
pub(crate) struct UnshotCorners {
    corners: Vec<PackedCorners>,
}

/// An element's four corners' ΔB: each channel a signed fraction of
/// `largest` (the largest magnitude among them, as `f32`) in steps of
/// 1/[`STEPS`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct PackedCorners {
    largest: f32,
    fractions: [[i16; 3]; 4],
}

/// Steps from zero to an element's largest corner value.
const STEPS: f64 = i16::MAX as f64;

/// Rounds corners to their stored form, beyond f32's range to its largest
/// value (an emitter of 10³⁹ W/m² would otherwise store infinity, and its
/// shot's scale 0 · ∞); a NaN is stored as zero.
fn packed(corners: [Rgb; 4]) -> PackedCorners {
    let limit = f64::from(f32::MAX);
    let largest = corners
        .iter()
        .map(|c| c.abs().max_element())
        .fold(0.0, f64::max)
        .min(limit);
    if largest <= 0.0 {
        return PackedCorners::default();
    }
    let largest = largest as f32;
    let unit = f64::from(largest);
    let fraction = |w: f64| (w / unit * STEPS).round().clamp(-STEPS, STEPS) as i16;
    PackedCorners {
        largest,
        fractions: corners.map(|c| c.to_array().map(fraction)),
    }
}

/// Corners in their stored form, widened back.
fn unpacked(corners: &PackedCorners) -> [Rgb; 4] {
    let step = f64::from(corners.largest) / STEPS;
    let value = |q: i16| f64::from(q) * step;
    corners
        .fractions
        .map(|[r, g, b]| Rgb::new(value(r), value(g), value(b)))
}

impl UnshotCorners {
    /// Every element's corners at its patch's unshot radiosity.
    pub(crate) fn new(mesh: &Mesh, per_patch: &[Rgb]) -> UnshotCorners {
        let corners = mesh
            .elements
            .par_iter()
            .map(|e| packed([per_patch[e.patch as usize]; 4]))
            .collect();
        UnshotCorners { corners }
    }

    /// Adds a per-vertex value (reflected irradiance) at the corners of
    /// each of `elements` (ascending indices, a closed zone's or all), in
    /// parallel: `value(element, v)` at its corner v.
    pub(crate) fn add_shot(
        &mut self,
        mesh: &Mesh,
        elements: &[u32],
        value: impl Fn(&Element, u32) -> Rgb + Sync,
    ) {
        par_update_at(&mut self.corners, elements, &|k, stored| {
            let element = &mesh.elements[elements[k] as usize];
            let mut added = [Rgb::ZERO; 4];
            for (slot, &v) in added.iter_mut().zip(element.corners()) {
                *slot = value(element, v);
            }
            // An element the shot does not reach (facing away, hidden) is
            // not unpacked and packed again: on the cluttered office
            // solved to 1 % (2,709 shots), that took 14 % of the solve.
            if added.iter().all(|&a| a == Rgb::ZERO) {
                return;
            }
            let mut corners = unpacked(stored);
            for (slot, a) in corners.iter_mut().zip(added) {
                *slot += a;
            }
            *stored = packed(corners);
        });
    }

    /// Clears a patch's share: it has shot it.
    pub(crate) fn clear(&mut self, patch: &Patch) {
        for &e in &patch.elements {
            self.corners[e as usize] = packed([Rgb::ZERO; 4]);
        }
    }

    /// A patch's field, to shoot `power` (W) from.
    pub(crate) fn field(&self, mesh: &Mesh, patch: &Patch, power: Rgb) -> PatchField {
        let elements = patch
            .elements
            .iter()
            .map(|&e| {
                let cell = mesh.element_cell(&mesh.elements[e as usize]);
                FieldElement::new(cell, unpacked(&self.corners[e as usize]))
            })
            .collect();
        PatchField::new(elements, power, patch.cell.normal())
    }

    /// Element e's corners, ΔB at each (in [`Element::corners`] order).
    pub(crate) fn of(&self, e: usize) -> [Rgb; 4] {
        unpacked(&self.corners[e])
    }

    /// Carries the corners over an adaptive split: `old` holds the corners
    /// of the elements before it, by their corner indices (an element's
    /// vertex array identifies it). A leaf that was not split keeps its
    /// corners; a new child takes ΔB interpolated from its parent at its
    /// corners (a parent corner, an edge's midpoint, a quad's centre), plus
    /// ρ (H_v − H̃_v), what the vertex reflects beyond the irradiance H̃_v
    /// interpolated the same way: the light refinement found there, which
    /// is the change ΔP in incident power that [`crate::Solver`]'s refine
    /// moves into the patch's unshot power (its ρ ΔP). For children that
    /// tile their parent as the parent's bilinear map does (parallelograms
    /// and triangles), the corner integral then changes by exactly ρ ΔP.
    pub(crate) fn after_split(
        &mut self,
        mesh: &Mesh,
        parent_of: impl Fn(usize) -> Option<Element>,
        old: &std::collections::HashMap<[u32; 4], [Rgb; 4]>,
        irradiance: &VertexIrradiance,
        reflectance: impl Fn(&Element) -> Rgb,
    ) {
        self.corners = mesh
            .elements
            .iter()
            .enumerate()
            .map(|(i, element)| -> [Rgb; 4] {
                if let Some(kept) = old.get(&element.vertices) {
                    return *kept;
                }
                let Some(parent) = parent_of(i) else {
                    return [Rgb::ZERO; 4];
                };
                let Some(parent_corners) = old.get(&parent.vertices) else {
                    return [Rgb::ZERO; 4];
                };
                let rho = reflectance(element);
                let mut corners = [Rgb::ZERO; 4];
                for (slot, &v) in corners.iter_mut().zip(element.corners()) {
                    let unshot = interpolate_in_parent(mesh, &parent, v, |k| parent_corners[k]);
                    let expected = interpolate_in_parent(mesh, &parent, v, |k| {
                        irradiance.at(parent.vertices[k] as usize)
                    });
                    *slot = unshot + rho * (irradiance.at(v as usize) - expected);
                }
                corners
            })
            .map(packed)
            .collect();
    }

    /// The corners of every element, by their vertex arrays: what
    /// [`UnshotCorners::after_split`] reads.
    pub(crate) fn by_vertices(&self, mesh: &Mesh) -> std::collections::HashMap<[u32; 4], [Rgb; 4]> {
        mesh.elements
            .iter()
            .zip(&self.corners)
            .map(|(e, c)| (e.vertices, unpacked(c)))
            .collect()
    }
}

/// A per-corner value of `parent` at vertex `v` of one of its children: the
/// corner's own value, the mean of an edge's ends at its midpoint, the mean
/// of all corners at a quad's centre.
fn interpolate_in_parent(
    mesh: &Mesh,
    parent: &Element,
    v: u32,
    value: impl Fn(usize) -> Rgb,
) -> Rgb {
    let corners = parent.corners();
    if let Some(k) = corners.iter().position(|&c| c == v) {
        return value(k);
    }
    let n = corners.len();
    for k in 0..n {
        let (a, b) = (corners[k], corners[(k + 1) % n]);
        if mesh.edge_midpoints.get(&(a.min(b), a.max(b))) == Some(&v) {
            return (value(k) + value((k + 1) % n)) * 0.5;
        }
    }
    (0..n).map(value).sum::<Rgb>() / n as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Stored corners come back within half a step of the element's
    /// largest value (1.53 · 10⁻⁵ of it), signs and zeros kept; values
    /// beyond `f32`'s range stay finite, and 28 bytes hold an element's
    /// corners.
    #[test]
    fn stored_corners_come_back_within_half_a_step_of_their_largest() {
        let mut random = crate::lighting::SampleStream::new(5, 0);
        for _ in 0..1000 {
            let magnitude = 10f64.powf(12.0 * random.next_f64() - 6.0);
            let mut value = || magnitude * (2.0 * random.next_f64() - 0.5);
            let corners = [(); 4].map(|()| Rgb::new(value(), value(), value()));
            let largest = corners
                .iter()
                .map(|c| c.abs().max_element())
                .fold(0.0, f64::max);
            let back = unpacked(&packed(corners));
            for (c, b) in corners.iter().zip(&back) {
                let error = (*c - *b).abs().max_element();
                assert!(error <= 1.54e-5 * largest, "{c:?} {b:?}");
                for (x, y) in c.to_array().into_iter().zip(b.to_array()) {
                    assert!(x * y >= 0.0 || x.abs() <= 3.1e-5 * largest, "{x} {y}");
                }
            }
        }
        assert_eq!(unpacked(&packed([Rgb::ZERO; 4])), [Rgb::ZERO; 4]);
        let huge = unpacked(&packed([Rgb::splat(1e39), Rgb::ZERO, Rgb::ZERO, Rgb::ZERO]));
        assert!(huge[0].is_finite() && huge[0].r > 3e38 && huge[1] == Rgb::ZERO);
        assert_eq!(std::mem::size_of::<PackedCorners>(), 28);
    }
}
