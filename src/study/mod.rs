//! Studies of the meshers: contour meshes against square meshes on the
//! receivers lit by a dominant small emitter (vertices and interpolation
//! error), and the pictures that show them: log–log plots
//! ([`write_loglog_plot`]) and meshes side by side ([`write_mesh_panels`]),
//! which take plain data and draw text with the bundled DejaVu Sans
//! (`assets/fonts`). Nothing else in isorad imports this module.
//!
//! For each receiver, every mesh gets the exact direct radiosity of the
//! dominant light at its vertices (visibility included), and its
//! piecewise-linear interpolation is compared with the exact value on a
//! dense grid of points inside the receiver (DESIGN.md, "How the error of a
//! mesh is measured"). The vertex values are exact, so the error is the
//! mesh's alone.

mod compare;
mod mesh_panels;
mod plot;
mod records;

pub use compare::compare_receiver;

pub use mesh_panels::{MeshPanel, write_mesh_panels};
pub use plot::{Series, write_loglog_plot};
pub use records::{MeshRecord, MeshSpec, ReceiverComparison, write_json};

use crate::meshing::MeshSettings;

/// What a comparison meshes and how finely it measures.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct CompareSettings {
    /// N of the square N × N meshes.
    pub square_sizes: Vec<usize>,
    /// (D, K) of the fixed contour meshes.
    pub contour_sizes: Vec<(usize, usize)>,
    /// Relative errors, in thousandths, that contour meshes are refined to
    /// (`ContourSettings::max_relative_error`).
    pub contour_errors_per_mille: Vec<u32>,
    /// The error is measured on a `grid` × `grid` lattice over the receiver.
    pub grid: usize,
    /// Shadow rays per light polygon for the exact field's visibility.
    pub shadow_rays: usize,
    /// The contour meshes refined to an error (radial and level lines)
    /// follow the receiver's shadow boundaries, as the renderer's meshes do,
    /// and the fixed D × K layouts are measured a second time with them
    /// ([`MeshSpec::ShadowContour`]) where the receiver has any (true); the
    /// fixed layouts themselves are the seed's, without them.
    pub shadow_boundaries: bool,
    /// Vertex budgets of the greedy-insertion meshes
    /// ([`MeshSpec::Greedy`]), on the field sampled with visibility.
    pub greedy_vertices: Vec<usize>,
    /// Lattice cells along the receiver's longer side on which the
    /// greedy-insertion meshes sample the field (a lattice apart from the
    /// error grid's).
    pub greedy_lattice: usize,
    /// The mesh settings the renderer would use (a scene file's `[mesh]`):
    /// the element spacing the level lines fill gaps to and the shadow
    /// boundaries are merged at.
    pub mesh: MeshSettings,
}

impl Default for CompareSettings {
    /// Square 5…40; contour the seed's sizes (10×3 … 80×12), the
    /// balanced D = 2K sizes that do best per vertex, and contour meshes
    /// refined to 8, 4, 2, 1 and 0.5 %; a 400² grid.
    fn default() -> Self {
        CompareSettings {
            square_sizes: vec![5, 10, 20, 30, 40],
            contour_sizes: vec![
                (10, 3),
                (20, 5),
                (40, 8),
                (80, 12),
                (8, 4),
                (12, 6),
                (16, 8),
                (24, 12),
                (32, 16),
            ],
            contour_errors_per_mille: vec![80, 40, 20, 10, 5],
            grid: 400,
            shadow_rays: 16,
            shadow_boundaries: true,
            greedy_vertices: vec![50, 100, 200, 300, 500, 800],
            greedy_lattice: 192,
            mesh: MeshSettings::default(),
        }
    }
}

/// The seed paper's Figure 5 trio and the meshes isorad renders with,
/// where measured: square 10×10 | contour 20×5 (the seed's) |
/// shadow-aware contour 20×5 | contour refined to 1 % | level lines to
/// 1 % | greedy insertion to 300 vertices | square 30×30, with their exact
/// vertex values.
#[must_use]
pub fn panels_for_figure(comparison: &ReceiverComparison) -> Vec<MeshPanel> {
    [
        MeshSpec::Square { n: 10 },
        MeshSpec::Contour {
            directions: 20,
            levels: 5,
        },
        MeshSpec::ShadowContour {
            directions: 20,
            levels: 5,
        },
        MeshSpec::ContourToError { per_mille: 10 },
        MeshSpec::LevelLines { per_mille: 10 },
        MeshSpec::Greedy { vertices: 300 },
        MeshSpec::Square { n: 30 },
    ]
    .into_iter()
    .filter_map(|spec| comparison.record(spec))
    .map(|record| MeshPanel {
        title: record.spec.to_string(),
        points: record.triangulation.points.clone(),
        values: record.values.clone(),
        triangles: record.triangulation.triangles.clone(),
        outline: comparison.outline.clone(),
    })
    .collect()
}
