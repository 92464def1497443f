//! Hierarchical reception: a dim reflected shot is gathered at a few
//! vertices of each patch it can barely light, and interpolated to the
//! patch's other vertices.
//!
//! Progressive shooting gathers every shot at every vertex that faces it,
//! so the thousandth shot, from a book's spine, costs as much as the first
//! from a lamp. Hanrahan, Salzman & Aupperle's "BF refinement" receives an
//! interaction at the coarsest level whose error it bounds by the shooter's
//! radiosity times the form factor. Here the levels are the patch and its
//! vertices: a shot from patch j of power P lands on receiving patch p at
//! an irradiance of at most
//!
//! ```text
//!   H ≤ P c_r c_s / (π d²),
//! ```
//!
//! since each point-to-point kernel cosθ_r cosθ_s / (π r²) is at most that
//! over P: d is a lower bound on the distance between the two cells (the
//! gap between their bounding spheres, or either's height above the other's
//! plane), and c_r bounds cosθ_r at any point of p by j's greatest height
//! above p's plane over d (at most 1; c_s likewise, with the cells'
//! roles swapped). A vertex of p whose irradiance so far is at least that
//! bound over ε, channel by channel, may take the shot interpolated from p's sample
//! vertices (those nearest its corners and its centre, linearly over the
//! fan of triangles they span), at an error of at most a fraction ε of the
//! light already there. The solver scales that interpolation by the
//! shooter's point kernel at the vertex over the kernel interpolated the
//! same way (`curvature_factor` in `solver/shot/coarse_reception.rs`), so that it
//! bends as the shot does. Two more conditions keep the error from adding up
//! over hundreds of shots in one direction:
//!
//! - every patch the vertex lies on must allow it, and it must be no
//!   patch's sample;
//! - the samples it is interpolated from must have received between half
//!   and twice what it has ([`SAMPLE_AGREEMENT`]), so a sample behind an
//!   object or under one does not lend its shade, shot after shot, to the
//!   lit vertices around it.
//!
//! An unlit vertex (an umbra of direct light, a crack) gathers until it has
//! some light. Emitters' shots are always gathered at every vertex: they
//! draw the sharp shadows. A patch with too few vertices for a fan (a
//! book's spine) samples at its centre vertex alone, whose value the
//! others take. The ledger is untouched: elements take their power from the
//! vertices' irradiance, interpolated or gathered. (In a closed zone the
//! elements' powers are then scaled to land whole, by up to
//! `LANDING_SCALE`'s upper end, and a shooter's unshot field can be
//! negative in places after adaptive refinement's corrections; the bound
//! holds up to those factors.)
//!
//! # References
//! P. Hanrahan, D. Salzman, L. Aupperle, "A Rapid Hierarchical Radiosity
//! Algorithm", SIGGRAPH 1991; N. Holzschuch, F. Sillion, "An exhaustive
//! error-bounding algorithm for hierarchical radiosity", Computer Graphics
//! Forum 1998.

use glam::DVec3;
use rayon::prelude::*;

use crate::mesh::{Cell, Mesh};
use crate::rgb::Rgb;
use crate::solver::light::vertex_irradiance::VertexIrradiance;
use crate::solver::shot::sample_fan::{SampleFan, SampleWeights};

/// An interpolated vertex's samples must have received at least this
/// share of its irradiance so far, and it at least this share of theirs.
const SAMPLE_AGREEMENT: f64 = 0.5;

/// Vertices planned per parallel task.
const PLAN_CHUNK: usize = 4096;

/// What each patch samples a dim shot at, and how every other vertex is
/// interpolated from those samples.
#[derive(Clone, Debug, Default)]
pub(crate) struct PatchReception {
    /// Per patch: the centre and radius of a sphere that holds its cell.
    spheres: Vec<(DVec3, f64)>,
    /// Per patch: its cell.
    cells: Vec<Cell>,
    /// Per patch: a point of its plane and its unit normal (None for a
    /// degenerate cell).
    planes: Vec<Option<Plane>>,
    /// Per patch: whether it has samples (two or more vertices).
    has_samples: Vec<bool>,
    /// Per vertex: how it is interpolated; None for a sample of any patch,
    /// a vertex of no patch, or one of a patch too small to sample (one
    /// vertex), which always gather.
    vertices: Vec<Option<VertexInterpolation>>,
    /// The second and further patches of vertices on several.
    other_patches: Vec<u32>,
    /// The mesh's vertex and element counts when this was built.
    built_for: (usize, usize),
}

