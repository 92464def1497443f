//! Dominant-small-emitter analysis: which receivers get the radial contour
//! mesher.
//!
//! The seed's contour mesher follows the level sets of one emitter's light.
//! That pays on a receiver when one light supplies most of its direct
//! light (the others only add a smooth background) and that light is
//! small against its distance (its field is close to the small-disc model:
//! one smooth peak, contours star-shaped about it). For each non-emitting
//! surface this module estimates each light's share of the direct light,
//! shadows included, and the dominant one's size ratio.
//!
//! # References
//! P. Arquès, V. Biri, S. Derpierre, "A new formulation of differential
//! radiosity and a rendering application", WSCG 2005, §4.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::area_light::AreaLight;
use super::direct_field::DirectField;
use super::sample_stream::SampleStream;
use super::stratified::stratified_points;
use crate::error::{Error, Result};
use crate::phase::{Phase, PhaseCounter, PhaseReporter, silent};
use crate::scene::{Scene, Surface, SurfaceId, Visibility, polygon_contains};

/// Receiver sample points are pulled this fraction of the way towards their
/// triangle's centroid, keeping them off edges shared with walls.
const SAMPLE_SHRINK: f64 = 0.01;

/// Settings of [`analyse_receivers`]. Plain data: set the fields you need.
/// In a scene file: `[mesh.dominance]`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct DominanceSettings {
    /// A light dominates a receiver when it gives at least this share of
    /// the receiver's direct light (0.6). Above ½, so that two equal lamps
    /// never pass (no one contour family fits both); below 1 with room for a
    /// dim fill light, whose smooth background the mesh's vertices still
    /// gather exactly, since every shooter lights them.
    pub min_share: f64,
    /// The dominant light is small when its radius over its distance to
    /// the receiver is under this (0.25). The point-source kernel differs
    /// from a disc's by the factor 1 + (R/r)², about 6 % at R/r = ¼: the
    /// field is still the small-disc model's single smooth peak (eq. 4.1),
    /// whose closed-form centre (eq. 4.2) starts the ascent near the truth.
    /// The distance is from the light's centre to the receiver's point
    /// of maximum light if that lies on the receiver, else to the nearest
    /// point of the receiver.
    pub max_size_ratio: f64,
    /// Points on the receiver where each light's direct light is
    /// estimated (16): stratified over the polygon
    /// (equal-area strata), like a 4 × 4 grid, enough to rank lights
    /// whose shares differ by more than a few per cent.
    pub sample_points: usize,
    /// Shadow rays per light polygon at each sample point (4): a
    /// receiver in a light's full shadow must not be dominated by it,
    /// and a coarse penumbra estimate suffices for a share.
    pub shadow_rays: usize,
}

impl Default for DominanceSettings {
    fn default() -> DominanceSettings {
        DominanceSettings {
            min_share: 0.6,
            max_size_ratio: 0.25,
            sample_points: 16,
            shadow_rays: 4,
        }
    }
}

impl DominanceSettings {
    /// Checks the ranges: `min_share` in (0, 1], `max_size_ratio` positive
    /// and finite, at least one sample point and one shadow ray. An
    /// [`Error::InvalidSetting`] names the field (`min_share`).
    pub fn validate(&self) -> Result<()> {
        let invalid = |name: &str, message: String| Error::InvalidSetting {
            name: name.into(),
            message,
        };
        if !(self.min_share > 0.0 && self.min_share <= 1.0) {
            let message = format!("{} is not in (0, 1]", self.min_share);
            return Err(invalid("min_share", message));
        }
        if !(self.max_size_ratio > 0.0 && self.max_size_ratio.is_finite()) {
            let message = format!("{} is not positive", self.max_size_ratio);
            return Err(invalid("max_size_ratio", message));
        }
        for (name, count) in [
            ("sample_points", self.sample_points),
            ("shadow_rays", self.shadow_rays),
        ] {
            if count == 0 {
                return Err(invalid(name, "must be at least 1".into()));
            }
        }
        Ok(())
    }
}

/// What [`analyse_receivers`] found on one receiver.
#[derive(Clone, Debug, PartialEq)]
pub struct ReceiverAnalysis {
    /// The receiving surface.
    pub receiver: SurfaceId,
    /// The light giving at least `min_share` of the receiver's direct
    /// light, if any: an index into the area lights analysed, followed
    /// by the scene's photometric luminaires (index `area_lights.len() + k`
    /// for `scene.luminaires[k]`; see [`dominant_field`]).
    pub dominant: Option<usize>,
    /// The strongest light's share of the direct light, in [0, 1]
    /// (0 when no light arrives), whether or not it dominates.
    pub share: f64,
    /// The strongest light's radius over its distance to the receiver;
    /// infinite when no light arrives.
    pub size_ratio: f64,
    /// Dominated by a small light: the radial contour mesher applies.
    pub qualifies: bool,
    /// Every light giving at least 1 % of the receiver's direct light, in
    /// the order of `dominant`'s indices: the total direct field the
    /// level-line contour mesher follows.
    pub lit_by: Vec<usize>,
}

