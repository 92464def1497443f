//! The ambient term for the light not yet shot, gathered where it will land.
//!
//! Progressive shooting leaves unshot radiosity ΔB_p on the patches at any
//! moment. Cohen et al. (1988, §4) spread the unshot power evenly over the
//! scene as an ambient irradiance U / A · 1 / (1 − ρ̄): right on average for
//! a closed scene, wrong wherever the unshot light is unevenly placed. Under
//! a table in the open, the umbra's light comes all from the table's
//! underside and the floor round the shadow, which hold much of what is
//! still unshot, while the open floor beside it sends its light to the sky:
//! an even term makes the umbra 5 % too dark at the default tolerance, or,
//! assuming a closed scene, the open floor far too bright.
//!
//! isorad gathers the unshot light along rays instead, a coarse final
//! gather of what remains. Each patch casts [`PATCH_RAYS`] cosine-weighted
//! rays from stratified points on its elements, each vertex [`VERTEX_RAYS`]
//! from where it gathers, stratified in projected solid angle; each ray
//! records the patch it hits first (or none: the sky).
//! The light the unshot radiosity will still give, at patch resolution, is
//! the fixed point of
//!
//! ```text
//!   A_p = ρ_p · ⟨ΔB_h + A_h⟩_p
//! ```
//!
//! (⟨·⟩_p the mean over p's rays of the patch h each hits, 0 for a miss,
//! or, in a closed zone that keeps its light, over the rays that land:
//! with cosine-weighted directions that mean is the irradiance of a
//! Lambertian surround), found by Jacobi iteration, which converges as
//! (ρ f)^k for landing share f. A vertex's ambient irradiance is then
//! G_v = ⟨ΔB_h(y) + A_h⟩_v, and its radiosity gains ρ_v G_v. A vertex ray
//! reads ΔB_h(y) where it lands, y, interpolated on the element under y
//! (the ray keeps y to 1/255 of its patch's side), not the patch's mean:
//! after a lamp's shot alone, a table's underside, which sees the dark
//! floor under the table, got 73 % too much from the floor patch's mean,
//! 12 % too little from a lattice of cells an eighth of the patch wide
//! read at their centres, and gets 1.1 % too little from where its rays
//! land (`tests/it/strata.rs`, one floor patch). In a closed scene
//! of uniform ΔB and ρ this is Cohen's ΔB / (1 − ρ); over an open floor it
//! is nothing; under the table it is what the underside will still send.
//! A_h, one value per patch, is then resolved at the vertices by sweeps
//! along the same rays (`solver/ambient/sweeps.rs`). After a run that converged,
//! the patch shots have carried the unshot light to the patch tolerance
//! (`solver/ambient/patch_shots.rs`), and A_h is ρ_h times the irradiance they brought
//! patch h; the patches' rays and iteration here serve the images of a
//! solve under way, stopped short (cancelled, out of time, at a shot
//! limit) or made without patch shots (`patch_tolerance` 1).
//! The term is made room by room, each closed zone's vertices with their
//! own rays (`solver/ambient/rooms.rs`). The patches' rays are cast once and
//! kept, and so are the vertices' up to 2²⁴ rays (about 175,000
//! vertices): an intermediate image then repeats only the lookups. A
//! larger mesh casts each room's rays for each image and drops them
//! after, so that the term holds one room's rays at a time. Photometric
//! luminaires shoot before any patch, so the term never stands in for
//! their direct light (a preview before the
//! first shot shows none). The iteration stops after 1000 iterations: for
//! ρ f near 1 (reflectances of 0.99 in a closed room) it then falls short.
//!
//! # References
//! M. F. Cohen, S. E. Chen, J. R. Wallace, D. P. Greenberg, "A Progressive
//! Refinement Approach to Fast Radiosity Image Generation", SIGGRAPH 1988, §4
//! (the ambient term); M. F. Cohen, J. R. Wallace, "Radiosity and Realistic
//! Image Synthesis" (1993), §5.3 (Jacobi iteration).

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::lighting::SampleStream;
use crate::mesh::Mesh;
use crate::scene::{Rgb, Scene, SurfaceId, Visibility, distance_to_boundary, polygon_contains};
use crate::solver::light::element_index::{ElementIndex, padded_box};
use crate::solver::light::unshot::{cell_coordinates, interpolated};
use crate::solver::zones::{cosine_direction, cosine_direction_at};

/// Rays each patch casts into its hemisphere (8 × 8 strata).
const PATCH_SIDE: usize = 8;
/// Rays each patch casts.
pub(crate) const PATCH_RAYS: usize = PATCH_SIDE * PATCH_SIDE;
/// Rays each vertex casts into its hemisphere, in strata of projected
/// solid angle: [`VERTEX_RINGS`] rings of equal projected area times
/// `VERTEX_RAYS / VERTEX_RINGS` sectors. Since closed rooms stop after
/// their lamps' shots (`closed_zone_weight` 0.1), the term carries all of
/// their reflected light, and its noise is what the count sets (measured
/// by hand, `isorad render` at the references' sizes, the golden tests'
/// metric, per-pixel error and time): the cluttered office of
/// `bench/generate_building.py` renders at 2.79 % in 1.67 s with 64 rays,
/// 2.68 % in 1.77 s with 96 and 2.67 % in 2.06 s with 128; `scenes/room`
/// at 1.92, 1.69 and 1.64 %; the furnished office at 1.48, 1.39 and
/// 1.35 %. With 48 rays and closed rooms stopping at a third, the room
/// read 1.81 % where 64 gave 1.58 %. Earlier, with rooms shot to 10 %:
/// 3.96 % with 32 random rays, 3.78 % with 128, 3.77 % with 1024.
pub(crate) const VERTEX_RAYS: usize = 96;
const VERTEX_RINGS: usize = 8;

