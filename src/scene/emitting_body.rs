//! Emitting bodies: a lamp modelled as many faces on many planes (a
//! tessellated lens, a globe, a faceted tube) lit as one luminaire.
//!
//! A modelling program exports a 7 cm lens as some two thousand triangles
//! on about as many planes. Shot face by face, such a lamp costs a shot,
//! a dominance estimate and a shadow-boundary cast per face. Joined, it is
//! one [`super::PhotometricLuminaire`] whose intensity distribution is
//! computed from its faces: a diffuse face i of area A_i, unit normal m_i
//! and exitance M sends I_i(ω) = (M/π) A_i max(0, m_i·ω), so the body sends
//!
//! ```text
//!   I(ω) = (M/π) Σ_i A_i max(0, m_i·ω)        (its projected area times L)
//! ```
//!
//! exactly in the far field, and the flux ∫ I dω = M Σ_i A_i. Near the
//! body, within [`NEAR_RADII`] of its radius, the far-field law is replaced
//! by the exact sum of Lambert's polygon factors of the faces that face the
//! point, E = M Σ_i F(x → P_i) (or, for a body of more than
//! [`MAX_EXACT_FACES`] faces, Wallace's disc term over area-stratified
//! points of it), blended into the far field over the next
//! [`BLEND_RADII`]. Shadows come from [`BODY_SAMPLES`] area-stratified
//! points on its faces, each weighted by the light it sends the receiver.
//!
//! # References
//! J. H. Lambert, *Photometria* (1760) (the projected area of a diffuse
//! body; the polygon factor); J. R. Wallace, K. A. Elmquist, E. A. Haines,
//! "A Ray Tracing Algorithm for Progressive Radiosity", SIGGRAPH 1989 (the
//! disc term and the sampled visibility).

use glam::DVec3;
use rayon::prelude::*;

use super::{ShadowCache, Surface, SurfaceId, Visibility};
use crate::photometry::{IntensityDistribution, LUMENS_PER_WATT, LuminousOpening, Symmetry};
use crate::radiometry::{disc_form_factor, polygon_form_factor};
use crate::rgb::Rgb;

/// Points on the body that shadow rays go to.
pub const BODY_SAMPLES: usize = 32;

/// Within this many body radii of its centre, a point gets the exact
/// near field: the far-field law's error grows as (radius / r)².
pub const NEAR_RADII: f64 = 8.0;

/// Over this many further radii the near field blends into the far field.
pub const BLEND_RADII: f64 = 4.0;

/// Bodies of more faces take their near field from area-stratified points
/// (Wallace's disc term) instead of every face's exact factor.
pub const MAX_EXACT_FACES: usize = 1024;

/// The web's steps, degrees: C and γ.
const C_STEP: f64 = 5.0;
const GAMMA_STEP: f64 = 2.5;

/// One face of the body.
#[derive(Clone, Debug, PartialEq)]
struct BodyFace {
    vertices: Vec<DVec3>,
    normal: DVec3,
    area: f64,
}

/// A point of the body standing for `area` of it, facing `normal`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodySample {
    /// Where it is (on a face).
    pub position: DVec3,
    /// The face's unit normal.
    pub normal: DVec3,
    /// The area it stands for.
    pub area: f64,
}

/// A lamp of emitting faces on more than one plane, as one light.
#[derive(Clone, Debug, PartialEq)]
pub struct EmittingBody {
    /// Its surfaces, ascending.
    pub surfaces: Vec<SurfaceId>,
    /// Its material's name, for messages.
    pub material: String,
    /// The area centroid of its faces.
    pub centre: DVec3,
    /// The largest distance from the centre to a vertex.
    pub radius: f64,
    /// Its faces' total area.
    pub area: f64,
    /// Exitance M = π L_e per channel, W/m².
    pub exitance: Rgb,
    faces: Vec<BodyFace>,
    shadow_samples: Vec<BodySample>,
    near_samples: Vec<BodySample>,
}

impl EmittingBody {
    /// The body of `surfaces`, whose geometry is `of_surfaces` (one
    /// each, in order), of one emitting material named `material` with
    /// exitance `exitance`. `None` without faces of positive area.
    #[must_use]
    pub fn new(
        surfaces: Vec<SurfaceId>,
        of_surfaces: &[&Surface],
        material: String,
        exitance: Rgb,
    ) -> Option<EmittingBody> {
        let faces: Vec<BodyFace> = of_surfaces
            .iter()
            .map(|surface| BodyFace {
                vertices: surface.vertices().to_vec(),
                normal: surface.normal(),
                area: surface.area(),
            })
            .filter(|f| f.area > 0.0 && f.area.is_finite() && f.normal.is_finite())
            .collect();
        let area: f64 = faces.iter().map(|f| f.area).sum();
        if !(area > 0.0 && area.is_finite()) {
            return None;
        }
        let centre = faces
            .iter()
            .map(|f| centroid(&f.vertices) * f.area)
            .sum::<DVec3>()
            / area;
        let radius = faces
            .iter()
            .flat_map(|f| &f.vertices)
            .map(|v| v.distance(centre))
            .fold(0.0, f64::max);
        let shadow_samples = stratified_samples(&faces, centre, radius, BODY_SAMPLES);
        let near_samples = if faces.len() > MAX_EXACT_FACES {
            stratified_samples(&faces, centre, radius, MAX_EXACT_FACES)
        } else {
            Vec::new()
        };
        Some(EmittingBody {
            surfaces,
            material,
            centre,
            radius,
            area,
            exitance,
            faces,
            shadow_samples,
            near_samples,
        })
    }

