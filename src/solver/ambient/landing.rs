//! Where a vertex ray lands: its point on the patch's cell, kept to a
//! [`LANDING_STEPS`]th of its side ([`Landing`]), and the element under
//! that point with the point's coordinates in it ([`LandingElement`]).

use glam::DVec2;

use crate::mesh::Mesh;
use crate::rgb::Rgb;
use crate::solver::light::cell_coordinates::interpolated;

/// The element a vertex ray landed on and the landing point's coordinates
/// (s, t) in it ([`crate::mesh::Cell::point`] of the element's cell), or
/// none: found once per image, then read by the first gather and every
/// sweep (`solver/ambient/sweeps.rs`) at the cost of an interpolation.
/// Eight bytes a ray: the coordinates are kept to 1/65,535 of the element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LandingElement {
    element: u32,
    st: [u16; 2],
}

impl LandingElement {
    /// No element: the ray missed, or no element lies under its point.
    pub(crate) const NONE: LandingElement = LandingElement {
        element: u32::MAX,
        st: [0; 2],
    };

    /// The point at `st` = (s, t) of element `element`, each coordinate in
    /// [0, 1].
    pub(crate) fn new(element: u32, st: DVec2) -> LandingElement {
        let step = |w: f64| (w.clamp(0.0, 1.0) * f64::from(u16::MAX)).round() as u16;
        LandingElement {
            element,
            st: [step(st.x), step(st.y)],
        }
    }

    /// The element's index, or `None` for [`LandingElement::NONE`].
    pub(crate) fn element(self) -> Option<usize> {
        (self != LandingElement::NONE).then_some(self.element as usize)
    }

    /// A value given at the element's corners (in [`crate::mesh::Element::corners`]
    /// order) interpolated at the point, linearly over a triangle and
    /// bilinearly over a quad; `None` for [`LandingElement::NONE`].
    /// `corners(e)` gives element e's corner values.
    pub(crate) fn value(self, mesh: &Mesh, corners: impl Fn(usize) -> [Rgb; 4]) -> Option<Rgb> {
        let e = self.element as usize;
        let element = mesh.elements.get(e)?;
        let coordinate = |k: u16| f64::from(k) / f64::from(u16::MAX);
        let st = (coordinate(self.st[0]), coordinate(self.st[1]));
        Some(interpolated(
            corners(e),
            element.is_triangle(),
            glam::DVec2::from(st),
        ))
    }
}

/// Steps per side of a patch's cell to which a vertex ray's landing point
/// is kept: 4 mm on a metre-wide patch. Read at the centre of a coarser
/// lattice's cell instead, a ray that landed on a cell's lit part while
/// its centre lay under an object standing on the patch (a book on a
/// shelf, a screen's foot on a desk) would read nothing there.
pub(crate) const LANDING_STEPS: u8 = u8::MAX;

/// A vertex ray's landing point on its patch's cell: its parameters (s, t)
/// each as the step k of [`LANDING_STEPS`] that holds it (read back at the
/// step's middle, (k + ½) / steps), or [`Landing::NOWHERE`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Landing(pub(crate) [u8; 2]);

impl Landing {
    /// No point: the ray missed, or landed off its patch's cell.
    pub(crate) const NOWHERE: Landing = Landing([LANDING_STEPS; 2]);

    /// The landing at parameters `st` = (s, t) of a cell, each in [0, 1].
    pub(crate) fn at(st: DVec2) -> Landing {
        let last = f64::from(LANDING_STEPS - 1);
        let step = |w: f64| (w * f64::from(LANDING_STEPS)).clamp(0.0, last) as u8;
        Landing([step(st.x), step(st.y)])
    }

    /// The parameters (s, t) it stands for, or `None` for
    /// [`Landing::NOWHERE`].
    pub(crate) fn parameters(self) -> Option<DVec2> {
        let middle = |k: u8| (f64::from(k) + 0.5) / f64::from(LANDING_STEPS);
        (self != Landing::NOWHERE).then(|| DVec2::new(middle(self.0[0]), middle(self.0[1])))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A landing element reads its corners' values at its point, linearly
    /// over a triangle and bilinearly over a quad; no element reads none.
    #[test]
    fn a_landing_element_interpolates_its_corners() {
        let mut mesh = Mesh::default();
        for is_triangle in [false, true] {
            mesh.elements.push(crate::mesh::Element {
                vertices: [0, 1, 2, if is_triangle { 2 } else { 3 }],
                surface: crate::scene::SurfaceId::new(0),
                patch: 0,
                area: 1.0,
            });
        }
        let corners = |_| [1.0, 2.0, 4.0, 8.0].map(Rgb::splat);
        let quad = LandingElement::new(0, DVec2::new(0.25, 0.5)).value(&mesh, corners);
        // (1 − s)(1 − t)·1 + s(1 − t)·2 + s t·4 + (1 − s) t·8
        let expected = 0.375 + 0.25 + 0.5 + 3.0;
        // The coordinates are kept to 1/65,535.
        assert!((quad.unwrap().r - expected).abs() < 1e-3, "{quad:?}");
        let triangle = LandingElement::new(1, DVec2::new(0.25, 0.5)).value(&mesh, corners);
        assert!((triangle.unwrap().r - (0.25 + 0.5 + 2.0)).abs() < 1e-3);
        assert_eq!(LandingElement::NONE.value(&mesh, corners), None);
    }
}