/// No patch: the ray left the scene.
pub(crate) const MISS: u32 = u32::MAX;

/// The Jacobi iteration stops when no patch's value changes by more than
/// this fraction of the largest unshot radiosity, or after
/// [`MAX_ITERATIONS`].
const CONVERGENCE: f64 = 1e-6;
const MAX_ITERATIONS: usize = 1000;

/// Rays [`VertexRays::landing_elements`] sorts at a time: 4 MiB of keys.
const LOCATE_BLOCK: usize = 1 << 18;

/// Sorted rays one thread locates at a time, keeping its hint.
const LOCATE_CHUNK: usize = 4096;

/// The element under the point at parameters (s, t) of patch `p`'s cell
/// and the point's coordinates in it, `None` where no element lies; the
/// `usize` is a hint kept between reads on one patch (see
/// [`VertexRays::landing_elements`]).
pub(crate) type Locate<'a> = dyn Fn(usize, DVec2, &mut usize) -> Option<LandingElement> + Sync + 'a;

/// A value read where vertex ray k (its index among a [`VertexRays`]'s
/// rays) landed, `None` to read its patch's value instead.
pub(crate) type RayValue<'a> = dyn Fn(usize) -> Option<Rgb> + Sync + 'a;

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
        Some(interpolated(corners(e), element.is_triangle(), st))
    }
}

/// The patch each of the patches' cached rays hits, [`PATCH_RAYS`] per
/// patch: cast once, read by every image. Only the patches a solution
/// needs are cast (the rooms its readings lie in, see
/// [`crate::Ambient::For`]), the others when one
/// needs them; a patch's rays are the same whichever solution casts
/// them.
#[derive(Clone, Debug, Default)]
pub(crate) struct PatchRays {
    /// The cast patches' rays, [`PATCH_RAYS`] at a time in the order cast.
    hits: Vec<u32>,
    /// Where each patch's rays start in `hits`, over [`PATCH_RAYS`], or
    /// [`NOT_CAST`]: 4 bytes a patch, and 256 more for each cast one.
    slot: Vec<u32>,
}

/// A patch whose rays are not cast.
const NOT_CAST: u32 = u32::MAX;

/// The rays of a list of vertices (a closed room's, or all): the patch
/// each hits and where it lands on it, [`VERTEX_RAYS`] per vertex, vertex
/// after vertex in the list's order. Ray k of the list is ray
/// k mod [`VERTEX_RAYS`] of vertex `vertices[k / VERTEX_RAYS]`.
#[derive(Clone, Debug, Default)]
pub(crate) struct VertexRays {
    vertices: Vec<u32>,
    hits: Vec<u32>,
    /// Where each ray lands on its patch: the patch cell's parameters
    /// there ([`crate::mesh::Cell::point`]) to a [`LANDING_STEPS`]th of
    /// its side ([`Landing`]). The unshot light is read at that point,
    /// from the element under it, not as the patch's mean. Two bytes a
    /// ray: with the hit, these are most of what the term holds per vertex
    /// while a room's image is made (96 rays of 6 bytes; the parameters as
    /// two `f32` took 12), with each ray's landing element, 8 more
    /// ([`VertexRays::landing_elements`]).
    landings: Vec<Landing>,
}

/// Steps per side of a patch's cell to which a vertex ray's landing point
/// is kept: 4 mm on a metre-wide patch. Rays used to keep the cell of a
/// lattice an eighth of the patch wide, read at the cell's centre: a ray
/// that landed on a cell's lit part while its centre lay under an object
/// standing on the patch (a book on a shelf, a screen's foot on a desk)
/// read nothing there.
const LANDING_STEPS: u8 = u8::MAX;

/// A vertex ray's landing point on its patch's cell: its parameters (s, t)
/// each as the step k of [`LANDING_STEPS`] that holds it (read back at the
/// step's middle, (k + ½) / steps), or [`Landing::NOWHERE`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Landing([u8; 2]);

impl Landing {
    /// No point: the ray missed, or landed off its patch's cell.
    const NOWHERE: Landing = Landing([LANDING_STEPS; 2]);

    /// The landing at parameters `st` = (s, t) of a cell, each in [0, 1].
    fn at(st: DVec2) -> Landing {
        let last = f64::from(LANDING_STEPS - 1);
        let step = |w: f64| (w * f64::from(LANDING_STEPS)).clamp(0.0, last) as u8;
        Landing([step(st.x), step(st.y)])
    }

    /// The parameters (s, t) it stands for, or `None` for
    /// [`Landing::NOWHERE`].
    fn parameters(self) -> Option<DVec2> {
        let middle = |k: u8| (f64::from(k) + 0.5) / f64::from(LANDING_STEPS);
        (self != Landing::NOWHERE).then(|| DVec2::new(middle(self.0[0]), middle(self.0[1])))
    }
}

/// Each patch's residual A_h, the light the unshot radiosity will still
/// give it at patch resolution ([`PatchRays::residual`], or after patch
/// shots ρ_h times the irradiance they brought), and its value
/// ΔB_h + A_h, what a vertex ray reads where it lands on no element of
/// its room.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct PatchResidual {
    /// A_h per patch, W/m².
    pub(crate) residual: Vec<Rgb>,
    /// ΔB_h + A_h per patch, W/m².
    pub(crate) value: Vec<Rgb>,
}

/// Where an ambient ray leaves a surface: a point on it, the surface's unit
/// normal, and the surface (which the ray does not hit).
#[derive(Clone, Copy, Debug)]
struct RayStart {
    origin: DVec3,
    normal: DVec3,
    surface: SurfaceId,
}

