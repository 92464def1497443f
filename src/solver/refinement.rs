//! Adaptive element refinement: which elements to split while solving.
//!
//! After each shot from an emitter (direct light makes the shadow edges and
//! highlights), an element is split where the radiosity gradient jumps
//! across it (see [`elements_to_split`]): linear interpolation across it
//! would miss a shadow edge or a highlight. Its children's new vertices
//! gather everything already shot (see `Solver::refine`), so they hold
//! values as exact as the old vertices', never interpolated guesses; as only
//! emitters have shot while elements split, that gathering is cheap.
//!
//! # References
//! M. F. Cohen, D. P. Greenberg, D. S. Immel, P. J. Brock, "An Efficient
//! Radiosity Approach for Realistic Image Synthesis", IEEE CG&A 1986;
//! M. F. Cohen, J. R. Wallace, *Radiosity and Realistic Image Synthesis*,
//! 1993, §8.3 (adaptive subdivision on vertex differences).

use glam::DVec3;

use crate::mesh::{ElementHierarchy, Mesh};
use crate::meshing::RefinementSettings;
use crate::rgb::Rgb;

/// The elements to split now.
///
/// The indicator is the jump of the radiosity gradient (sum of channels)
/// between an element and its neighbours, in the manner of Zienkiewicz and
/// Zhu's recovery estimator: G_e is the gradient of the element's linear
/// interpolant, G_v the area-weighted mean of G_e over the elements around
/// vertex v, and
///
/// ```text
///   η_e = h_e · max_v |G_e − G_v|      (v over the element's outline)
/// ```
///
/// with h_e its longest edge. On a linear ramp every G_e is the same and η
/// vanishes however steep the ramp, so light that linear interpolation
/// already reproduces is left alone; a shadow edge or a highlight bends the
/// field, G jumps, and the elements there split. An element splits when
/// η_e exceeds `threshold` times its mean radiosity (or the floor), and
/// also when an edge carries more than one hanging vertex (a neighbour two
/// levels finer), so neighbours differ by at most one level. Elements
/// already `max_levels` below the starting mesh are left.
///
/// # References
/// O. C. Zienkiewicz, J. Z. Zhu, "A simple error estimator and adaptive
/// procedure for practical engineering analysis", Int. J. Numer. Methods
/// Eng. 24, 1987.
#[must_use]
pub fn elements_to_split(
    mesh: &Mesh,
    hierarchy: &ElementHierarchy,
    radiosity: &[Rgb],
    settings: &RefinementSettings,
) -> Vec<usize> {
    let brightness = |v: u32| radiosity[v as usize].element_sum();
    let position = |v: u32| mesh.vertices[v as usize].position;
    let gradients: Vec<DVec3> = mesh
        .elements
        .iter()
        .map(|e| element_gradient(e.corners(), &position, &brightness))
        .collect();
    let mut recovered = vec![DVec3::ZERO; mesh.vertices.len()];
    let mut weights = vec![0.0; mesh.vertices.len()];
    let (mut weighted, mut area) = (0.0, 0.0);
    for (element, gradient) in mesh.elements.iter().zip(&gradients) {
        let corners = element.corners();
        for &v in corners {
            recovered[v as usize] += *gradient * element.area;
            weights[v as usize] += element.area;
        }
        weighted += element.corner_mean(brightness) * element.area;
        area += element.area;
    }
    for (g, w) in recovered.iter_mut().zip(&weights) {
        if *w > 0.0 {
            *g /= *w;
        }
    }
    let floor = settings.floor * if area > 0.0 { weighted / area } else { 0.0 };
    (0..mesh.elements.len())
        .filter(|&index| {
            let element = &mesh.elements[index];
            let corners = element.corners();
            if hierarchy.leaf(index).level >= settings.max_levels {
                return false;
            }
            let longest = (0..corners.len())
                .map(|k| position(corners[k]).distance(position(corners[(k + 1) % corners.len()])))
                .fold(0.0, f64::max);
            if more_than_one_per_edge(mesh, corners) {
                return true;
            }
            let jump = mesh
                .element_outline(element)
                .iter()
                .filter(|&&v| weights[v as usize] > 0.0)
                .map(|&v| (gradients[index] - recovered[v as usize]).length())
                .fold(0.0, f64::max);
            let mean = element.corner_mean(brightness);
            longest * jump > settings.threshold * mean.max(floor)
        })
        .collect()
}

/// The gradient of the linear interpolant of `value` over a triangle or a
/// quad (the area-weighted mean of its two triangles' gradients): for a
/// triangle, ∇f = Σ_i f_i (n × e_i) / (2A), e_i the edge opposite vertex i.
fn element_gradient(
    corners: &[u32],
    position: &dyn Fn(u32) -> DVec3,
    value: &dyn Fn(u32) -> f64,
) -> DVec3 {
    let triangle = |a: u32, b: u32, c: u32| {
        let (pa, pb, pc) = (position(a), position(b), position(c));
        let normal2a = (pb - pa).cross(pc - pa);
        let twice_area = normal2a.length();
        if twice_area <= 0.0 {
            return (DVec3::ZERO, 0.0);
        }
        let n = normal2a / twice_area;
        let gradient = (n.cross(pc - pb) * value(a)
            + n.cross(pa - pc) * value(b)
            + n.cross(pb - pa) * value(c))
            / twice_area;
        (gradient, twice_area)
    };
    if corners.len() == 3 {
        return triangle(corners[0], corners[1], corners[2]).0;
    }
    let (g1, a1) = triangle(corners[0], corners[1], corners[2]);
    let (g2, a2) = triangle(corners[0], corners[2], corners[3]);
    if a1 + a2 > 0.0 {
        (g1 * a1 + g2 * a2) / (a1 + a2)
    } else {
        DVec3::ZERO
    }
}

/// Whether some edge of the element carries more than one hanging vertex.
fn more_than_one_per_edge(mesh: &Mesh, corners: &[u32]) -> bool {
    (0..corners.len()).any(|k| {
        let (a, b) = (corners[k], corners[(k + 1) % corners.len()]);
        mesh.edge_midpoints
            .get(&(a.min(b), a.max(b)))
            .is_some_and(|&m| {
                mesh.edge_midpoints.contains_key(&(a.min(m), a.max(m)))
                    || mesh.edge_midpoints.contains_key(&(m.min(b), m.max(b)))
            })
    })
}

/// The adaptive part of a solve: the element hierarchy and how far it may
/// be split.
#[derive(Clone, Debug)]
pub(crate) struct Refiner {
    pub(crate) hierarchy: ElementHierarchy,
    pub(crate) settings: RefinementSettings,
}

impl Refiner {
    /// A refiner whose hierarchy's roots are the mesh's elements.
    pub(crate) fn new(mesh: &Mesh, settings: RefinementSettings) -> Refiner {
        Refiner {
            hierarchy: ElementHierarchy::new(mesh),
            settings,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn element_gradient_of_a_linear_field_is_exact() {
        let points = [
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(2.0, 0.1, 1.0),
            DVec3::new(1.8, 1.5, 1.0),
            DVec3::new(-0.2, 1.2, 1.0),
        ];
        let position = |v: u32| points[v as usize];
        let value = |v: u32| {
            let p = points[v as usize];
            3.0 * p.x - 2.0 * p.y + 1.0
        };
        for corners in [&[0, 1, 2][..], &[0, 1, 2, 3][..], &[1, 2, 3][..]] {
            let g = element_gradient(corners, &position, &value);
            assert!((g - DVec3::new(3.0, -2.0, 0.0)).length() < 1e-12, "{g}");
        }
    }
}
