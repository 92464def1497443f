//! The direct radiosity of one light on one receiver's plane: the scalar
//! field the radial contour-level mesher meshes.
//!
//! A photometric luminaire ([`DirectField::photometric`]) gives
//! B(x) = Y(ρ ⊙ tint) / 179 lm/W · I(C, γ) cos θ / r², with the gradient of
//! [`PhotometricLuminaire::illuminance_with_gradient`] (analytic through the
//! web's bilinear interpolation), its visibility the share of its luminous
//! opening seen, and no kink line. An area light gives the following.
//!
//! For a receiver of reflectance ρ (per channel) and a light of exitance
//! E made of planar polygons P_i with emitting normal m and centre c, the
//! unoccluded direct radiosity at a point x of the receiver's plane (normal
//! n) is
//!
//! ```text
//!   B_S(x) = Y(ρ ⊙ E) · Σ_i F(x → P_i)     where m · (x − c) > 0, else 0
//! ```
//!
//! with F Lambert's exact point-to-polygon form factor and
//! Y(r, g, b) = 0.2126 r + 0.7152 g + 0.0722 b (Rec. 709 luminance), so that
//! one scalar stands for the three channels as an eye weighs them. Its
//! gradient is Arvo's (`polygon_form_factor_with_gradient`) projected on the
//! plane's axes u, v. The field is continuous; it has a kink on the line where
//! the light's plane cuts the receiver's (beyond it the light shows
//! its back), which [`DirectField::kink_line`] gives.
//!
//! # References
//! J. H. Lambert, *Photometria* (1760); J. Arvo, "The Irradiance Jacobian for
//! Partially Occluded Polyhedral Sources", SIGGRAPH 1994; P. Arquès,
//! V. Biri, S. Derpierre, "A new formulation of differential radiosity and a
//! rendering application", WSCG 2005 (§4: the contour mesher this field
//! feeds); ITU-R BT.709 (the luminance weights).

use glam::{DVec2, DVec3};

use super::area_light::AreaLight;
use super::sample_stream::SampleStream;
use super::stratified::stratified_points;
use crate::photometry::LUMENS_PER_WATT;
use crate::radiometry::{DiscModel, ReceiverPlane, SmallDisc, polygon_form_factor_with_gradient};
use crate::scene::{PhotometricLuminaire, PlaneFrame, Scene, SurfaceId, Visibility};

/// Most iterations of the ascent in [`DirectField::maximum`].
const MAX_ASCENT_STEPS: usize = 100;

/// Most step halvings per ascent step.
const MAX_HALVINGS: usize = 60;

/// One light's direct radiosity on one receiver's plane, in the
/// receiver's plane coordinates ([`crate::scene::Surface::frame`]).
#[derive(Clone, Debug)]
pub struct DirectField {
    /// The receiver's frame: plane coordinates and its front normal n.
    frame: PlaneFrame,
    /// The receiving surface.
    receiver: SurfaceId,
    /// What gives the light.
    source: FieldSource,
    /// Radiosity per unit of the source's raw field: Y(ρ ⊙ E), W/m², for
    /// an area light (per unit form factor); Y(ρ ⊙ tint) / 179 lm/W
    /// for a photometric one (per lux).
    scale: f64,
    /// Length scale of the geometry: max(|height of the centre|, radius).
    length: f64,
}

/// The two kinds of light a field can come from.
#[derive(Clone, Debug)]
enum FieldSource {
    /// Emitting polygons: the raw field is Σ_i F(x → P_i).
    Polygons {
        /// The light's polygons (world) with their surfaces.
        polygons: Vec<(SurfaceId, Vec<DVec3>)>,
        /// The same polygons in `light_frame`'s plane coordinates.
        plane_polygons: Vec<Vec<DVec2>>,
        /// The light's plane: origin at its centre, normal m.
        light_frame: PlaneFrame,
        /// The light's area.
        light_area: f64,
    },
    /// A photometric luminaire: the raw field is its unoccluded
    /// illuminance, lx ([`PhotometricLuminaire::illuminance_with_gradient`]).
    Photometric(Box<PhotometricLuminaire>),
}