/// A vertex's ambient irradiance G_v, W/m², and the standard error of its
/// channels' sum.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct AmbientEstimate {
    pub(crate) irradiance: Rgb,
    pub(crate) standard_error: f64,
}

impl PatchRays {
    /// Those of `patches` (all of `mesh`'s, by `None`) whose rays are not
    /// cast yet: every one when `mesh`'s patches are not those the rays
    /// were cast for.
    pub(crate) fn uncast(&self, mesh: &Mesh, patches: Option<&[u32]>) -> Vec<u32> {
        let fresh = self.slot.len() != mesh.patches.len();
        let cast = |p: u32| !fresh && self.slot.get(p as usize).is_none_or(|&k| k != NOT_CAST);
        match patches {
            Some(patches) => patches.iter().copied().filter(|&p| !cast(p)).collect(),
            None => (0..mesh.patches.len() as u32)
                .filter(|&p| !cast(p))
                .collect(),
        }
    }

    /// Patch p's rays, if cast.
    fn of(&self, p: usize) -> Option<&[u32]> {
        let k = *self.slot.get(p).filter(|&&k| k != NOT_CAST)? as usize;
        self.hits.get(k * PATCH_RAYS..(k + 1) * PATCH_RAYS)
    }

    /// Casts the rays of `patches` (ascending): from stratified points on
    /// each one's elements, cosine-weighted. A ray from surface `s`
    /// traverses `visibility_of(s)`: the BVH of its closed zone's bounds,
    /// or the scene's.
    pub(crate) fn cast<'v>(
        &mut self,
        scene: &Scene,
        mesh: &Mesh,
        patches: &[u32],
        locator: &PatchLocator,
        visibility_of: &(dyn Fn(SurfaceId) -> &'v Visibility + Sync),
    ) {
        if self.slot.len() != mesh.patches.len() {
            self.hits = Vec::new();
            self.slot = vec![NOT_CAST; mesh.patches.len()];
        }
        let hits: Vec<u32> = patches
            .par_iter()
            .flat_map_iter(|&p| (0..PATCH_RAYS).map(move |k| (p as usize, k)))
            .map(|(p, k)| patch_ray(scene, mesh, p, k, PATCH_RAYS, locator, visibility_of))
            .collect();
        let first = self.hits.len() / PATCH_RAYS;
        for (k, &p) in patches.iter().enumerate() {
            self.slot[p as usize] = (first + k) as u32;
        }
        self.hits.extend(hits);
    }

    /// The fixed point A_p = ρ_p ⟨ΔB_h + A_h⟩_p, by Jacobi iteration, for
    /// unshot radiosity `unshot` and reflectance `reflectance` per patch;
    /// the mean of a `lossless` patch's rays as
    /// [`VertexRays::irradiance`] takes it. Found on the patches whose rays
    /// are cast and `within` (ascending; all, by `None`); zero elsewhere.
    #[must_use]
    pub(crate) fn residual(
        &self,
        unshot: &[Rgb],
        reflectance: &[Rgb],
        lossless: &[bool],
        within: Option<&[u32]>,
    ) -> Vec<Rgb> {
        let patches = unshot.len();
        let mut residual = vec![Rgb::ZERO; patches];
        if self.slot.len() != patches {
            return residual;
        }
        let listed: Vec<u32> = match within {
            Some(within) => within.to_vec(),
            None => (0..patches as u32).collect(),
        };
        let listed: Vec<(usize, &[u32])> = listed
            .into_iter()
            .map(|p| p as usize)
            .filter_map(|p| Some((p, self.of(p)?)))
            .collect();
        let scale = listed
            .iter()
            .map(|&(p, _)| unshot[p].max_element())
            .fold(0.0, f64::max);
        for _ in 0..MAX_ITERATIONS {
            let next: Vec<Rgb> = listed
                .par_iter()
                .map(|&(p, hits)| {
                    let seen = hits
                        .iter()
                        .filter(|&&h| h != MISS)
                        .map(|&h| unshot[h as usize] + residual[h as usize])
                        .sum::<Rgb>();
                    reflectance[p] * seen / rays_counted(hits, lossless[p])
                })
                .collect();
            let mut change = 0.0_f64;
            for (&(p, _), value) in listed.iter().zip(next) {
                change = change.max((value - residual[p]).abs().max_element());
                residual[p] = value;
            }
            if change <= CONVERGENCE * scale {
                break;
            }
        }
        residual
    }
}

impl VertexRays {
    /// Casts the rays of `vertices`, [`VERTEX_RAYS`] from where each
    /// gathers, stratified in projected solid angle. A vertex's rays are
    /// the same whatever list it is cast in: each is seeded by its vertex
    /// and its index. A ray from surface `s` traverses `visibility_of(s)`.
    #[must_use]
    pub(crate) fn cast<'v>(
        scene: &Scene,
        mesh: &Mesh,
        vertices: Vec<u32>,
        locator: &PatchLocator,
        visibility_of: &(dyn Fn(SurfaceId) -> &'v Visibility + Sync),
    ) -> VertexRays {
        let count = vertices.len() * VERTEX_RAYS;
        let mut hits = vec![MISS; count];
        let mut landings = vec![Landing::NOWHERE; count];
        hits.par_chunks_mut(VERTEX_RAYS)
            .zip(landings.par_chunks_mut(VERTEX_RAYS))
            .zip(vertices.par_iter())
            .for_each(|((hits, landings), &v)| {
                let vertex = &mesh.vertices[v as usize];
                let normal = scene.surface(vertex.surface).normal();
                let visibility = visibility_of(vertex.surface);
                for (k, (hit, landing)) in hits.iter_mut().zip(landings.iter_mut()).enumerate() {
                    let mut stream = SampleStream::new(u64::from(v), k as u64 | 2 << 40);
                    let origin = vertex.receiver_position();
                    let sectors = VERTEX_RAYS / VERTEX_RINGS;
                    let direction =
                        stratified_direction(normal, k, VERTEX_RINGS, sectors, &mut stream);
                    let start = RayStart {
                        origin,
                        normal,
                        surface: vertex.surface,
                    };
                    let (patch, point) = locator.hit(scene, visibility, start, direction);
                    *hit = patch;
                    *landing = mesh
                        .patches
                        .get(patch as usize)
                        .and_then(|patch| cell_coordinates(&patch.cell, point))
                        .filter(|(s, t)| s.is_finite() && t.is_finite())
                        .map_or(Landing::NOWHERE, |st| Landing::at(st.into()));
                }
            });
        VertexRays {
            vertices,
            hits,
            landings,
        }
    }

