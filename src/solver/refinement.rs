//! Adaptive element refinement: which elements to split while solving.
//!
//! An element is split when the radiosities at the vertices of its outline
//! (its corners and the hanging vertices finer neighbours put on its edges)
//! differ by more than a fraction of its brightness: linear interpolation
//! across it would then miss a shadow edge or a highlight. Its children's new
//! vertices gather everything already shot (see `Solver::refine`), so they
//! hold values as exact as the old vertices', never interpolated guesses.
//!
//! # References
//! M. F. Cohen, D. P. Greenberg, D. S. Immel, P. J. Brock, "An Efficient
//! Radiosity Approach for Realistic Image Synthesis", IEEE CG&A 1986;
//! M. F. Cohen, J. R. Wallace, *Radiosity and Realistic Image Synthesis*,
//! 1993, §8.3 (adaptive subdivision on vertex differences).

use crate::mesh::Mesh;
use crate::scene::Rgb;

/// When and how far elements are split during an adaptive solve.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct RefinementSettings {
    /// Split an element when its vertices' radiosities (sum of channels)
    /// span more than `threshold` times its mean radiosity.
    pub threshold: f64,
    /// Differences in elements darker than `floor` times the scene's mean
    /// radiosity are measured against that floor instead: deep shadows are
    /// not refined for differences nobody can see.
    pub floor: f64,
    /// Smallest element edge after splitting, as a fraction of the starting
    /// element edge (`1/8`: three levels).
    pub min_edge_fraction: f64,
    /// The starting mesh's element edge, as a multiple of the square
    /// mesher's: adaptive meshing starts coarser and refines where needed.
    pub coarsening: f64,
    /// Stop splitting once the mesh holds this many vertices.
    pub max_vertices: usize,
}

impl Default for RefinementSettings {
    fn default() -> Self {
        RefinementSettings {
            threshold: 0.2,
            floor: 0.05,
            min_edge_fraction: 0.125,
            coarsening: 2.0,
            max_vertices: 2_000_000,
        }
    }
}

impl RefinementSettings {
    /// Checks every field is in range.
    pub fn validate(&self) -> crate::Result<()> {
        let invalid = |name: &str, message: String| {
            Err(crate::Error::InvalidSetting {
                name: name.into(),
                message,
            })
        };
        if !(self.threshold > 0.0 && self.threshold.is_finite()) {
            return invalid(
                "refine-threshold",
                format!("{} must be a positive number", self.threshold),
            );
        }
        if !(self.floor >= 0.0 && self.floor.is_finite()) {
            return invalid("refine-floor", format!("{} must be ≥ 0", self.floor));
        }
        if !(self.min_edge_fraction > 0.0 && self.min_edge_fraction <= 1.0) {
            return invalid(
                "min-edge-fraction",
                format!("{} must lie in (0, 1]", self.min_edge_fraction),
            );
        }
        if !(self.coarsening >= 1.0 && self.coarsening.is_finite()) {
            return invalid("coarsening", format!("{} must be ≥ 1", self.coarsening));
        }
        Ok(())
    }
}

/// The elements to split now: those whose outline's radiosities span more
/// than the threshold, and those with more than one hanging vertex on an
/// edge (a neighbour two levels finer), so that neighbours differ by at most
/// one level and Gouraud shading stays smooth across them. Elements already
/// as small as `min_edge` are left.
#[must_use]
pub fn elements_to_split(
    mesh: &Mesh,
    radiosity: &[Rgb],
    settings: &RefinementSettings,
    min_edge: f64,
) -> Vec<usize> {
    let brightness = |v: u32| radiosity[v as usize].element_sum();
    let (weighted, area) = mesh.elements.iter().fold((0.0, 0.0), |(w, a), e| {
        let corners = e.corners();
        let mean = corners.iter().map(|&v| brightness(v)).sum::<f64>() / corners.len() as f64;
        (w + mean * e.area, a + e.area)
    });
    let floor = settings.floor * if area > 0.0 { weighted / area } else { 0.0 };
    let mut outline = Vec::new();
    (0..mesh.elements.len())
        .filter(|&index| {
            let element = &mesh.elements[index];
            let corners = element.corners();
            let position = |v: u32| mesh.vertices[v as usize].position;
            let longest = (0..corners.len())
                .map(|k| position(corners[k]).distance(position(corners[(k + 1) % corners.len()])))
                .fold(0.0, f64::max);
            if longest < 2.0 * min_edge {
                return false;
            }
            outline.clear();
            outline.extend(mesh.element_outline(element));
            if more_than_one_per_edge(mesh, corners) {
                return true;
            }
            let (low, high) = outline
                .iter()
                .map(|&v| brightness(v))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), b| {
                    (lo.min(b), hi.max(b))
                });
            let mean = corners.iter().map(|&v| brightness(v)).sum::<f64>() / corners.len() as f64;
            high - low > settings.threshold * mean.max(floor) && high - low > 0.0
        })
        .collect()
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
