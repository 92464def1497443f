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
//! floor under the table, would read far too much from the floor patch's
//! mean, and reads its light within about 1 % from where its rays land
//! (`tests/it/strata.rs`, one floor patch). In a closed scene
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

use crate::rgb::Rgb;

/// Rays each patch casts into its hemisphere (8 × 8 strata).
const PATCH_SIDE: usize = 8;
/// Rays each patch casts.
pub(crate) const PATCH_RAYS: usize = PATCH_SIDE * PATCH_SIDE;
/// Rays each vertex casts into its hemisphere, in strata of projected
/// solid angle: [`VERTEX_RINGS`] rings of equal projected area times
/// `VERTEX_RAYS / VERTEX_RINGS` sectors. Since closed rooms stop after
/// their lamps' shots (`closed_zone_weight` 0.1), the term carries all of
/// their reflected light, and its noise is what the count sets: by the
/// golden tests' metric, 96 rays is where more stop paying for their time
/// in the offices' images.
pub(crate) const VERTEX_RAYS: usize = 96;
/// Rings of the vertex rays' strata ([`VERTEX_RAYS`]).
pub(crate) const VERTEX_RINGS: usize = 8;

/// No patch: the ray left the scene.
pub(crate) const MISS: u32 = u32::MAX;

/// Each patch's residual A_h, the light the unshot radiosity will still
/// give it at patch resolution (`PatchRays::residual`, or after patch
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

/// A vertex's ambient irradiance G_v, W/m², and the standard error of its
/// channels' sum.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct AmbientEstimate {
    pub(crate) irradiance: Rgb,
    pub(crate) standard_error: f64,
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