    /// The vertices whose rays these are, in the rays' order.
    pub(crate) fn vertices(&self) -> &[u32] {
        &self.vertices
    }

    /// The ambient irradiance G_v of each listed vertex (see the module
    /// docs), in the list's order, for each patch's `residual` A_h
    /// ([`PatchRays::residual`]) and its value ΔB_h + A_h (`patches`).
    /// Ray k reads the unshot radiosity where it lands, `unshot_at(k)` (on
    /// the element under its point, see [`VertexRays::landing_elements`]),
    /// or the patch's mean where that gives none: a floor patch half under
    /// a desk then sends the desk's underside the light of its dark half
    /// and the ceiling that of its lit half, as its shots do.
    /// The residual A_h stays the patch's here (`solver/ambient/sweeps.rs` then
    /// resolves it at the vertices). Each estimate comes with a bound on
    /// its standard error, that of the mean of its rays' values summed
    /// over the channels, from its strata collapsed in pairs of
    /// neighbouring sectors (a miss counted as 0, or its pair left out
    /// where the mean leaves misses out): a surface that fills a ring of
    /// strata evenly adds nothing to it, however bright.
    ///
    /// In a zone that keeps all its light (`lossless` of a surface, see
    /// [`crate::SolverSettings::conserve_closed_zones`]) a ray that ends on
    /// no front (a crack at a contact, a back inside an object) is no light
    /// leaving: a source's mean is then over the rays that land, where at
    /// least half of them do. Counted as dark, the cluttered office's 1 %
    /// of such rays compounded over the residual's bounces: its ceiling,
    /// solved to 30 %, was 1.50 % below its converged light, and is 1.33 %
    /// below with them left out.
    #[must_use]
    pub(crate) fn irradiance(
        &self,
        mesh: &Mesh,
        patches: &PatchResidual,
        unshot_at: &RayValue<'_>,
        lossless: &(dyn Fn(SurfaceId) -> bool + Sync),
    ) -> Vec<AmbientEstimate> {
        let value_at = |k: usize| {
            let h = self.hits[k] as usize;
            unshot_at(k).map(|w| w + patches.residual[h])
        };
        self.gather(mesh, &value_at, &|h| patches.value[h], lossless)
    }

    /// The element under every ray's landing point, by
    /// `locate(patch, (s, t), hint)`: [`LandingElement::NONE`] for a miss,
    /// or where no element lies. The rays are located in order of patch,
    /// then of s and t, [`LOCATE_BLOCK`] rays at a time: a patch's elements
    /// are then read while they are in cache, and `hint`, the element the
    /// last ray on that patch found, is most often the next ray's (in the
    /// vertices' order, locating took a third of the cluttered office's
    /// ambient term, mostly waiting on the cache).
    #[must_use]
    pub(crate) fn landing_elements(&self, locate: &Locate<'_>) -> Vec<LandingElement> {
        let mut located = vec![LandingElement::NONE; self.hits.len()];
        for (b, block) in located.chunks_mut(LOCATE_BLOCK).enumerate() {
            let start = b * LOCATE_BLOCK;
            // The block's landed rays, keyed by patch, s step and t step.
            let mut order: Vec<(u64, u32)> = (0..block.len())
                .filter_map(|i| {
                    let (h, landing) = (self.hits[start + i], self.landings[start + i]);
                    let [s, t] = landing.0;
                    let key = (u64::from(h) << 16) | (u64::from(s) << 8) | u64::from(t);
                    (h != MISS && landing != Landing::NOWHERE).then_some((key, i as u32))
                })
                .collect();
            order.par_sort_unstable_by_key(|&(key, _)| key);
            let found: Vec<LandingElement> = order
                .par_chunks(LOCATE_CHUNK)
                .flat_map_iter(|chunk| {
                    let mut last = (usize::MAX, 0);
                    chunk.iter().map(move |&(key, i)| {
                        let h = (key >> 16) as usize;
                        if last.0 != h {
                            last = (h, 0);
                        }
                        self.landings[start + i as usize]
                            .parameters()
                            .and_then(|st| locate(h, st, &mut last.1))
                            .unwrap_or(LandingElement::NONE)
                    })
                })
                .collect();
            for (&(_, i), element) in order.iter().zip(found) {
                block[i as usize] = element;
            }
        }
        located
    }

