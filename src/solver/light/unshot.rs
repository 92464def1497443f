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

use glam::DVec3;
use rayon::prelude::*;

use crate::mesh::{Cell, Element, Mesh, Patch};
use crate::scene::Rgb;
use crate::solver::light::element_index::{ElementIndex, padded_box};
use crate::solver::light::indexed_update::par_update_at;
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

/// One element of a shooting patch: its shape, bounding box and ΔB at its corners.
#[derive(Clone, Debug)]
struct FieldElement {
    cell: Cell,
    min: DVec3,
    max: DVec3,
    corners: [Rgb; 4],
}

impl FieldElement {
    fn new(cell: Cell, corners: [Rgb; 4]) -> FieldElement {
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
        Some(interpolated(self.corners, self.cell.is_triangle, st))
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

/// Values at an element's corners at coordinates (s, t) of its cell
/// ([`Cell::point`]): linear over a triangle (the fourth value unused),
/// bilinear over a quad.
pub(crate) fn interpolated([a, b, c, d]: [Rgb; 4], is_triangle: bool, (s, t): (f64, f64)) -> Rgb {
    if is_triangle {
        a * (1.0 - s - t) + b * s + c * t
    } else {
        a * ((1.0 - s) * (1.0 - t)) + b * (s * (1.0 - t)) + c * (s * t) + d * ((1.0 - s) * t)
    }
}

/// The coordinates (s, t) of y in a cell, inverting [`Cell::point`]
/// (Gauss–Newton on the bilinear map; one step is exact for a triangle
/// and for a parallelogram, whose map is affine: the square grid's
/// elements and patches); `None` when y lies outside.
pub(crate) fn cell_coordinates(cell: &Cell, y: DVec3) -> Option<(f64, f64)> {
    const INSIDE: f64 = 1e-9;
    let [a, b, c, d] = cell.corners;
    let (mut s, mut t) = if cell.is_triangle {
        (0.0, 0.0)
    } else {
        (0.5, 0.5)
    };
    let steps = if is_affine(cell) { 1 } else { 8 };
    for _ in 0..steps {
        let (du, dv) = if cell.is_triangle {
            (b - a, c - a)
        } else {
            (
                (b - a) * (1.0 - t) + (c - d) * t,
                (d - a) * (1.0 - s) + (c - b) * s,
            )
        };
        let r = y - cell.point(s, t);
        let (uu, uv, vv) = (du.dot(du), du.dot(dv), dv.dot(dv));
        let det = uu * vv - uv * uv;
        if det.abs() <= f64::MIN_POSITIVE {
            return None;
        }
        let (ru, rv) = (du.dot(r), dv.dot(r));
        let (ds, dt) = ((vv * ru - uv * rv) / det, (uu * rv - uv * ru) / det);
        s += ds;
        t += dt;
        // Converged.
        if ds.abs().max(dt.abs()) < 1e-12 {
            break;
        }
    }
    let inside = if cell.is_triangle {
        s >= -INSIDE && t >= -INSIDE && s + t <= 1.0 + INSIDE
    } else {
        (-INSIDE..=1.0 + INSIDE).contains(&s) && (-INSIDE..=1.0 + INSIDE).contains(&t)
    };
    inside.then_some((s.clamp(0.0, 1.0), t.clamp(0.0, 1.0)))
}

/// Whether a cell's map ([`Cell::point`]) is affine: a triangle, or a
/// quad whose bilinear twist a − b + c − d (the s·t term) vanishes, to
/// 10⁻¹² of its diagonals and the rounding of its corners' coordinates: a
/// parallelogram.
fn is_affine(cell: &Cell) -> bool {
    let [a, b, c, d] = cell.corners;
    let size = (c - a).length().max((d - b).length());
    let magnitude = [a, b, c, d]
        .map(|p| p.abs().max_element())
        .into_iter()
        .fold(0.0, f64::max);
    let tolerance = 1e-12 * size + 16.0 * f64::EPSILON * magnitude;
    cell.is_triangle || (a - b + c - d).length() <= tolerance
}

/// The point of a convex cell nearest y: y's foot on the cell's plane if
/// that lies inside, else the nearest point of its edges.
pub(crate) fn nearest_point_of(cell: &Cell, y: DVec3) -> DVec3 {
    if let Some((s, t)) = cell_coordinates(cell, y) {
        let [a, b, c, _] = cell.corners;
        return if cell.is_triangle {
            a + (b - a) * s + (c - a) * t
        } else {
            cell.point(s, t)
        };
    }
    let polygon = cell.polygon();
    let mut best = (f64::INFINITY, polygon[0]);
    for (k, &p) in polygon.iter().enumerate() {
        let q = polygon[(k + 1) % polygon.len()];
        let edge = q - p;
        let along = (y - p).dot(edge) / edge.length_squared();
        let nearest = p + edge
            * if along.is_finite() {
                along.clamp(0.0, 1.0)
            } else {
                0.0
            };
        let d = (y - nearest).length_squared();
        if d < best.0 {
            best = (d, nearest);
        }
    }
    best.1
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
    fn new(elements: Vec<FieldElement>, power: Rgb, normal: DVec3) -> PatchField {
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
    use crate::scene::{Material, Scene, ShadowCache, SurfaceId, Visibility};
    use crate::solver::settings::FormFactorKernel;
    use crate::solver::shot::shooter::{Receiver, Shooter};

    /// A scene of grey polygons, in order (surface k is polygon k), and
    /// its shadow-ray structure.
    fn grey_scene(polygons: &[&[DVec3]]) -> (Scene, Visibility) {
        let mut scene = Scene::new();
        let grey = scene
            .add_material(Material::diffuse("grey", Rgb::splat(0.5)))
            .unwrap();
        for (k, polygon) in polygons.iter().enumerate() {
            scene.add_polygon(&format!("p{k}"), grey, polygon).unwrap();
        }
        let visibility = Visibility::new(&scene);
        (scene, visibility)
    }

    /// The red irradiance one gather of a shooter gives a receiver at x
    /// (unit `normal`, on `surface`), with jitter `key`.
    fn gather_once(
        shooter: &Shooter,
        visibility: &Visibility,
        (x, normal, surface): (DVec3, DVec3, SurfaceId),
        key: u64,
    ) -> f64 {
        let receiver = Receiver {
            position: x,
            normal,
            surface,
            key,
            clear: false,
            occluders: None,
        };
        shooter
            .gather(
                &receiver,
                3.0,
                7,
                FormFactorKernel::Mixed,
                (visibility, &mut ShadowCache::default()),
            )
            .irradiance
            .r
    }

    /// [`gather_once`] averaged over `trials` jitters.
    fn mean_gather(
        shooter: &Shooter,
        visibility: &Visibility,
        at: (DVec3, DVec3, SurfaceId),
        trials: u64,
    ) -> f64 {
        let total: f64 = (0..trials)
            .map(|key| gather_once(shooter, visibility, at, key))
            .sum();
        total / trials as f64
    }

    #[test]
    fn coordinates_invert_the_cell_map() {
        let quad = Cell::quad(
            DVec3::ZERO,
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(3.0, 2.0, 0.0),
            DVec3::new(0.5, 1.5, 0.0),
        );
        let tri = Cell::triangle(
            DVec3::ZERO,
            DVec3::new(3.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
        );
        // A slanted parallelogram in space: its map is affine, one step;
        // the trapezoid above is not.
        let (a, u, v) = (
            DVec3::new(1.0, -2.0, 0.5),
            DVec3::new(0.3, 0.1, 0.2),
            DVec3::new(-0.1, 0.25, 0.05),
        );
        let parallelogram = Cell::quad(a, a + u, a + u + v, a + v);
        for (cell, s, t) in [
            (quad, 0.3, 0.8),
            (tri, 0.2, 0.5),
            (parallelogram, 0.9, 0.15),
        ] {
            let (s2, t2) = cell_coordinates(&cell, cell.point(s, t)).unwrap();
            assert!((s2 - s).abs() < 1e-12 && (t2 - t).abs() < 1e-12);
        }
        assert!(is_affine(&parallelogram) && is_affine(&tri) && !is_affine(&quad));
        // Far from the origin, a small parallelogram is still one.
        let far = DVec3::splat(1000.0);
        let small = Cell::quad(far, far + u * 0.01, far + (u + v) * 0.01, far + v * 0.01);
        assert!(is_affine(&small));
        assert!(cell_coordinates(&quad, DVec3::new(5.0, 1.0, 0.0)).is_none());
    }

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

    /// A floor patch whose unshot radiosity rises fourfold across it, shot
    /// with one stratum to points of a ceiling 1.2 above: on average over
    /// the jitter, each point receives the integral of ΔB times the point
    /// kernel over the patch (checked by a 400 × 400 midpoint sum). Read as
    /// ΔB at the sample times the patch's exact factor, a near stratum
    /// weighted ΔB evenly: 17 % too much beside the patch's dark edge.
    #[test]
    fn a_near_stratum_shoots_its_field_weighted_by_the_kernel() {
        use crate::solver::shot::shooter::ShotRadiosity;

        let at = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        let floor = [
            at(-3.0, 0.0, -3.0),
            at(-3.0, 0.0, 3.0),
            at(3.0, 0.0, 3.0),
            at(3.0, 0.0, -3.0),
        ];
        let ceiling: Vec<DVec3> = floor.iter().rev().map(|p| *p + at(0.0, 1.2, 0.0)).collect();
        let (scene, visibility) = grey_scene(&[&floor, &ceiling]);
        let (floor, ceiling) = (SurfaceId::new(0), SurfaceId::new(1));
        let up = scene.surface(floor).normal();
        let down = scene.surface(ceiling).normal();

        // The patch [0, 1] × [0, 1] of the floor, 2 × 2 elements, ΔB = 1 + 3x.
        let p = |x: f64, z: f64| at(x, 0.0, z);
        let cell = Cell::quad(p(0.0, 0.0), p(0.0, 1.0), p(1.0, 1.0), p(1.0, 0.0));
        let delta = |q: DVec3| 1.0 + 3.0 * q.x;
        let mut elements = Vec::new();
        for (x0, z0) in [(0.0, 0.0), (0.5, 0.0), (0.0, 0.5), (0.5, 0.5)] {
            let c = Cell::quad(
                p(x0, z0),
                p(x0, z0 + 0.5),
                p(x0 + 0.5, z0 + 0.5),
                p(x0 + 0.5, z0),
            );
            elements.push(FieldElement::new(
                c,
                c.corners.map(|q| Rgb::splat(delta(q))),
            ));
        }
        let field = PatchField::new(elements, Rgb::splat(2.5), up);
        let shooter = Shooter::new(cell, up, floor, (1, 1), ShotRadiosity::Field(field));
        for x in [at(0.5, 1.2, 0.5), at(-0.5, 1.2, 0.5), at(2.0, 1.2, 0.2)] {
            let m = 400;
            let mut exact = 0.0;
            for j in 0..m {
                for i in 0..m {
                    let y = cell.point((i as f64 + 0.5) / m as f64, (j as f64 + 0.5) / m as f64);
                    let d = y - x;
                    let r2 = d.length_squared();
                    exact += delta(y) * down.dot(d) * -up.dot(d) / (std::f64::consts::PI * r2 * r2);
                }
            }
            exact /= (m * m) as f64;
            let mean = mean_gather(&shooter, &visibility, (x, down, ceiling), 20_000);
            let error = mean / exact - 1.0;
            assert!(
                error.abs() < 0.01,
                "at {x}: {mean} against {exact} ({error:+.4})"
            );
        }
        // A millimetre over the patch, where the point kernel's 1/r² spike
        // (A k(y) > 1 within about 2 cm) catches one jittered sample in
        // five hundred: no gather may exceed the brightest ΔB (4) times the
        // patch's factor (under 1). With the point factor uncapped, one
        // gave 66.
        let x = at(0.5, 0.001, 0.5);
        let brightest = (0..20_000)
            .map(|key| gather_once(&shooter, &visibility, (x, down, ceiling), key))
            .fold(0.0, f64::max);
        assert!(brightest <= 4.0, "a gather gave {brightest}");
    }

    /// A block stands on a floor patch whose light is even: the elements
    /// cover the patch but for the block's footprint. A receiver on the
    /// block's side, 1 cm above the floor, sees mostly the floor within a
    /// few centimetres of the block: Lambert's factor of the floor in front
    /// of the side, times the radiosity. The patch's sampled cells are an
    /// eighth of it wide, and the column beside the block has its centres
    /// under it (the block's side at x = 0.55, the centres at 0.5625):
    /// read there, that column shot nothing, and the receiver got 0.55 of
    /// its light.
    #[test]
    fn a_receiver_at_the_foot_of_an_object_standing_on_the_patch_sees_its_light() {
        use crate::radiometry::polygon_form_factor;
        use crate::solver::shot::shooter::ShotRadiosity;

        let at = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        let floor = [
            at(0.0, 0.0, 0.0),
            at(0.0, 0.0, 1.0),
            at(1.0, 0.0, 1.0),
            at(1.0, 0.0, 0.0),
        ];
        // The block's side facing −x, over x = 0.55, z in [0.25, 0.75].
        let side = [
            at(0.55, 0.0, 0.25),
            at(0.55, 0.0, 0.75),
            at(0.55, 0.5, 0.75),
            at(0.55, 0.5, 0.25),
        ];
        let (scene, visibility) = grey_scene(&[&floor, &side]);
        let (floor, side) = (SurfaceId::new(0), SurfaceId::new(1));
        let up = scene.surface(floor).normal();
        let out = scene.surface(side).normal();
        assert!(out.x < -0.99, "{out}");

        let p = |x: f64, z: f64| at(x, 0.0, z);
        let cell = Cell::quad(p(0.0, 0.0), p(0.0, 1.0), p(1.0, 1.0), p(1.0, 0.0));
        let (xs, zs) = ([0.0, 0.275, 0.55, 0.775, 1.0], [0.0, 0.25, 0.5, 0.75, 1.0]);
        let mut elements = Vec::new();
        let mut power = 0.0;
        for i in 0..4 {
            for j in 0..4 {
                let under_block = i >= 2 && (1..3).contains(&j);
                if under_block {
                    continue;
                }
                let c = Cell::quad(
                    p(xs[i], zs[j]),
                    p(xs[i], zs[j + 1]),
                    p(xs[i + 1], zs[j + 1]),
                    p(xs[i + 1], zs[j]),
                );
                power += c.area;
                elements.push(FieldElement::new(c, [Rgb::splat(1.0); 4]));
            }
        }
        let field = PatchField::new(elements, Rgb::splat(power), up);
        let shooter = Shooter::new(cell, up, floor, (1, 1), ShotRadiosity::Field(field));
        let x = at(0.55, 0.01, 0.5);
        let mean = mean_gather(&shooter, &visibility, (x, out, side), 2000);
        let in_front = [p(0.0, 0.0), p(0.0, 1.0), p(0.55, 1.0), p(0.55, 0.0)];
        let exact = polygon_form_factor(x, out, &in_front);
        let error = mean / exact - 1.0;
        assert!(error.abs() < 0.02, "{mean} against {exact} ({error:+.4})");
    }
}
