//! The power an element receives from an emitter's shot: the corners'
//! irradiance, integrated with the curvature of the emitter's unoccluded
//! field.
//!
//! An element's received power is what it reflects into its patch's unshot
//! power, so it carries every later bounce. The corners' mean times the area
//! (the trapezoid rule, which Gouraud shading draws) misses the curvature of
//! the light: it is short by (1/12)(e₁ᵀ H e₁ + e₂ᵀ H e₂) of the mean over a
//! parallelogram with edges e₁, e₂ and Hessian H. Direct light is concave
//! over most of a room's surfaces (it falls off from under and beside each
//! lamp), so the rule loses power on them: a 2 × 2 m floor in 1 m elements
//! 1 m under a 1 m lamp received 13.5 % too little
//! (`tests/it/solver.rs`). Coarse meshes of a room come out dark against a
//! path tracer partly for this; the rest is the reflected light's own
//! curvature and the rows of elements along the room's junctions.
//!
//! The emitter's unoccluded field is known exactly at any point (Lambert's
//! polygon factor), so the received power is corrected by the ratio of that
//! field's quadrature over the element to its trapezoid over the same
//! corners,
//!
//! ```text
//!   P_e = A_e · mean_c(E_c) · Q_e / mean_c(E_u(x_c)),
//!   Q_e = (1 − w) mean_c(E_u(x_c)) + w E_u(x_0),
//! ```
//!
//! E_c the gathered irradiance at the corners (occlusion included), E_u the
//! unoccluded irradiance, x_0 the element's centre, and w = 2/3 for a
//! parallelogram, 3/4 for a triangle: the corners-and-centre rules exact for
//! quadratics. A fully lit element gets that quadrature; a shadowed one
//! keeps its corners' occlusion and gets the field's curvature.
//!
//! # References
//! G. Strang, G. Fix, "An Analysis of the Finite Element Method", 1973,
//! ch. 4.3 (numerical integration); M. F. Cohen, J. R. Wallace, "Radiosity
//! and Realistic Image Synthesis", 1993, ch. 6 (discretisation error).

use glam::DVec3;
use rayon::prelude::*;

use crate::mesh::{Cell, Mesh};
use crate::radiometry::polygon_form_factor;
use crate::rgb::Rgb;
use crate::scene::Scene;
use crate::solver::shot::receivers::ShotReceivers;

/// How far the correction may move an element's power: a factor between
/// 1/`MAX_RATIO` and `MAX_RATIO` (a corner exactly on the emitter's plane
/// sees none of it while the element's interior does).
const MAX_RATIO: f64 = 2.0;

/// The unoccluded form factor from a point with normal `n` to an emitter
/// polygon facing `emitter_normal`: zero behind the emitter's plane.
fn unoccluded_factor(x: DVec3, n: DVec3, emitter: &[DVec3], emitter_normal: DVec3) -> f64 {
    if emitter_normal.dot(x - emitter[0]) <= 0.0 {
        return 0.0;
    }
    polygon_form_factor(x, n, emitter).max(0.0)
}

/// A source of direct light whose unoccluded field is known at any point.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Emitter {
    /// An emitting patch: its cell and the normal of its front.
    Patch { cell: Cell, normal: DVec3 },
    /// Photometric luminaire k of the scene (an emitting body among them):
    /// its unoccluded irradiance
    /// ([`crate::scene::PhotometricLuminaire::unoccluded_irradiance`]).
    Luminaire(usize),
}

impl Emitter {
    /// The unoccluded field at `x` facing `n`: a patch's form factor, or a
    /// luminaire's irradiance's luminance (any measure proportional to
    /// the light serves: only ratios are taken).
    fn unoccluded(&self, scene: &Scene, x: DVec3, n: DVec3) -> f64 {
        match *self {
            Emitter::Patch { cell, normal } => unoccluded_factor(x, n, cell.polygon(), normal),
            Emitter::Luminaire(k) => scene
                .luminaires
                .get(k)
                .map_or(0.0, |l| l.unoccluded_irradiance(x, n).luminance()),
        }
    }
}

/// The power (W) each of the `receivers`' elements receives from the shot
/// of `emitter` (an emitting patch or a luminaire) that gave their
/// vertices `incident` irradiance, each at its place, in the order of the
/// elements (see the module's documentation).
/// The receivers' vertices are the elements' corners (the shot's closed
/// zone, or the whole mesh), in the order of their places: the unoccluded
/// field is read once at each (at its receiver position) and once per
/// element, at its centre, so a shot in one room of a building costs that
/// room alone.
pub(crate) fn emitter_shot_powers(
    scene: &Scene,
    mesh: &Mesh,
    emitter: &Emitter,
    incident: &[Rgb],
    receivers: &ShotReceivers<'_>,
) -> Vec<Rgb> {
    let ShotReceivers {
        vertices,
        elements,
        places,
    } = *receivers;
    let normal = |surface| scene.surface(surface).normal();
    // The unoccluded factor at every vertex, shadowed or not.
    let factors: Vec<f64> = vertices
        .par_iter()
        .map(|&v| {
            let vertex = &mesh.vertices[v as usize];
            let n = normal(vertex.surface);
            emitter.unoccluded(scene, vertex.receiver_position(), n)
        })
        .collect();
    elements
        .par_iter()
        .map(|&e| {
            let element = &mesh.elements[e as usize];
            let trapezoid = element.corner_mean(|v| incident[places.of(v)]) * element.area;
            if trapezoid == Rgb::ZERO {
                return Rgb::ZERO;
            }
            let corners = element.corner_mean(|v| factors[places.of(v)]);
            if corners <= f64::MIN_POSITIVE {
                return trapezoid;
            }
            let centre = mesh.element_cell(element).centre();
            let centre = emitter.unoccluded(scene, centre, normal(element.surface));
            // Corners and centre, exact for a quadratic: (1/3, 2/3) over a
            // parallelogram, (1/4, 3/4) over a triangle.
            let centre_weight = if element.is_triangle() {
                0.75
            } else {
                2.0 / 3.0
            };
            let quadrature = (1.0 - centre_weight) * corners + centre_weight * centre;
            trapezoid * (quadrature / corners).clamp(1.0 / MAX_RATIO, MAX_RATIO)
        })
        .collect()
}