impl DirectField {
    /// The field of `area_light` on surface `receiver`'s plane.
    ///
    /// `None` when the light cannot light the receiver's front: no vertex
    /// of the light in front of the receiver's plane, or no vertex of the
    /// receiver in front of the light's; also for a receiver index out of
    /// range, a receiver that is part of the light, a light without
    /// valid surfaces, a zero normal or a non-finite scale.
    #[must_use]
    pub fn new(scene: &Scene, receiver: SurfaceId, area_light: &AreaLight) -> Option<DirectField> {
        let surface = scene.surfaces.get(receiver.index())?;
        let frame = *surface.frame();
        let m = area_light.normal.normalize_or_zero();
        let usable = !area_light.surfaces.is_empty()
            && !area_light.surfaces.contains(&receiver)
            && m != DVec3::ZERO
            && area_light.centre.is_finite();
        if !usable {
            return None;
        }
        let polygons: Vec<(SurfaceId, Vec<DVec3>)> = area_light
            .surfaces
            .iter()
            .map(|&id| Some((id, scene.surfaces.get(id.index())?.vertices().to_vec())))
            .collect::<Option<_>>()?;
        // Some of the area light in front of the receiver, some of the receiver in front of it.
        let length = frame.height(area_light.centre).abs().max(area_light.radius);
        let tolerance = 1e-9 * (length + area_light.centre.distance(frame.origin));
        let light_frame = PlaneFrame::new(area_light.centre, m);
        let lights_plane = polygons
            .iter()
            .flat_map(|(_, p)| p)
            .any(|&v| frame.height(v) > tolerance);
        let faces_receiver = surface
            .vertices()
            .iter()
            .any(|&v| light_frame.height(v) > tolerance);
        let material = scene.materials.get(surface.material)?;
        let scale = (material.reflectance * area_light.exitance).luminance();
        if !(lights_plane && faces_receiver && scale.is_finite() && length > 0.0) {
            return None;
        }
        let plane_polygons = polygons
            .iter()
            .map(|(_, p)| p.iter().map(|&v| light_frame.to_plane(v)).collect())
            .collect();
        Some(DirectField {
            frame,
            receiver,
            source: FieldSource::Polygons {
                polygons,
                plane_polygons,
                light_frame,
                light_area: area_light.area,
            },
            scale,
            length,
        })
    }

    /// The field of photometric luminaire `luminaire` on surface
    /// `receiver`'s plane: B(p) = Y(ρ ⊙ tint) / 179 lm/W · E_v(p), with
    /// E_v = I(C, γ) · multiplier · cos θ / r² and its analytic gradient
    /// through the web's interpolation.
    ///
    /// `None` when the luminaire's centre is not in front of the receiver's
    /// plane, for a receiver index out of range, or a non-finite scale.
    #[must_use]
    pub fn photometric(
        scene: &Scene,
        receiver: SurfaceId,
        luminaire: &PhotometricLuminaire,
    ) -> Option<DirectField> {
        let surface = scene.surfaces.get(receiver.index())?;
        let frame = *surface.frame();
        let height = frame.height(luminaire.position);
        let length = height.max(luminaire.opening_radius());
        let material = scene.materials.get(surface.material)?;
        let scale = (material.reflectance * luminaire.color).luminance() / LUMENS_PER_WATT;
        if !(height > 0.0 && scale.is_finite() && length.is_finite()) {
            return None;
        }
        Some(DirectField {
            frame,
            receiver,
            source: FieldSource::Photometric(Box::new(luminaire.clone())),
            scale,
            length,
        })
    }

    /// The receiver's plane frame, in whose coordinates the field is given.
    #[must_use]
    pub fn frame(&self) -> &PlaneFrame {
        &self.frame
    }

    /// The radiosity per unit of the raw field: Y(ρ ⊙ E), W/m², per unit
    /// form factor for an area light; Y(ρ ⊙ tint) / 179 lm/W per lux
    /// for a photometric one.
    #[must_use]
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The geometry's length scale: the larger of the light's height
    /// over the receiver's plane and its radius.
    #[must_use]
    pub fn length_scale(&self) -> f64 {
        self.length
    }

    /// The light's centre (world): its area's centroid, or the
    /// photometric centre.
    #[must_use]
    pub fn centre(&self) -> DVec3 {
        match &self.source {
            FieldSource::Polygons { light_frame, .. } => light_frame.origin,
            FieldSource::Photometric(luminaire) => luminaire.position,
        }
    }