    /// Each listed vertex's mean over its rays of `value_at(k)` where ray
    /// k lands on patch h, or `fallback(h)` where that gives none, with its
    /// standard error (see [`VertexRays::irradiance`]).
    #[must_use]
    pub(crate) fn gather(
        &self,
        mesh: &Mesh,
        value_at: &RayValue<'_>,
        fallback: &(dyn Fn(usize) -> Rgb + Sync),
        lossless: &(dyn Fn(SurfaceId) -> bool + Sync),
    ) -> Vec<AmbientEstimate> {
        let seen = |(i, &v): (usize, &u32)| {
            let rays = i * VERTEX_RAYS..(i + 1) * VERTEX_RAYS;
            let hits = &self.hits[rays.clone()];
            let mut sum = Rgb::ZERO;
            // Each ray's value summed over the channels, 0 for a miss.
            let mut sums = [0.0; VERTEX_RAYS];
            for (k, &h) in hits.iter().enumerate() {
                if h == MISS {
                    continue;
                }
                let value = value_at(rays.start + k).unwrap_or_else(|| fallback(h as usize));
                sum += value;
                sums[k] = value.element_sum();
            }
            let n = rays_counted(hits, lossless(mesh.vertices[v as usize].surface));
            // Strata collapsed in pairs of neighbouring sectors: each pair
            // estimates twice a stratum's variance, so over the K pairs
            // kept Var(mean) ≈ Σ (x_a − x_b)² / (2 K n) (Cochran 1977,
            // §5A.12; Σ / n² with every pair). Where the mean leaves the
            // misses out, so do the pairs.
            let skip_misses = n < hits.len() as f64;
            let (mut squares, mut pairs) = (0.0, 0.0);
            for (pair, rays) in sums.chunks_exact(2).zip(hits.chunks_exact(2)) {
                if skip_misses && rays.contains(&MISS) {
                    continue;
                }
                squares += (pair[0] - pair[1]).powi(2);
                pairs += 1.0;
            }
            let variance = if pairs > 0.0 {
                squares / (2.0 * pairs * n)
            } else {
                0.0
            };
            AmbientEstimate {
                irradiance: sum / n,
                standard_error: variance.sqrt(),
            }
        };
        self.vertices.par_iter().enumerate().map(seen).collect()
    }

    /// Each listed vertex's harmonic mean distance to where its rays land,
    /// R_v = N / Σ 1/d_k over the N rays that land on a patch (infinite
    /// where none does): the scale over which its ambient irradiance
    /// changes (`solver/ambient/smoothing.rs`).
    #[must_use]
    pub(crate) fn harmonic_distances(&self, mesh: &Mesh) -> Vec<f64> {
        self.vertices
            .par_iter()
            .enumerate()
            .map(|(i, &v)| {
                let rays = i * VERTEX_RAYS..(i + 1) * VERTEX_RAYS;
                let x = mesh.vertices[v as usize].receiver_position();
                let (mut count, mut inverse) = (0.0, 0.0);
                for (&h, landing) in self.hits[rays.clone()].iter().zip(&self.landings[rays]) {
                    let (Some(patch), Some(st)) =
                        (mesh.patches.get(h as usize), landing.parameters())
                    else {
                        continue;
                    };
                    let d = patch.cell.point(st.x, st.y).distance(x);
                    if d > 0.0 && d.is_finite() {
                        count += 1.0;
                        inverse += 1.0 / d;
                    }
                }
                if inverse > 0.0 {
                    count / inverse
                } else {
                    f64::INFINITY
                }
            })
            .collect()
    }
}

/// The patch that ray `k` of `count` of patch `p` hits first, or [`MISS`]:
/// from the `k`-th of `count` stratified points on its elements,
/// cosine-weighted, traversing `visibility_of` its surface. A patch without
/// elements (all hidden) casts only misses. The same ray whoever casts it:
/// seeded by the patch and its index.
pub(crate) fn patch_ray<'v>(
    scene: &Scene,
    mesh: &Mesh,
    p: usize,
    k: usize,
    count: usize,
    locator: &PatchLocator,
    visibility_of: &(dyn Fn(SurfaceId) -> &'v Visibility + Sync),
) -> u32 {
    let patch = &mesh.patches[p];
    let normal = scene.surface(patch.surface).normal();
    let mut stream = SampleStream::new(p as u64, k as u64 | 1 << 40);
    point_on_elements(mesh, p, k, count, &mut stream).map_or(MISS, |origin| {
        // Not stratified: the points are, by k.
        let direction = cosine_direction(normal, &mut stream);
        let start = RayStart {
            origin,
            normal,
            surface: patch.surface,
        };
        let visibility = visibility_of(patch.surface);
        locator.hit(scene, visibility, start, direction).0
    })
}

/// The number of rays a source's mean is over: all of its `hits`, or, for
/// a source in a zone that keeps its light (`lossless`), those that land
/// where at least half do (a source most of whose rays miss lies inside an
/// object, and keeps the mean over all its rays).
pub(crate) fn rays_counted(hits: &[u32], lossless: bool) -> f64 {
    let landed = hits.iter().filter(|&&h| h != MISS).count();
    if lossless && 2 * landed >= hits.len() {
        landed as f64
    } else {
        hits.len() as f64
    }
}

/// Cosine-weighted direction k of a rings × sectors stratification of the
/// projected solid angle about the unit `normal`, jittered in its stratum:
/// ring k / sectors (of equal projected area, u₁ = r² uniform), sector
/// k mod sectors. Only a vertex's rays are stratified so: a patch's rays
/// are stratified by where they leave from, and pairing that stratum with
/// a direction stratum would bias the mean.
fn stratified_direction(
    normal: DVec3,
    k: usize,
    rings: usize,
    sectors: usize,
    stream: &mut SampleStream,
) -> DVec3 {
    let (ring, sector) = (k / sectors % rings, k % sectors);
    let u1 = (ring as f64 + stream.next_f64()) / rings as f64;
    let u2 = (sector as f64 + stream.next_f64()) / sectors as f64;
    cosine_direction_at(normal, (u1, u2))
}

