//! The ambient term's further bounces, resolved at the vertices.
//!
//! The ambient term (`solver/ambient/rays.rs`) gathers at each vertex the unshot
//! radiosity ΔB where its rays land, plus A_h, the light patch h will still
//! reflect, found at patch resolution: one value for the whole patch. Where
//! part of a patch is hidden from most of the room, that is wrong in a way
//! no number of rays averages out. A wall patch half behind a bookcase
//! sends the books' backs, which see only its hidden half, the mean of its
//! lit and hidden halves; a floor patch half under a desk sends the
//! ceiling, which sees its open half, the same mean: solved from the
//! lamps' shots alone, the cluttered office's book backs would take far
//! too much of the light still to come, and its ceiling too little.
//!
//! So the term is taken further by Jacobi sweeps over the vertices, along
//! the same rays. With G⁽⁰⁾ the patch-level estimate (smoothed, as
//! images show it), each sweep gathers
//!
//! ```text
//!   G⁽ᵏ⁺¹⁾_v = ⟨ ΔB(y) + ρ(y) G⁽ᵏ⁾(y) ⟩_v
//! ```
//!
//! where G⁽ᵏ⁾(y) is interpolated on the element under the landing point y
//! from its corners' values, as ΔB is. If G⁽ᵏ⁾ were the light each point
//! will still receive, G⁽ᵏ⁺¹⁾ would equal it; its error, patch-level or
//! noise, is carried one bounce further by every sweep, so it shrinks by ρ
//! times the share of rays that land and is spread over the surfaces each
//! vertex sees. Each sweep is smoothed as the first is
//! (`solver/ambient/smoothing.rs`). The sweeps stop when the mean change of G
//! over a room's vertices falls below [`SWEEP_CONVERGENCE`] of its mean
//! (each closed zone is swept on its own, `solver/ambient/rooms.rs`), or
//! after the solver's `ambient_sweeps`.
//!
//! This is Jacobi iteration for the remaining transport (Cohen & Wallace
//! 1993, §5.3) with the form factors estimated once by the rays, as in
//! stochastic Jacobi radiosity (Neumann, Feda, Kopp & Purgathofer 1994;
//! Bekaert 1999), but at vertices and from a start already near the
//! answer: three to five sweeps suffice.
//!
//! # References
//! M. F. Cohen, J. R. Wallace, "Radiosity and Realistic Image Synthesis"
//! (1993), §5.3; L. Neumann, M. Feda, M. Kopp, W. Purgathofer, "A New
//! Stochastic Radiosity Method for Highly Complex Scenes", Eurographics
//! Rendering Workshop 1994; P. Bekaert, "Hierarchical and Stochastic
//! Algorithms for Radiosity", PhD thesis, KU Leuven, 1999.

use rayon::prelude::*;

use crate::mesh::Mesh;
use crate::rgb::Rgb;
use crate::scene::SurfaceId;
use crate::solver::ambient::landing::LandingElement;
use crate::solver::ambient::rays::AmbientEstimate;
use crate::solver::ambient::rooms::RoomView;
use crate::solver::ambient::vertex_rays::VertexRays;

/// The sweeps stop when the mean absolute change of G over the room's
/// vertices (channels summed) is below this fraction of G's mean. The
/// change shrinks about 2.5-fold per sweep in the offices; the error left
/// is about the last change.
pub(crate) const SWEEP_CONVERGENCE: f64 = 0.005;

/// What the sweeps read where a room's rays land: the element under each
/// ray's landing point, the room's elements' corners' unshot radiosity at
/// the scale that carries its patch's power (in the room's order), each
/// patch's mean unshot radiosity (read where a landing point finds no
/// element), and each patch's ΔB + A at patch resolution (read where a
/// ray leaves the room through a seam: `solver/ambient/rooms.rs`).
pub(crate) struct UnshotLight<'a> {
    pub(crate) landed: &'a [LandingElement],
    pub(crate) corners: &'a [[Rgb; 4]],
    pub(crate) per_patch: &'a [Rgb],
    pub(crate) outside: &'a [Rgb],
}