    /// Unoccluded direct radiosity B_S(p) = Y(ρ ⊙ E) · Σ_i F(p → P_i), W/m²,
    /// and its gradient (∂B/∂u, ∂B/∂v) in plane coordinates, W/m² per unit
    /// length (for a photometric luminaire, Y(ρ ⊙ tint) / 179 · E_v(p) and
    /// its analytic gradient). Exact: Lambert's form factor and Arvo's gradient
    /// ([`crate::radiometry::polygon_form_factor_with_gradient`]), the in-plane gradient
    /// projected on the frame's u and v. Zero (with a zero gradient) behind
    /// the light's plane and at non-finite p.
    ///
    /// # References
    /// Lambert (1760); Arvo, SIGGRAPH 1994.
    #[must_use]
    pub fn value_and_gradient(&self, p: DVec2) -> (f64, DVec2) {
        let (f, g) = self.form_factor_with_gradient(p);
        (self.scale * f, g * self.scale)
    }

    /// Unoccluded direct radiosity B_S(p), W/m² (see
    /// [`value_and_gradient`](Self::value_and_gradient)).
    #[must_use]
    pub fn value(&self, p: DVec2) -> f64 {
        self.value_and_gradient(p).0
    }

    /// The source's raw field at p (Σ_i F(p → P_i), or a photometric
    /// light's illuminance in lx) and its gradient in plane coordinates.
    fn form_factor_with_gradient(&self, p: DVec2) -> (f64, DVec2) {
        let x = self.frame.to_world(p);
        if !x.is_finite() {
            return (0.0, DVec2::ZERO);
        }
        let (f, g) = match &self.source {
            FieldSource::Polygons {
                polygons,
                light_frame,
                ..
            } => {
                if light_frame.height(x) <= 0.0 {
                    return (0.0, DVec2::ZERO);
                }
                let (mut f, mut g) = (0.0, DVec3::ZERO);
                for (_, polygon) in polygons {
                    let (fi, gi) = polygon_form_factor_with_gradient(x, self.frame.normal, polygon);
                    f += fi;
                    g += gi;
                }
                (f, g)
            }
            FieldSource::Photometric(luminaire) => {
                luminaire.illuminance_with_gradient(x, self.frame.normal)
            }
        };
        (f, DVec2::new(g.dot(self.frame.u), g.dot(self.frame.v)))
    }

    /// The fraction of the light that reaches p unblocked:
    ///
    /// ```text
    ///   V(p) = Σ_k δ_k w_k / Σ_k w_k,   w_k = a_k cosθ_r cosθ_s / r_k²
    /// ```
    ///
    /// over `samples` stratified points y_k per polygon (areas a_k, see
    /// `stratified_points`), δ_k a shadow ray from p to y_k, both ends
    /// lifted off their surfaces by [`Visibility::surface_offset`] along
    /// their normals, as the solver does, and the receiver and the sampled
    /// surface ignored. The jitter is a hash of p: the same p gives the same
    /// answer. 0 where no sample faces p (behind the light, or all of it
    /// below the receiver's plane) or p is not finite.
    ///
    /// # References
    /// J. R. Wallace, K. A. Elmquist, E. A. Haines, "A Ray Tracing Algorithm
    /// for Progressive Radiosity", SIGGRAPH 1989.
    #[must_use]
    pub fn visible_fraction(&self, visibility: &Visibility, p: DVec2, samples: usize) -> f64 {
        let x = self.frame.to_world(p);
        let (
            FieldSource::Polygons {
                polygons,
                plane_polygons,
                light_frame,
                ..
            },
            true,
        ) = (&self.source, x.is_finite())
        else {
            return self.opening_fraction(visibility, x);
        };
        if light_frame.height(x) <= 0.0 {
            return 0.0;
        }
        let (n, m) = (self.frame.normal, light_frame.normal);
        let offset = visibility.surface_offset();
        let from = x + n * offset;
        let mut random = SampleStream::new(p.x.to_bits() ^ u64::from(self.receiver), p.y.to_bits());
        let (mut visible, mut total) = (0.0, 0.0);
        for ((surface, _), polygon) in polygons.iter().zip(plane_polygons) {
            for (q, area) in stratified_points(polygon, samples.max(1), 0.0, &mut random) {
                // The point-kernel weight of the sample; nothing if either faces away.
                let y = light_frame.to_world(q);
                let d = y - x;
                let r2 = d.length_squared();
                let (cos_r, cos_s) = (n.dot(d), -m.dot(d));
                if cos_r <= 0.0 || cos_s <= 0.0 || r2 <= 0.0 {
                    continue;
                }
                let weight = area * cos_r * cos_s / (r2 * r2);
                total += weight;
                if visibility.is_unblocked(from, y + m * offset, [self.receiver, *surface]) {
                    visible += weight;
                }
            }
        }
        if total > 0.0 && (visible / total).is_finite() {
            visible / total
        } else {
            0.0
        }
    }