/// The `k`-th of `count` stratified points on patch `p`'s elements
/// (its visible part: the cell less what objects standing on it hide),
/// stratified by area over the elements in order, jittered within each.
/// `None` for a patch without elements.
fn point_on_elements(
    mesh: &Mesh,
    p: usize,
    k: usize,
    count: usize,
    stream: &mut SampleStream,
) -> Option<DVec3> {
    let patch = &mesh.patches[p];
    let total: f64 = patch
        .elements
        .iter()
        .map(|&e| mesh.elements[e as usize].area)
        .sum();
    if patch.elements.is_empty() || total <= 0.0 {
        return None;
    }
    let mut target = (k as f64 + stream.next_f64()) / count as f64 * total;
    let mut chosen = patch.elements[patch.elements.len() - 1];
    for &e in &patch.elements {
        let area = mesh.elements[e as usize].area;
        if target < area {
            chosen = e;
            break;
        }
        target -= area;
    }
    let cell = mesh.element_cell(&mesh.elements[chosen as usize]);
    Some(cell.point(stream.next_f64(), stream.next_f64()))
}

/// Which patch of a surface holds a point: each patch's cell in its
/// surface's plane coordinates, grouped by surface, and on a surface of
/// more than [`INDEXED_PATCHES`] patches a grid of them
/// ([`ElementIndex`]), so that a ray landing on a floor tries the few
/// patches there rather than all. Flat, 80 bytes a patch and 12 a
/// surface: as a list of lists per surface it raised the million quads'
/// peak, at their image, from 6.7 to 7.1 GiB.
pub(crate) struct PatchLocator {
    /// Surface s's patches are `patches[starts[s]..starts[s + 1]]`.
    starts: Vec<u32>,
    /// Each patch's index and cell, surface by surface, each surface's in
    /// the mesh's order.
    patches: Vec<(u32, PlaneCell)>,
    /// Boxed: 8 bytes a surface without one (most of a building's).
    index: Vec<Option<Box<ElementIndex>>>,
    reach: f64,
}

/// A patch's cell in its surface's plane coordinates.
#[derive(Clone, Copy, Debug)]
struct PlaneCell {
    corners: [DVec2; 4],
    is_triangle: bool,
}

impl PlaneCell {
    fn polygon(&self) -> &[DVec2] {
        if self.is_triangle {
            &self.corners[..3]
        } else {
            &self.corners
        }
    }
}

/// Patches a surface may have before [`PatchLocator`] indexes them.
const INDEXED_PATCHES: usize = 8;

impl PatchLocator {
    /// The locator of every patch of `mesh`. Always all of them, also for
    /// one room's term: the rays it casts are kept for later images,
    /// which must not depend on which room was drawn first.
    pub(crate) fn new(scene: &Scene, mesh: &Mesh) -> PatchLocator {
        // Patches counted, then placed, surface by surface.
        let surfaces = scene.surfaces.len();
        let mut starts = vec![0u32; surfaces + 1];
        for patch in &mesh.patches {
            if let Some(count) = starts.get_mut(patch.surface.index() + 1) {
                *count += 1;
            }
        }
        for s in 0..surfaces {
            starts[s + 1] += starts[s];
        }
        let mut next = starts.clone();
        let mut order = vec![0u32; mesh.patches.len()];
        for (p, patch) in mesh.patches.iter().enumerate() {
            if let Some(slot) = next.get_mut(patch.surface.index()) {
                order[*slot as usize] = p as u32;
                *slot += 1;
            }
        }
        order.truncate(starts[surfaces] as usize);
        let patches: Vec<(u32, PlaneCell)> = order
            .par_iter()
            .map(|&p| {
                let cell = &mesh.patches[p as usize].cell;
                let frame = scene.surface(mesh.patches[p as usize].surface).frame();
                let corners = cell.corners.map(|q| frame.to_plane(q));
                let is_triangle = cell.is_triangle;
                (
                    p,
                    PlaneCell {
                        corners,
                        is_triangle,
                    },
                )
            })
            .collect();
        let index = (0..surfaces)
            .into_par_iter()
            .map(|s| {
                let listed = &order[starts[s] as usize..starts[s + 1] as usize];
                (listed.len() > INDEXED_PATCHES).then(|| {
                    let boxes: Vec<(DVec3, DVec3)> = listed
                        .iter()
                        .map(|&p| padded_box(mesh.patches[p as usize].cell.polygon()))
                        .collect();
                    Box::new(ElementIndex::new(&boxes, scene.surfaces[s].normal()))
                })
            })
            .collect();
        PatchLocator {
            starts,
            patches,
            index,
            reach: 2.0 * scene.diagonal(),
        }
    }

    /// The patch that a ray from `origin` on `surface` (unit `normal`)
    /// along `direction` hits first, or [`MISS`], and where (NaN for a
    /// miss).
    fn hit(
        &self,
        scene: &Scene,
        visibility: &Visibility,
        start: RayStart,
        direction: DVec3,
    ) -> (u32, DVec3) {
        const NONE: (u32, DVec3) = (MISS, DVec3::NAN);
        let RayStart {
            origin,
            normal,
            surface,
        } = start;
        let start = origin + normal * visibility.surface_offset();
        let Some((hit, distance)) = visibility.closest_hit(start, direction, self.reach, surface)
        else {
            return NONE;
        };
        let target = scene.surface(hit);
        // Light arriving from a surface's back: one-sided surfaces send none.
        if target.normal().dot(direction) >= 0.0 {
            return NONE;
        }
        let landed = start + direction * distance;
        let point = target.frame().to_plane(landed);
        self.patch_at(hit, landed, point)
            .map_or(NONE, |p| (p, landed))
    }