/// How a vertex that is no sample is interpolated.
#[derive(Clone, Copy, Debug)]
struct VertexInterpolation {
    /// Its first patch, whose samples it is interpolated from.
    patch: u32,
    /// Its other patches: `other_patches[others.0..others.1]`.
    others: (u32, u32),
    weights: SampleWeights,
}

/// Which vertices gather a shot, and which are interpolated.
#[derive(Clone, Debug, Default)]
pub(crate) struct ReceptionPlan {
    /// Vertices that gather the shot, in the order given.
    pub gathered: Vec<u32>,
    /// Vertices interpolated from gathered ones (their weights are
    /// [`PatchReception::weights_of`]).
    pub interpolated: Vec<u32>,
}

impl PatchReception {
    /// Samples and weights of every patch of `mesh`, unless already built
    /// for it (a mesh of its size, not invalidated since).
    pub(crate) fn refresh(&mut self, mesh: &Mesh) {
        let size = (mesh.vertices.len(), mesh.elements.len());
        if size != self.built_for || self.cells.len() != mesh.patches.len() {
            *self = PatchReception::new(mesh);
        }
    }

    /// Marks the samples stale: the mesh changed (adaptive refinement).
    pub(crate) fn invalidate(&mut self) {
        self.cells.clear();
    }

    fn new(mesh: &Mesh) -> PatchReception {
        let mut reception = PatchReception {
            built_for: (mesh.vertices.len(), mesh.elements.len()),
            ..PatchReception::default()
        };
        // Per vertex: its patches, and its first patch's weights unless it
        // is a sample of some patch.
        let mut patches_of: Vec<Vec<u32>> = vec![Vec::new(); mesh.vertices.len()];
        let mut weights_of: Vec<Option<SampleWeights>> = vec![None; mesh.vertices.len()];
        let mut is_sample = vec![false; mesh.vertices.len()];
        let mut seen = vec![u32::MAX; mesh.vertices.len()];
        let mut vertices = Vec::new();
        for (p, patch) in mesh.patches.iter().enumerate() {
            vertices.clear();
            for &e in &patch.elements {
                for &v in mesh.elements[e as usize].corners() {
                    if seen[v as usize] != p as u32 {
                        seen[v as usize] = p as u32;
                        vertices.push(v);
                    }
                }
            }
            let cell = &patch.cell;
            let centre = cell.centre();
            let radius = cell
                .polygon()
                .iter()
                .map(|c| c.distance(centre))
                .fold(0.0, f64::max);
            reception.spheres.push((centre, radius));
            reception.cells.push(*cell);
            reception.planes.push(plane_of(cell));
            let interpolation = SampleFan::new(mesh, cell, &vertices);
            reception.has_samples.push(interpolation.is_some());
            for &v in &vertices {
                patches_of[v as usize].push(p as u32);
                match interpolation.as_ref().map(|i| i.weights(mesh, v)) {
                    Some(Some(weights)) => {
                        weights_of[v as usize].get_or_insert(weights);
                    }
                    _ => is_sample[v as usize] = true,
                }
            }
        }
        for (v, patches) in patches_of.into_iter().enumerate() {
            let interpolation = match (patches.split_first(), weights_of[v]) {
                (Some((&patch, others)), Some(weights)) if !is_sample[v] => {
                    let start = reception.other_patches.len() as u32;
                    reception.other_patches.extend_from_slice(others);
                    let end = reception.other_patches.len() as u32;
                    Some(VertexInterpolation {
                        patch,
                        others: (start, end),
                        weights,
                    })
                }
                _ => None,
            };
            reception.vertices.push(interpolation);
        }
        reception
    }