    /// A photometric luminaire's visible share at world point x: the
    /// fraction of its opening's sample points
    /// ([`PhotometricLuminaire::opening_samples`]) that x sees (the centre
    /// alone for a point source); 0 for an area light's field or a
    /// point that is not finite or not lit.
    fn opening_fraction(&self, visibility: &Visibility, x: DVec3) -> f64 {
        let FieldSource::Photometric(luminaire) = &self.source else {
            return 0.0;
        };
        if !x.is_finite() || self.frame.normal.dot(luminaire.position - x) <= 0.0 {
            return 0.0;
        }
        luminaire.visible_share(x, self.frame.normal, self.receiver, visibility)
    }

    /// Whether the light's centre c is visible from p (a point light's
    /// visibility, for finding shadow boundaries): p in front of the
    /// light, c in front of the receiver's plane, and the segment
    /// between them, ends lifted by [`Visibility::surface_offset`],
    /// unblocked.
    #[must_use]
    pub fn sees_centre(&self, visibility: &Visibility, p: DVec2) -> bool {
        let x = self.frame.to_world(p);
        let offset = visibility.surface_offset();
        let from = x + self.frame.normal * offset;
        match &self.source {
            FieldSource::Polygons {
                polygons,
                light_frame,
                ..
            } => {
                let c = light_frame.origin;
                let facing =
                    x.is_finite() && light_frame.height(x) > 0.0 && self.frame.height(c) > 0.0;
                facing
                    && visibility.is_unblocked(
                        from,
                        c + light_frame.normal * offset,
                        [self.receiver, polygons[0].0],
                    )
            }
            FieldSource::Photometric(luminaire) => {
                let c = luminaire.position;
                let back = (x - c).normalize_or_zero() * offset;
                x.is_finite()
                    && self.frame.height(c) > 0.0
                    && visibility.is_unblocked(from, c + back, [self.receiver, self.receiver])
            }
        }
    }

    /// Where the light's plane m · (x − c) = 0 cuts the receiver's plane,
    /// as (a point, a unit direction) in plane coordinates; `None` when the
    /// planes are parallel (|m × n| < 10⁻⁹). With a = (m·u, m·v), the line is
    /// m·(o − c) + a·q = 0, through q₀ = −m·(o − c) a/|a|² along (a_y, −a_x)/|a|;
    /// the lit side (in front of the light) lies to the left of that
    /// direction. The field has a kink there: the light ends.
    ///
    /// A photometric luminaire has no such plane: `None`.
    #[must_use]
    pub fn kink_line(&self) -> Option<(DVec2, DVec2)> {
        let FieldSource::Polygons { light_frame, .. } = &self.source else {
            return None;
        };
        let m = light_frame.normal;
        let a = DVec2::new(m.dot(self.frame.u), m.dot(self.frame.v));
        let sine = a.length();
        if sine.is_nan() || sine < 1e-9 {
            return None;
        }
        let offset = m.dot(self.frame.origin - light_frame.origin);
        let point = -a * (offset / (sine * sine));
        let direction = DVec2::new(a.y, -a.x) / sine;
        (point.is_finite() && direction.is_finite()).then_some((point, direction))
    }

    /// The point of the receiver's (infinite) plane where the field is
    /// largest, in plane coordinates; `None` when it is zero everywhere
    /// that is tried (no light reaches the plane).
    ///
    /// The start is the seed's closed form for a small disc of the
    /// light's area at its centre (point-source model,
    /// [`SmallDisc::maximum_on_plane`], eq. 4.2), or, when that is not lit,
    /// the best of the projections of the light's centre and vertices.
    /// It is refined on the exact field by safeguarded Newton: the Hessian
    /// from central differences of the analytic gradient; the Newton step
    /// −H⁻¹∇F when H is negative definite and the step climbs, else a step
    /// along ∇F; every step at most the geometry's length scale and halved
    /// until the field grows (or, within rounding of the peak, its gradient
    /// shrinks); at most 100 steps. The field's scale does not move the
    /// maximum, so this works on Σ F and a black receiver gets one too.
    ///
    /// # References
    /// P. Arquès, V. Biri, S. Derpierre, WSCG 2005, eq. 4.2; J. Nocedal,
    /// S. J. Wright, *Numerical Optimization* (2006), ch. 3 (backtracking).
    #[must_use]
    pub fn maximum(&self) -> Option<DVec2> {
        let start = self.ascent_start()?;
        let peak = self.ascend(start);
        peak.is_finite().then_some(peak)
    }