    /// The number of faces.
    #[must_use]
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// Σ_i A_i max(0, m_i·ω): the body's area projected towards the unit
    /// direction ω, as seen from far along it.
    #[must_use]
    pub fn projected_area(&self, direction: DVec3) -> f64 {
        self.faces
            .iter()
            .map(|f| f.area * f.normal.dot(direction).max(0.0))
            .sum()
    }

    /// The direction of the distribution's γ = 0: against the faces' mean
    /// normal when they lean one way (a lens facing down sends γ = 0
    /// down), else straight down the scene's −y.
    #[must_use]
    pub fn aim(&self) -> DVec3 {
        let mean: DVec3 = self.faces.iter().map(|f| f.normal * f.area).sum();
        if mean.length() > 0.05 * self.area {
            mean.normalize()
        } else {
            DVec3::NEG_Y
        }
    }

    /// Its intensity I(C, γ) = 179 lm/W · Y(M)/π · Σ A_i max(0, m_i·ω),
    /// candela per unit of tint, on a web of 5° in C and 2.5° in γ about
    /// `aim` and `c0`, with the luminous opening of a disc of its diameter.
    #[must_use]
    pub fn intensity_distribution(&self, aim: DVec3, c0: DVec3) -> IntensityDistribution {
        let c90 = (-aim).cross(c0);
        let per_area = LUMENS_PER_WATT * self.exitance.luminance() / std::f64::consts::PI;
        let steps = |step: f64, span: f64| (span / step).round() as usize;
        let c_angles: Vec<f64> = (0..=steps(C_STEP, 360.0))
            .map(|k| k as f64 * C_STEP)
            .collect();
        let gamma_angles: Vec<f64> = (0..=steps(GAMMA_STEP, 180.0))
            .map(|k| k as f64 * GAMMA_STEP)
            .collect();
        let planes: Vec<Vec<f64>> = c_angles
            .par_iter()
            .map(|&c| {
                let (sc, cc) = c.to_radians().sin_cos();
                gamma_angles
                    .iter()
                    .map(|&g| {
                        let (sg, cg) = g.to_radians().sin_cos();
                        let omega = aim * cg + (c0 * cc + c90 * sc) * sg;
                        per_area * self.projected_area(omega)
                    })
                    .collect()
            })
            .collect();
        let opening = LuminousOpening {
            width: -2.0 * self.radius,
            length: 0.0,
            height: 0.0,
        };
        IntensityDistribution::from_planes(
            Symmetry::None,
            &c_angles,
            &gamma_angles,
            &planes,
            opening,
        )
    }

    /// Whether `x` is near enough for the near field, and the far field's
    /// weight there: 0 within [`NEAR_RADII`] radii, rising linearly to 1
    /// over the next [`BLEND_RADII`].
    #[must_use]
    pub fn far_weight(&self, x: DVec3) -> f64 {
        let radii = x.distance(self.centre) / self.radius.max(f64::MIN_POSITIVE);
        ((radii - NEAR_RADII) / BLEND_RADII).clamp(0.0, 1.0)
    }

    /// The unoccluded irradiance at `x` facing the unit `normal`, per unit
    /// exitance: Σ_i F(x → P_i) over the faces whose front x is before
    /// (Lambert, exact), or over the near samples by Wallace's disc term
    /// for a body of many faces.
    #[must_use]
    pub fn near_factor(&self, x: DVec3, normal: DVec3) -> f64 {
        if self.near_samples.is_empty() {
            return self
                .faces
                .iter()
                .filter(|f| f.normal.dot(x - f.vertices[0]) > 0.0)
                .map(|f| polygon_form_factor(x, normal, &f.vertices).max(0.0))
                .sum();
        }
        self.near_samples
            .iter()
            .map(|s| {
                let d = s.position - x;
                let r2 = d.length_squared();
                let r = r2.sqrt();
                if r <= 0.0 {
                    return 0.0;
                }
                disc_form_factor(s.area, normal.dot(d) / r, -s.normal.dot(d) / r, r2)
            })
            .sum()
    }

    /// The shadow rays' targets: [`BODY_SAMPLES`] points stratified by
    /// area over the faces, in an order that keeps strata compact.
    #[must_use]
    pub fn shadow_samples(&self) -> &[BodySample] {
        &self.shadow_samples
    }