    /// The irradiance a vertex of patch `p` must have received so far for
    /// a shot of `power` (W per channel) from patch `j` to be interpolated
    /// there at relative error `fraction`: the shot's bound P c_r c_s / (π d²)
    /// over `fraction`; infinite when `p` has no samples or may touch `j`.
    pub(crate) fn interpolation_threshold(
        &self,
        p: usize,
        j: usize,
        power: Rgb,
        fraction: f64,
    ) -> Rgb {
        let never = Rgb::splat(f64::INFINITY);
        if !self.has_samples[p] || p == j || fraction <= 0.0 {
            return never;
        }
        let (d, cosines) = self.shot_geometry(p, j);
        if d <= 0.0 {
            return never;
        }
        // A channel of negative unshot power (adaptive refinement's
        // corrections can leave one) reaches as far as its magnitude.
        let needed = power.abs() * cosines / (std::f64::consts::PI * d * d * fraction);
        if needed.r.is_nan() || needed.g.is_nan() || needed.b.is_nan() {
            return never;
        }
        needed
    }

    /// For patches `p` and `j`: a lower bound d on the distance between
    /// any point of one and any point of the other (the gap between their
    /// bounding spheres, or the height of either cell above the other's
    /// plane, whichever is greater: a point of a cell is at least as far
    /// from another cell as from that cell's plane), and a bound on the
    /// product of the cosines at the two ends of any segment between them
    /// (each at most the other cell's greatest height above the cell's
    /// plane over d, and at most 1).
    fn shot_geometry(&self, p: usize, j: usize) -> (f64, f64) {
        let ((cp, rp), (cj, rj)) = (self.spheres[p], self.spheres[j]);
        let spheres = cp.distance(cj) - rp - rj;
        let j_over_p = self.planes[p].map(|plane| heights_above(&self.cells[j], plane));
        let p_over_j = self.planes[j].map(|plane| heights_above(&self.cells[p], plane));
        let d = spheres.max(gap(j_over_p)).max(gap(p_over_j));
        let cosine = |heights: Option<(f64, f64)>| match heights {
            Some((low, high)) => (low.abs().max(high.abs()) / d).min(1.0),
            None => 1.0,
        };
        (d, cosine(j_over_p) * cosine(p_over_j))
    }

    /// Which of `vertices` gather a shot and which are interpolated, given
    /// each patch's [`PatchReception::interpolation_threshold`]
    /// (`thresholds[p]`) and the irradiance each vertex has received so far
    /// (see the module's documentation for the conditions). In parallel.
    pub(crate) fn plan(
        &self,
        vertices: &[u32],
        thresholds: &[Rgb],
        irradiance: &VertexIrradiance,
        plan: &mut ReceptionPlan,
    ) {
        plan.gathered.clear();
        plan.interpolated.clear();
        let chunks: Vec<ReceptionPlan> = vertices
            .par_chunks(PLAN_CHUNK)
            .map(|vertices| {
                let mut chunk = ReceptionPlan::default();
                for &v in vertices {
                    if self.may_interpolate(v, thresholds, irradiance) {
                        chunk.interpolated.push(v);
                    } else {
                        chunk.gathered.push(v);
                    }
                }
                chunk
            })
            .collect();
        for chunk in chunks {
            plan.gathered.extend(chunk.gathered);
            plan.interpolated.extend(chunk.interpolated);
        }
    }

    /// The samples vertex `v` is interpolated from and their weights (None
    /// for a vertex that always gathers).
    pub(crate) fn weights_of(&self, v: u32) -> Option<SampleWeights> {
        self.vertices[v as usize].as_ref().map(|i| i.weights)
    }

    /// Whether vertex `v` may be interpolated: it is no sample, its
    /// irradiance reaches the threshold of every patch it lies on, and its
    /// samples agree with it ([`SAMPLE_AGREEMENT`]).
    fn may_interpolate(&self, v: u32, thresholds: &[Rgb], irradiance: &VertexIrradiance) -> bool {
        let Some(interpolation) = self.vertices[v as usize].as_ref() else {
            return false;
        };
        let h = irradiance.at(v as usize);
        let reaches = |p: u32| {
            let t = thresholds[p as usize];
            h.r >= t.r && h.g >= t.g && h.b >= t.b
        };
        let (start, end) = interpolation.others;
        let others = &self.other_patches[start as usize..end as usize];
        if !reaches(interpolation.patch) || !others.iter().all(|&p| reaches(p)) {
            return false;
        }
        let hv = h.element_sum();
        let agrees = |&(s, w): &(u32, f32)| {
            let hs = irradiance.at(s as usize).element_sum();
            w == 0.0 || (hs >= SAMPLE_AGREEMENT * hv && hv >= SAMPLE_AGREEMENT * hs)
        };
        hv > 0.0 && interpolation.weights.iter().all(agrees)
    }
}