/// Which contour layout a receiver gets under `MeshKind::Contour`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContourMesher {
    /// The radial contour-level layout around the dominant small light's
    /// maximum.
    Radial,
    /// Level lines of the total direct field of every light that reaches it
    /// (several lights, or one that is not small).
    LevelLines,
    /// No direct light: the square grid.
    Square,
}

impl ReceiverAnalysis {
    /// The contour layout this receiver gets: radial when a small light
    /// dominates it, level lines when any light reaches it, else square.
    #[must_use]
    pub fn contour_mesher(&self) -> ContourMesher {
        if self.qualifies {
            ContourMesher::Radial
        } else if self.lit_by.is_empty() {
            ContourMesher::Square
        } else {
            ContourMesher::LevelLines
        }
    }

    /// The lights whose direct field this receiver's contour layout
    /// follows: the dominant one for [`ContourMesher::Radial`], every one
    /// in `lit_by` for [`ContourMesher::LevelLines`], none for the grid.
    #[must_use]
    pub fn contour_lights(&self) -> Vec<usize> {
        match (self.contour_mesher(), self.dominant) {
            (ContourMesher::Radial, Some(dominant)) => vec![dominant],
            _ => self.lit_by.clone(),
        }
    }
}

/// A light is among a receiver's `lit_by` when it gives at least this
/// share of the direct light.
const LIT_BY_SHARE: f64 = 0.01;

/// Analyses every non-emitting surface of the scene (in order), in parallel.
///
/// For a receiver with stratified sample points x_k of areas a_k, the direct
/// light of light j (an area light or a photometric luminaire) is
/// estimated as
///
/// ```text
///   D_j = Σ_k a_k · B_j(x_k) · V_j(x_k)
/// ```
///
/// with B_j the exact unoccluded field ([`DirectField::value`]) and V_j the
/// visible fraction ([`DirectField::visible_fraction`], `shadow_rays` rays
/// per polygon). The strongest light j* has share D_j*/Σ_j D_j; it
/// dominates when that reaches `min_share`, and the receiver qualifies for
/// the contour mesher when also radius_j*/distance < `max_size_ratio`.
///
/// # References
/// Arquès, Biri, Derpierre, WSCG 2005, §4 (the dominant small emitter).
#[must_use]
pub fn analyse_receivers(
    scene: &Scene,
    visibility: &Visibility,
    area_lights: &[AreaLight],
    settings: &DominanceSettings,
) -> Vec<ReceiverAnalysis> {
    let all: Vec<usize> = (0..area_lights.len() + scene.luminaires.len()).collect();
    analyse_receivers_among(scene, area_lights, settings, &|_| (visibility, all.clone()))
}