    /// The patch of `surface` that holds point `landed` on it (`point` in
    /// its plane coordinates): the first of its patches, in the mesh's
    /// order, whose cell contains the point, or else the nearest.
    fn patch_at(&self, surface: SurfaceId, landed: DVec3, point: DVec2) -> Option<u32> {
        let s = surface.index();
        let (&from, &to) = (self.starts.get(s)?, self.starts.get(s + 1)?);
        let candidates = &self.patches[from as usize..to as usize];
        let inside = |(_, cell): &&(u32, PlaneCell)| polygon_contains(cell.polygon(), point);
        let found = match self.index.get(s).and_then(Option::as_ref) {
            Some(index) => index
                .near(landed)
                .iter()
                .filter_map(|&k| candidates.get(k as usize))
                .find(inside),
            None => candidates.iter().find(inside),
        };
        let distance = |(_, cell): &(u32, PlaneCell)| distance_to_boundary(cell.polygon(), point);
        found
            .or_else(|| {
                candidates
                    .iter()
                    .min_by(|a, b| distance(a).total_cmp(&distance(b)))
            })
            .map(|&(p, _)| p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Patches' rays, `PATCH_RAYS` hits after another.
    fn patch_rays(hits: Vec<u32>) -> PatchRays {
        let slot = (0..(hits.len() / PATCH_RAYS) as u32).collect();
        PatchRays { hits, slot }
    }

    /// Two patches that see only each other (every ray of each hits the
    /// other): A = ρ (ΔB + A) on both, so A = ρ ΔB / (1 − ρ) and the ambient
    /// irradiance G = ΔB + A = ΔB / (1 − ρ), Cohen's closed-scene term.
    #[test]
    fn an_enclosure_of_uniform_patches_gets_cohens_term() {
        let rays = patch_rays([vec![1; PATCH_RAYS], vec![0; PATCH_RAYS]].concat());
        let unshot = [Rgb::splat(2.0), Rgb::splat(2.0)];
        let reflectance = [Rgb::splat(0.5), Rgb::splat(0.5)];
        let residual = rays.residual(&unshot, &reflectance, &[false; 2], None);
        for a in residual {
            // ρ ΔB / (1 − ρ) = 0.5 · 2 / 0.5.
            assert!((a.g - 2.0).abs() < 1e-5, "{a:?}");
        }
    }

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

    /// A vertex ray reads the unshot light where it landed, and the
    /// patch's mean where that gives none or it landed off the patch; a
    /// miss reads nothing.
    #[test]
    fn a_vertex_ray_reads_where_it_landed() {
        let landings: Vec<Landing> = (0..VERTEX_RAYS)
            .map(|k| match k % 4 {
                0 | 1 => Landing::at(DVec2::new(0.1, 0.9)),
                2 => Landing::at(DVec2::new(0.7, 0.2)),
                _ => Landing::NOWHERE,
            })
            .collect();
        let hits: Vec<u32> = (0..VERTEX_RAYS)
            .map(|k| if k % 8 == 7 { MISS } else { 0 })
            .collect();
        let rays = VertexRays {
            vertices: vec![0],
            hits,
            landings,
        };
        let mut mesh = Mesh::default();
        let surface = crate::scene::SurfaceId::new(0);
        mesh.vertices
            .push(crate::mesh::MeshVertex::new(DVec3::ZERO, surface));
        let unshot = [Rgb::splat(1.0)];
        // 2 left of s = 0.5 and 4 right of it; each point read within a
        // step of where its ray landed.
        // Element 0 lies left of s = 0.5, element 1 right of it.
        let locate = |patch: usize, st: DVec2, _: &mut usize| {
            let (s, t) = (st.x, st.y);
            assert_eq!(patch, 0);
            let step = 1.0 / f64::from(LANDING_STEPS);
            let near = |a: f64, b: f64| (a - b).abs() <= step;
            assert!((near(s, 0.1) && near(t, 0.9)) || (near(s, 0.7) && near(t, 0.2)));
            Some(LandingElement::new(u32::from(s >= 0.5), st))
        };
        let landed = rays.landing_elements(&locate);
        assert_eq!(landed.len(), VERTEX_RAYS);
        let field = |k: usize| {
            let element = landed[k].element;
            (landed[k] != LandingElement::NONE)
                .then(|| Rgb::splat(if element == 0 { 2.0 } else { 4.0 }))
        };
        let patches = PatchResidual {
            residual: vec![Rgb::ZERO],
            value: unshot.to_vec(),
        };
        let g = rays.irradiance(&mesh, &patches, &field, &|_| false);
        // Of every 8 rays: four at 2, two at 4, one nowhere (the mean, 1)
        // and one miss: (4·2 + 2·4 + 1) / 8.
        assert!((g[0].irradiance.g - 17.0 / 8.0).abs() < 1e-12, "{g:?}");
        // Its standard error's bound, from the ray pairs (6, 6), (12, 3),
        // (6, 6) and (12, 0) of the channels' sums in each of the n / 8
        // groups of 8 rays: √(n / 8 · (9² + 12²)) / n.
        let (n, groups) = (VERTEX_RAYS as f64, (VERTEX_RAYS / 8) as f64);
        let expected = (groups * (81.0 + 144.0)).sqrt() / n;
        assert!((g[0].standard_error - expected).abs() < 1e-12, "{g:?}");
        // In a zone that keeps its light the miss is left out: / 7.
        let g = rays.irradiance(&mesh, &patches, &field, &|_| true);
        assert!((g[0].irradiance.g - 17.0 / 7.0).abs() < 1e-12, "{g:?}");
        // And so is the pair that holds it: 3 pairs kept in each group,
        // Σ = groups · 9², over the 7 rays in each that land.
        let expected = (groups * 81.0 / (2.0 * 3.0 * groups * 7.0 * groups)).sqrt();
        assert!((g[0].standard_error - expected).abs() < 1e-12, "{g:?}");
    }

    /// Rays located in order of patch and place come back to their own
    /// slots, across blocks: each gets what its own patch and point give,
    /// and a miss or a landing off its patch gets none.
    #[test]
    fn rays_located_in_sorted_order_keep_their_own_elements() {
        let count = LOCATE_BLOCK + LOCATE_BLOCK / 2 + 7 * VERTEX_RAYS;
        let mut stream = SampleStream::new(17, 3);
        let (mut hits, mut landings) = (Vec::new(), Vec::new());
        for _ in 0..count {
            let u = stream.next_f64();
            hits.push(if u < 0.05 { MISS } else { (u * 500.0) as u32 });
            landings.push(if stream.next_f64() < 0.02 {
                Landing::NOWHERE
            } else {
                Landing::at(DVec2::new(stream.next_f64(), stream.next_f64()))
            });
        }
        let rays = VertexRays {
            vertices: (0..(count / VERTEX_RAYS) as u32).collect(),
            hits,
            landings,
        };
        // An element per patch and step of s; the point's (s, t) kept.
        let locate = |patch: usize, st: DVec2, _: &mut usize| {
            let step = (st.x * f64::from(LANDING_STEPS)) as u32;
            Some(LandingElement::new(patch as u32 * 256 + step, st))
        };
        let landed = rays.landing_elements(&locate);
        assert_eq!(landed.len(), count);
        for (k, found) in landed.iter().enumerate() {
            let (h, landing) = (rays.hits[k], rays.landings[k]);
            let expected = match landing.parameters() {
                Some(st) if h != MISS => locate(h as usize, st, &mut 0).unwrap(),
                _ => LandingElement::NONE,
            };
            assert_eq!(*found, expected, "ray {k}");
        }
    }

    /// On a floor of many patches, the grid finds the patch a scan of
    /// them all finds, first in the mesh's order, at points inside cells,
    /// on their shared edges and corners, and off the floor (the nearest).
    #[test]
    fn the_patch_grid_finds_what_a_scan_finds() {
        let mut scene = Scene::new();
        let white = scene
            .add_material(crate::Material::diffuse("white", Rgb::splat(0.5)))
            .unwrap();
        // A slanted 4 × 3 floor: cells are not aligned with the axes.
        let (o, u, v) = (
            DVec3::new(0.5, 0.2, -1.0),
            DVec3::new(4.0, 0.3, 0.0),
            DVec3::new(0.0, 0.2, 3.0),
        );
        let floor = [o, o + v, o + u + v, o + u];
        scene.add_polygon("floor", white, &floor).unwrap();
        let id = SurfaceId::new(0);
        let settings = crate::mesh::SquareMeshSettings {
            max_edge: 0.25,
            elements_per_side: None,
            patch_max_edge: 0.5,
        };
        let mesh = crate::mesh::mesh_square(&scene, &settings);
        let locator = PatchLocator::new(&scene, &mesh);
        assert!(mesh.patches.len() > 4 * INDEXED_PATCHES);
        assert!(locator.index[id.index()].is_some());
        let frame = scene.surface(id).frame();
        // Every patch's cell from the mesh itself, in its order.
        let cells: Vec<(u32, Vec<DVec2>)> = (mesh.patches.iter().enumerate())
            .filter(|(_, patch)| patch.surface == id)
            .map(|(p, patch)| {
                let cell = patch.cell.polygon().iter().map(|&q| frame.to_plane(q));
                (p as u32, cell.collect())
            })
            .collect();
        let scanned = |point: DVec2| {
            cells
                .iter()
                .find(|(_, cell)| polygon_contains(cell, point))
                .or_else(|| {
                    cells.iter().min_by(|a, b| {
                        distance_to_boundary(&a.1, point)
                            .total_cmp(&distance_to_boundary(&b.1, point))
                    })
                })
                .map(|&(p, _)| p)
        };
        // Points on an 8 × 6 lattice of the patches' corners, their
        // edges' midpoints, their centres, and a step beyond the floor.
        for i in -1..=17 {
            for j in -1..=13 {
                let (s, t) = (f64::from(i) / 16.0, f64::from(j) / 12.0);
                let landed = o + u * s + v * t;
                let point = frame.to_plane(landed);
                assert_eq!(
                    locator.patch_at(id, landed, point),
                    scanned(point),
                    "{s} {t}"
                );
            }
        }
    }

    /// Rays that leave the scene carry nothing: a patch half of whose rays
    /// miss sees half the other's light.
    #[test]
    fn light_that_leaves_adds_nothing() {
        let half: Vec<u32> = (0..PATCH_RAYS)
            .map(|k| if k % 2 == 0 { 1 } else { MISS })
            .collect();
        let rays = patch_rays([half, vec![MISS; PATCH_RAYS]].concat());
        let unshot = [Rgb::ZERO, Rgb::splat(4.0)];
        let reflectance = [Rgb::splat(0.5), Rgb::splat(0.5)];
        let residual = rays.residual(&unshot, &reflectance, &[false; 2], None);
        assert!((residual[0].r - 1.0).abs() < 1e-12, "{residual:?}");
        assert_eq!(residual[1], Rgb::ZERO);
        // In a zone that keeps its light, the misses are left out of the
        // mean (half the rays land: just enough); a patch none of whose
        // rays land still sees nothing.
        let residual = rays.residual(&unshot, &reflectance, &[true; 2], None);
        assert!((residual[0].r - 2.0).abs() < 1e-12, "{residual:?}");
        assert_eq!(residual[1], Rgb::ZERO);
        // Fewer than half landing: inside an object, the mean over all.
        let few: Vec<u32> = (0..PATCH_RAYS)
            .map(|k| if k % 4 == 0 { 1 } else { MISS })
            .collect();
        let rays = patch_rays([few, vec![MISS; PATCH_RAYS]].concat());
        let residual = rays.residual(&unshot, &reflectance, &[true; 2], None);
        assert!((residual[0].r - 0.5).abs() < 1e-12, "{residual:?}");
    }
}