/// A plane: a point of it and its unit normal.
#[derive(Clone, Copy, Debug)]
struct Plane {
    origin: DVec3,
    normal: DVec3,
}

/// A point of a cell's plane and its unit normal (along its corners'
/// winding); None for a degenerate cell.
fn plane_of(cell: &Cell) -> Option<Plane> {
    let [a, b, c, _] = cell.corners;
    let normal = (b - a).cross(c - a).normalize_or_zero();
    (normal != DVec3::ZERO).then_some(Plane { origin: a, normal })
}

/// The least and the greatest height of `cell`'s corners above `plane`.
fn heights_above(cell: &Cell, plane: Plane) -> (f64, f64) {
    let Plane { origin, normal } = plane;
    let heights = cell.polygon().iter().map(|&c| normal.dot(c - origin));
    heights.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), h| {
        (lo.min(h), hi.max(h))
    })
}

/// The least distance from a cell to a plane, from the range of its
/// corners' heights above it: 0 when they lie on both sides (or unknown).
fn gap(heights: Option<(f64, f64)>) -> f64 {
    match heights {
        Some((low, _)) if low > 0.0 => low,
        Some((_, high)) if high < 0.0 => -high,
        _ => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{SquareMeshSettings, mesh_square};
    use std::f64::consts::PI;

    /// The Cornell box on its default square mesh (blocks standing on the
    /// floor, so some patches lose corners under them).
    fn cornell_mesh() -> Mesh {
        let scene = crate::load_scene("cornell").expect("built in").scene;
        mesh_square(&scene, &SquareMeshSettings::for_scene(&scene))
    }

    fn linear(x: DVec3) -> f64 {
        1.0 + 0.3 * x.x - 0.2 * x.y + 0.7 * x.z
    }

    #[test]
    fn interpolation_weights_are_convex_and_reproduce_a_linear_field() {
        let mesh = cornell_mesh();
        let reception = PatchReception::new(&mesh);
        let (mut interpolated, mut exact) = (0, 0);
        for (v, interpolation) in reception.vertices.iter().enumerate() {
            let Some(interpolation) = interpolation else {
                continue;
            };
            interpolated += 1;
            let weights = interpolation.weights;
            let sum: f64 = weights.iter().map(|w| f64::from(w.1)).sum();
            assert!((sum - 1.0).abs() < 1e-6, "vertex {v}: weights sum to {sum}");
            let patch = &mesh.patches[interpolation.patch as usize];
            for &(s, w) in &weights {
                assert!((0.0..=1.0).contains(&w), "vertex {v}: weight {w}");
                assert!(s as usize != v, "vertex {v} is its own sample");
                assert_eq!(mesh.vertices[s as usize].surface, patch.surface);
            }
            let at = |v: u32| linear(mesh.vertices[v as usize].receiver_position());
            let value: f64 = weights.iter().map(|&(s, w)| f64::from(w) * at(s)).sum();
            // Exact up to the weights' single precision.
            if (value - at(v as u32)).abs() < 1e-6 * value.abs().max(1.0) {
                exact += 1;
            }
        }
        println!("{exact} of {interpolated} interpolated vertices exact on a linear field");
        assert!(interpolated > mesh.vertices.len() / 2, "{interpolated}");
        // Only vertices outside their patch's fan (beside a block's foot,
        // where a corner's nearest vertex moved) take a clamped value.
        assert!(
            exact as f64 > 0.95 * interpolated as f64,
            "{exact} of {interpolated}"
        );
    }

    /// A plan with the given threshold on every patch, every vertex having
    /// received 1 W/m² except those listed with their own.
    fn plan_with(mesh: &Mesh, threshold: f64, irradiance_of: &[(u32, f64)]) -> ReceptionPlan {
        let reception = PatchReception::new(mesh);
        let thresholds = vec![Rgb::splat(threshold); mesh.patches.len()];
        let mut values = vec![Rgb::ONE; mesh.vertices.len()];
        for &(v, h) in irradiance_of {
            values[v as usize] = Rgb::splat(h);
        }
        let vertices: Vec<u32> = (0..mesh.vertices.len() as u32).collect();
        let mut irradiance = VertexIrradiance::zeros(mesh.vertices.len());
        irradiance.add_at(&vertices, &values);
        let mut plan = ReceptionPlan::default();
        reception.plan(&vertices, &thresholds, &irradiance, &mut plan);
        assert_eq!(
            plan.gathered.len() + plan.interpolated.len(),
            mesh.vertices.len()
        );
        plan
    }

    #[test]
    fn a_vertex_is_interpolated_only_above_its_threshold_and_beside_agreeing_samples() {
        let mesh = cornell_mesh();
        let reception = PatchReception::new(&mesh);
        // Above every threshold, every vertex that is no sample interpolates.
        let all = plan_with(&mesh, 0.5, &[]);
        let expected = reception.vertices.iter().filter(|i| i.is_some()).count();
        assert_eq!(all.interpolated.len(), expected);
        for &v in &all.gathered {
            assert!(reception.vertices[v as usize].is_none());
        }
        // Below them none does.
        assert!(plan_with(&mesh, 2.0, &[]).interpolated.is_empty());
        let v = all.interpolated[all.interpolated.len() / 2];
        let weights = reception.weights_of(v).expect("interpolated");
        // A vertex below its threshold gathers, though its samples agree.
        let dim = plan_with(&mesh, 0.7, &[(v, 0.6)]);
        assert!(dim.gathered.contains(&v));
        // An unlit vertex gathers whatever the threshold.
        let unlit = plan_with(&mesh, 0.0, &[(v, 0.0)]);
        assert!(unlit.gathered.contains(&v));
        assert_eq!(unlit.interpolated.len(), expected - 1);
        // So does a lit one whose sample lies in shade.
        let sample = weights.iter().find(|w| w.1 > 0.0).expect("a weight").0;
        let shaded = plan_with(&mesh, 0.0, &[(sample, 0.3)]);
        assert!(shaded.gathered.contains(&v));
    }

    #[test]
    fn the_shot_bound_holds_between_any_two_points_of_the_cells() {
        // d never exceeds the cells' distance, and the point kernel
        // cosθ_r cosθ_s / (π r²) between any two of their points never
        // exceeds the threshold's bound, cos_r cos_s / (π d²).
        let mesh = cornell_mesh();
        let reception = PatchReception::new(&mesh);
        let points = |cell: &Cell| {
            let mut points = Vec::new();
            for i in 0..=4 {
                for j in 0..=4 {
                    points.push(cell.point(f64::from(i) / 4.0, f64::from(j) / 4.0));
                }
            }
            points
        };
        let normal = |cell: &Cell| {
            let [a, b, c, _] = cell.corners;
            (b - a).cross(c - a).normalize()
        };
        let mut tilted = 0;
        for p in (0..mesh.patches.len()).step_by(3) {
            for j in (0..mesh.patches.len()).step_by(7) {
                let (cp, cj) = (&mesh.patches[p].cell, &mesh.patches[j].cell);
                let (d, cosines) = reception.shot_geometry(p, j);
                if d <= 0.0 {
                    continue;
                }
                let bound = cosines / (PI * d * d);
                if bound < 1.0 / (PI * d * d) {
                    tilted += 1;
                }
                let (np, nj) = (normal(cp), normal(cj));
                for x in points(cp) {
                    for y in points(cj) {
                        let r = y - x;
                        assert!(
                            d <= r.length() + 1e-9,
                            "patches {p}, {j}: d {d} > {}",
                            r.length()
                        );
                        let r2 = r.length_squared();
                        if r2 == 0.0 {
                            continue;
                        }
                        let kernel = np.dot(r).abs() * nj.dot(r).abs() / (PI * r2 * r2);
                        assert!(
                            kernel <= bound * (1.0 + 1e-9) + 1e-9 / (PI * d * d),
                            "patches {p}, {j}: kernel {kernel} > bound {bound}"
                        );
                    }
                }
            }
        }
        // The cosines tighten the bound for many pairs.
        assert!(tilted > 100, "{tilted}");
    }
}