    /// The lit starting point of the ascent: for an area light the
    /// small disc's peak if lit, else the best projection of the
    /// light's centre or vertices; for a photometric one, the best of
    /// the foot of its centre and the point its aim meets the plane.
    fn ascent_start(&self) -> Option<DVec2> {
        let candidates: Vec<DVec2> = match &self.source {
            FieldSource::Polygons {
                polygons,
                light_frame,
                light_area,
                ..
            } => {
                let disc = SmallDisc {
                    centre: light_frame.origin,
                    normal: light_frame.normal,
                    area: *light_area,
                    exitance: 1.0,
                };
                let plane = ReceiverPlane {
                    point: self.frame.origin,
                    normal: self.frame.normal,
                };
                let disc_peak = disc
                    .maximum_on_plane(DiscModel::PointSource, &plane)
                    .map(|w| self.frame.to_plane(w));
                let projections = std::iter::once(light_frame.origin)
                    .chain(polygons.iter().flat_map(|(_, p)| p.iter().copied()))
                    .map(|w| self.frame.to_plane(w));
                disc_peak.into_iter().chain(projections).collect()
            }
            FieldSource::Photometric(luminaire) => {
                let c = luminaire.position;
                let height = self.frame.height(c);
                let toward = -self.frame.normal.dot(luminaire.aim);
                let along_aim = (toward > 1e-9).then(|| c + luminaire.aim * (height / toward));
                std::iter::once(c)
                    .chain(along_aim)
                    .map(|w| self.frame.to_plane(w))
                    .collect()
            }
        };
        let (best, value) = candidates
            .into_iter()
            .map(|q| (q, self.form_factor_with_gradient(q).0))
            .fold((DVec2::ZERO, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        (value > 0.0).then_some(best)
    }

    /// Safeguarded Newton ascent of Σ F from a lit point.
    fn ascend(&self, start: DVec2) -> DVec2 {
        let mut p = start;
        let (mut f, mut g) = self.form_factor_with_gradient(p);
        for _ in 0..MAX_ASCENT_STEPS {
            // Stationary to rounding: done.
            if g.length() * self.length <= 1e-14 * f {
                break;
            }
            // Halve the step until the field grows, or, at the peak's
            // rounding level, the gradient shrinks.
            let mut step = self.ascent_step(p, g);
            let mut accepted = None;
            for _ in 0..MAX_HALVINGS {
                let q = p + step;
                let (fq, gq) = self.form_factor_with_gradient(q);
                let flat = fq >= f * (1.0 - 4.0 * f64::EPSILON) && gq.length() < g.length();
                if fq > f || flat {
                    accepted = Some((q, fq, gq));
                    break;
                }
                step *= 0.5;
            }
            let Some((q, fq, gq)) = accepted else { break };
            (p, f, g) = (q, fq, gq);
            if step.length() <= 1e-15 * self.length {
                break;
            }
        }
        p
    }

    /// The Newton step −H⁻¹g if H (central differences of the gradient) is
    /// negative definite and the step climbs, else a step along g; at most
    /// the length scale long.
    fn ascent_step(&self, p: DVec2, g: DVec2) -> DVec2 {
        let delta = 1e-4 * self.length;
        let gradient = |q: DVec2| self.form_factor_with_gradient(q).1;
        let du = (gradient(p + DVec2::X * delta) - gradient(p - DVec2::X * delta)) / (2.0 * delta);
        let dv = (gradient(p + DVec2::Y * delta) - gradient(p - DVec2::Y * delta)) / (2.0 * delta);
        let (huu, hvv, huv) = (du.x, dv.y, 0.5 * (du.y + dv.x));
        let determinant = huu * hvv - huv * huv;
        let newton = DVec2::new(hvv * g.x - huv * g.y, huu * g.y - huv * g.x) / -determinant;
        let step = if huu < 0.0 && determinant > 0.0 && newton.is_finite() && newton.dot(g) > 0.0 {
            newton
        } else {
            g.normalize_or_zero() * (0.5 * self.length)
        };
        step.clamp_length_max(self.length)
    }
}