/// [`analyse_receivers`], with each receiver paired only with the lights
/// that `room_of(receiver)` lists (indices in [`dominant_field`]'s order,
/// ascending; the others give it no light), its shadow rays traced through
/// the BVH given with them: the lights and the surfaces of its own
/// closed room, so that a building of separate rooms costs what its rooms
/// cost alone instead of every receiver times every light.
#[must_use]
pub fn analyse_receivers_among<'v>(
    scene: &Scene,
    area_lights: &[AreaLight],
    settings: &DominanceSettings,
    room_of: &(dyn Fn(SurfaceId) -> (&'v Visibility, Vec<usize>) + Sync),
) -> Vec<ReceiverAnalysis> {
    analyse_receivers_reporting(scene, area_lights, settings, room_of, &silent)
}

/// [`analyse_receivers_among`], reporting its progress receiver by
/// receiver as [`Phase::Dominance`].
pub(crate) fn analyse_receivers_reporting<'v>(
    scene: &Scene,
    area_lights: &[AreaLight],
    settings: &DominanceSettings,
    room_of: &(dyn Fn(SurfaceId) -> (&'v Visibility, Vec<usize>) + Sync),
    report: PhaseReporter,
) -> Vec<ReceiverAnalysis> {
    let receivers: Vec<SurfaceId> = scene
        .surfaces_with_ids()
        .filter(|(_, surface)| {
            !scene
                .materials
                .get(surface.material)
                .is_some_and(|m| m.is_emitter())
        })
        .map(|(id, _)| id)
        .collect();
    let counter = PhaseCounter::start(Phase::Dominance, receivers.len(), report);
    let analyses = receivers
        .par_iter()
        .map(|&receiver| {
            let (visibility, lights) = room_of(receiver);
            let analysis =
                analyse_receiver(scene, visibility, area_lights, settings, receiver, &lights);
            counter.add(1);
            analysis
        })
        .collect();
    counter.finish();
    analyses
}

/// The analysis of one receiver.
fn analyse_receiver(
    scene: &Scene,
    visibility: &Visibility,
    area_lights: &[AreaLight],
    settings: &DominanceSettings,
    receiver: SurfaceId,
    lights: &[usize],
) -> ReceiverAnalysis {
    let surface = scene.surface(receiver);
    // Stratified sample points, and each light's direct light on them.
    let mut random = SampleStream::new(u64::from(receiver), 0xD0_4A11);
    let polygon = surface.plane_vertices();
    let points = stratified_points(
        &polygon,
        settings.sample_points.max(1),
        SAMPLE_SHRINK,
        &mut random,
    );
    // Each light's index, direct light and field.
    let light: Vec<(usize, f64, Option<DirectField>)> = lights
        .iter()
        .map(|&k| {
            let field = dominant_field(scene, receiver, area_lights, k);
            let direct = field.as_ref().map_or(0.0, |field| {
                direct_light(field, visibility, &points, settings.shadow_rays)
            });
            (k, direct, field)
        })
        .collect();
    // The strongest light and its share.
    let total: f64 = light.iter().map(|(_, d, _)| d).sum();
    let strongest = light.iter().max_by(|a, b| a.1.total_cmp(&b.1));
    let (Some((best, best_light, best_field)), true) =
        (strongest, total > 0.0 && total.is_finite())
    else {
        return ReceiverAnalysis {
            receiver,
            dominant: None,
            share: 0.0,
            size_ratio: f64::INFINITY,
            qualifies: false,
            lit_by: Vec::new(),
        };
    };
    let best = *best;
    let lit_by = light
        .iter()
        .filter(|(_, direct, _)| *direct >= LIT_BY_SHARE * total)
        .map(|(k, _, _)| *k)
        .collect();
    let share = (best_light / total).clamp(0.0, 1.0);
    let (centre, radius) = match area_lights.get(best) {
        Some(lamp) => (lamp.centre, lamp.radius),
        None => {
            let luminaire = &scene.luminaires[best - area_lights.len()];
            (luminaire.position, luminaire.opening_radius())
        }
    };
    let size_ratio = best_field.as_ref().map_or(f64::INFINITY, |field| {
        let distance = light_distance(field, surface, centre);
        if distance > 0.0 {
            radius / distance
        } else {
            f64::INFINITY
        }
    });
    let dominant = (share >= settings.min_share).then_some(best);
    ReceiverAnalysis {
        receiver,
        dominant,
        share,
        size_ratio,
        qualifies: dominant.is_some() && size_ratio < settings.max_size_ratio,
        lit_by,
    }
}

/// The direct field on `receiver` of light `k` in the analysis's order:
/// area light `area_lights[k]`, or photometric luminaire
/// `scene.luminaires[k − area_lights.len()]`; `None` when it cannot light the
/// receiver or `k` is out of range.
#[must_use]
pub fn dominant_field(
    scene: &Scene,
    receiver: SurfaceId,
    area_lights: &[AreaLight],
    k: usize,
) -> Option<DirectField> {
    match area_lights.get(k) {
        Some(lamp) => DirectField::new(scene, receiver, lamp),
        None => DirectField::photometric(
            scene,
            receiver,
            scene.luminaires.get(k - area_lights.len())?,
        ),
    }
}

/// D = Σ_k a_k B(x_k) V(x_k) over the sample points (x_k, a_k).
fn direct_light(
    field: &DirectField,
    visibility: &Visibility,
    points: &[(DVec2, f64)],
    shadow_rays: usize,
) -> f64 {
    points
        .iter()
        .map(|&(p, area)| {
            let unoccluded = field.value(p);
            if unoccluded > 0.0 {
                area * unoccluded * field.visible_fraction(visibility, p, shadow_rays)
            } else {
                0.0
            }
        })
        .sum()
}

/// Distance from the light's centre to the receiver's point of maximum
/// light when that lies on the receiver, else to the receiver's nearest point.
fn light_distance(field: &DirectField, surface: &Surface, centre: DVec3) -> f64 {
    let frame = field.frame();
    let polygon = surface.plane_vertices();
    let point = match field.maximum() {
        Some(peak) if polygon_contains(&polygon, peak) => peak,
        _ => nearest_point(&polygon, frame.to_plane(centre)),
    };
    centre.distance(frame.to_world(point))
}

/// The point of a polygon (plane coordinates) nearest to `p`: p itself when
/// inside, else the nearest point of its boundary.
fn nearest_point(polygon: &[DVec2], p: DVec2) -> DVec2 {
    if polygon_contains(polygon, p) || polygon.is_empty() {
        return p;
    }
    (0..polygon.len())
        .map(|k| {
            let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
            let edge = b - a;
            let t =
                ((p - a).dot(edge) / edge.length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
            a + edge * t
        })
        .min_by(|a, b| a.distance(p).total_cmp(&b.distance(p)))
        .unwrap_or(p)
}