/// G of `room`'s vertices (in its order) after up to `max_sweeps` sweeps
/// along their `rays` from `first` (see the module docs), with
/// `reflectance` per vertex of the room; `smooth` turns a sweep's
/// estimates into the values the next sweep reads.
#[allow(clippy::too_many_arguments)]
pub(crate) fn swept(
    rays: &VertexRays,
    mesh: &Mesh,
    room: RoomView<'_>,
    first: Vec<Rgb>,
    max_sweeps: usize,
    unshot: &UnshotLight<'_>,
    reflectance: &[Rgb],
    lossless: &(dyn Fn(SurfaceId) -> bool + Sync),
    smooth: &dyn Fn(&[AmbientEstimate]) -> Vec<Rgb>,
) -> Vec<Rgb> {
    let mut ambient = first;
    for _ in 0..max_sweeps {
        let further: Vec<Rgb> = ambient
            .par_iter()
            .zip(reflectance)
            .map(|(g, rho)| *rho * *g)
            .collect();
        let estimates = gathered_once(rays, mesh, room, unshot, &further, lossless);
        let next = smooth(&estimates);
        let change = mean_change(&next, &ambient);
        ambient = next;
        if change <= SWEEP_CONVERGENCE {
            break;
        }
    }
    ambient
}

/// One sweep's estimates: each of the room's vertices' mean of ΔB(y) + R(y)
/// over its rays, R the light `further` per vertex of the room (ρ G), both
/// interpolated on the element under each landing point, or their patch's
/// area-weighted means where none is.
fn gathered_once(
    rays: &VertexRays,
    mesh: &Mesh,
    room: RoomView<'_>,
    unshot: &UnshotLight<'_>,
    further: &[Rgb],
    lossless: &(dyn Fn(SurfaceId) -> bool + Sync),
) -> Vec<AmbientEstimate> {
    let RoomView { room, local } = room;
    let further_at = |v: u32| local.vertex(v as usize).map_or(Rgb::ZERO, |i| further[i]);
    let per_patch: Vec<Rgb> = room
        .patches
        .par_iter()
        .map(|&p| {
            let patch = &mesh.patches[p as usize];
            let (mut sum, mut area) = (Rgb::ZERO, 0.0);
            for &e in &patch.elements {
                let element = &mesh.elements[e as usize];
                sum += element.corner_mean(further_at) * element.area;
                area += element.area;
            }
            unshot.per_patch[p as usize] + if area > 0.0 { sum / area } else { Rgb::ZERO }
        })
        .collect();
    let fallback = |h: usize| local.patch(h).map_or(unshot.outside[h], |i| per_patch[i]);
    // Each element's corners' ΔB + R, once per sweep rather than at every
    // ray that lands on it.
    let corners: Vec<[Rgb; 4]> = room
        .elements
        .par_iter()
        .zip(unshot.corners)
        .map(|(&e, unshot)| {
            let mut values = *unshot;
            for (value, &v) in values.iter_mut().zip(&mesh.elements[e as usize].vertices) {
                *value += further_at(v);
            }
            values
        })
        .collect();
    let value_at = |k: usize| {
        let landed = unshot.landed[k];
        let i = local.element(landed.element()?)?;
        landed.value(mesh, |_| corners[i])
    };
    rays.gather(mesh, &value_at, &fallback, lossless)
}

/// Σ |a − b| / Σ a over the vertices, channels summed (0 where `a` is dark).
fn mean_change(next: &[Rgb], last: &[Rgb]) -> f64 {
    let (mut change, mut total) = (0.0, 0.0);
    for (a, b) in next.iter().zip(last) {
        change += (*a - *b).abs().element_sum();
        total += a.element_sum();
    }
    if total > 0.0 { change / total } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_change_is_relative_to_the_new_estimate() {
        let next = [Rgb::splat(1.0), Rgb::splat(3.0)];
        let last = [Rgb::splat(1.5), Rgb::splat(3.0)];
        assert!((mean_change(&next, &last) - 0.5 / 4.0).abs() < 1e-12);
        assert_eq!(mean_change(&[Rgb::ZERO], &[Rgb::splat(1.0)]), 0.0);
    }
}