    /// The share of the body's light that reaches `x` (on `surface`, front
    /// normal `normal`) unblocked: Σ_k w_k δ_k / Σ_k w_k over the shadow
    /// samples y_k, w_k = a_k cosθ_r cosθ_s / r², δ_k a ray from `x`
    /// lifted a surface offset along `normal` to y_k lifted as far along
    /// its face's normal. Samples facing away weigh nothing; 0 when none
    /// faces x.
    #[must_use]
    pub fn visible_share(
        &self,
        x: DVec3,
        normal: DVec3,
        surface: SurfaceId,
        visibility: &Visibility,
    ) -> f64 {
        let offset = visibility.surface_offset();
        let start = x + normal * offset;
        let mut cache = ShadowCache::default();
        let (mut seen, mut total) = (0.0, 0.0);
        for sample in &self.shadow_samples {
            let d = sample.position - x;
            let r2 = d.length_squared();
            let (cos_r, cos_s) = (normal.dot(d), -sample.normal.dot(d));
            if cos_r <= 0.0 || cos_s <= 0.0 || r2 <= 0.0 {
                continue;
            }
            let weight = sample.area * cos_r * cos_s / (r2 * r2);
            total += weight;
            let target = sample.position + sample.normal * offset;
            if visibility.is_unblocked_cached(start, target, [surface, surface], &mut cache) {
                seen += weight;
            }
        }
        if total > 0.0 && (seen / total).is_finite() {
            seen / total
        } else {
            0.0
        }
    }

    /// Points shadow boundaries are cast from: the body's extreme vertex
    /// along each of the eight diagonals (±1, ±1, ±1), without repeats.
    #[must_use]
    pub fn outline(&self) -> Vec<DVec3> {
        let mut points: Vec<DVec3> = Vec::new();
        for k in 0..8 {
            let sign = |bit: i32| if k & bit == 0 { 1.0 } else { -1.0 };
            let direction = DVec3::new(sign(1), sign(2), sign(4));
            let extreme = self
                .faces
                .iter()
                .flat_map(|f| &f.vertices)
                .copied()
                .max_by(|a, b| a.dot(direction).total_cmp(&b.dot(direction)));
            if let Some(p) = extreme.filter(|p| !points.contains(p)) {
                points.push(p);
            }
        }
        points
    }
}

/// The mean of a polygon's vertices.
fn centroid(vertices: &[DVec3]) -> DVec3 {
    vertices.iter().sum::<DVec3>() / vertices.len().max(1) as f64
}

/// `count` points stratified by area over `faces`: the faces in Morton
/// order of their centroids (about the body's box of half-size `radius`
/// at `centre`) so that consecutive strata are near one another, the
/// stratum k at cumulative area (k + ½)/count of the total, placed in its
/// face's fan triangle at that area by the square-root map with the
/// radical inverse of k across.
fn stratified_samples(
    faces: &[BodyFace],
    centre: DVec3,
    radius: f64,
    count: usize,
) -> Vec<BodySample> {
    let morton = |p: DVec3| {
        let unit = ((p - centre) / (2.0 * radius.max(f64::MIN_POSITIVE)) + 0.5)
            .clamp(DVec3::ZERO, DVec3::ONE);
        let spread = |v: f64| {
            let mut x = (v * 1023.0) as u64;
            x = (x | (x << 16)) & 0x0300_00FF;
            x = (x | (x << 8)) & 0x0300_F00F;
            x = (x | (x << 4)) & 0x030C_30C3;
            (x | (x << 2)) & 0x0924_9249
        };
        spread(unit.x) | (spread(unit.y) << 1) | (spread(unit.z) << 2)
    };
    let mut order: Vec<usize> = (0..faces.len()).collect();
    order.sort_by_key(|&i| morton(centroid(&faces[i].vertices)));
    let total: f64 = faces.iter().map(|f| f.area).sum();
    let stratum = total / count as f64;
    let mut samples = Vec::with_capacity(count);
    let (mut before, mut next) = (0.0, 0usize);
    for &i in &order {
        let face = &faces[i];
        while next < count && ((next as f64 + 0.5) * stratum) < before + face.area {
            let within = ((next as f64 + 0.5) * stratum - before).max(0.0);
            let across = f64::from((next as u32).reverse_bits()) / 2f64.powi(32);
            samples.push(BodySample {
                position: point_in_face(face, within, across),
                normal: face.normal,
                area: stratum,
            });
            next += 1;
        }
        before += face.area;
    }
    samples
}

/// The point of a face (a fan of triangles from its first vertex) at area
/// `within` along the fan, `across` (in [0, 1)) across its triangle: the
/// square-root map of a triangle, s = √(share of the triangle's area).
fn point_in_face(face: &BodyFace, within: f64, across: f64) -> DVec3 {
    let v = &face.vertices;
    let mut left = within;
    for k in 1..v.len().saturating_sub(1) {
        let (a, b, c) = (v[0], v[k], v[k + 1]);
        let area = 0.5 * (b - a).cross(c - a).length();
        if left <= area || k + 2 == v.len() {
            let s = (left / area.max(f64::MIN_POSITIVE)).clamp(0.0, 1.0).sqrt();
            return a + (b - a) * (s * (1.0 - across)) + (c - a) * (s * across);
        }
        left -= area;
    }
    centroid(v)
}
