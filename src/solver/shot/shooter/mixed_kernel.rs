//! The `Mixed` kernel's gather: Wallace's disc term on far strata,
//! Lambert's exact factor on near ones, each times its own shadow ray.

use glam::{DVec2, DVec3};

use super::strata::Strata;
use super::{Gathered, NEAR_FIELD, Receiver, Shooter, ShotRadiosity};
use crate::lighting::SampleStream;
use crate::mesh::Cell;
use crate::radiometry::{disc_form_factor, polygon_form_factor};
use crate::rgb::Rgb;
use crate::scene::{ShadowCache, Visibility};
use crate::solver::light::cell_coordinates::nearest_point_of;

impl Shooter {
    /// The `Mixed` kernel: Wallace's disc term on far strata, Lambert's exact
    /// factor on near ones, each times its own shadow ray.
    ///
    /// Lambert's factor is additive over the strata, which tile the patch:
    /// Σ_near F_k = F_patch − Σ_far F_k. So the near strata's visible share is
    /// summed either directly over the visible ones or, when fewer factors
    /// are needed that way, as F_patch less the far and the hidden near
    /// strata's factors. A fully visible patch seen from nearby then costs
    /// one polygon factor instead of one per stratum; the result is the same
    /// sum, up to rounding. When the strata shoot different radiosities W_k
    /// ([`ShotRadiosity::Field`]), the complement gives the visible near
    /// strata's total factor F, which is shared among them in proportion to
    /// their disc terms g_k: H_near = F · Σ W_k g_k / Σ g_k (exact for a
    /// uniform shot; the direct sum when that is cheaper). That direct sum
    /// takes each visible near stratum's field by a control variate,
    /// W̄_k F_k + A_k k(y_k) (W(y_k) − W̄_k), with W̄_k the stratum's mean
    /// radiosity and k the point kernel cosθ_r cosθ_s / (π r²) at its
    /// sample: unbiased for ∫ ΔB k over the stratum, where W(y_k) F_k would
    /// weight ΔB evenly over a stratum seen from nearby (a whole patch,
    /// for a dim shot's one stratum) and light the receivers beside its dark
    /// part as if it were bright.
    ///
    /// The complement's share is biased where W varies across strata the
    /// receiver stands beside: the disc terms weigh the stratum under the
    /// receiver far less than its exact factor does (in the corner of a
    /// floor and a wall, a wall point just above a floor whose ΔB rises
    /// away from the wall receives up to twice the integral). Rooms'
    /// junctions are dim, so their vertices come out bright. The bias is
    /// kept: it offsets what the corners' interpolation loses where light
    /// falls off concavely into a junction, and the exact integral (strata
    /// beside the receiver split until each piece is farther than its size)
    /// took two to three times as long and moved every tested scene further
    /// from the path tracer; see CHANGELOG.md.
    pub(super) fn gather_mixed(
        &self,
        receiver: &Receiver,
        strata: &Strata,
        random: &mut SampleStream,
        visibility: &Visibility,
        cache: &mut ShadowCache,
    ) -> Gathered {
        // One shadow ray per stratum: the far strata's light, the near sorted.
        let mut pass = self.strata_pass(receiver, strata, random, visibility, cache);
        // The visible near strata's light, summed directly or as a complement.
        let near_visible_irradiance = self.near_visible_irradiance(receiver, strata, &mut pass);
        pass.gathered.irradiance = near_visible_irradiance + pass.far_visible;
        pass.gathered
    }

    /// The first pass of a `Mixed` gather: each stratum's shadow ray, to a
    /// jittered point of it (of its part above the receiver's plane when
    /// near), the far strata's disc terms summed where visible, and the
    /// near strata sorted into visible and hidden.
    fn strata_pass(
        &self,
        receiver: &Receiver,
        strata: &Strata,
        random: &mut SampleStream,
        visibility: &Visibility,
        cache: &mut ShadowCache,
    ) -> StrataPass {
        let (x, n) = (receiver.position, receiver.normal);
        let mut pass = StrataPass {
            gathered: Gathered::default(),
            far_visible: Rgb::ZERO,
            kinds: [(); 3].map(|()| StrataSet::new(strata.cells.len())),
            near_visible: 0,
            near_hidden: 0,
            far: 0,
            near_shape: Rgb::ZERO,
            near_weight: 0.0,
            near_radiosity: Rgb::ZERO,
            near_samples: Vec::new(),
            field_hint: 0,
        };
        let gathered = &mut pass.gathered;
        // The receiver's height above the source's plane, the same for every stratum.
        let receiver_height = self.normal.dot(x - self.cell.corners[0]);
        for (k, stratum) in strata.cells.iter().enumerate() {
            // The random numbers are drawn for every stratum, in order.
            let uv = DVec2::new(random.next_f64(), random.next_f64());
            let y = stratum.point(uv.x, uv.y);
            let d = y - x;
            let r2 = d.length_squared();
            let nearest = r2
                .min(n.dot(d).powi(2))
                .min(receiver_height * receiver_height);
            if nearest < NEAR_FIELD * stratum.area {
                // Aim at a part of the stratum above the receiver's plane.
                let Some((target, target_uv)) = near_target(x, n, stratum, y, uv) else {
                    continue;
                };
                gathered.rays += u32::from(!receiver.clear);
                gathered.known_visible += u32::from(receiver.clear);
                let seen =
                    receiver.clear || self.is_visible(receiver, target, visibility, &mut *cache);
                gathered.blocked += u32::from(!seen);
                if seen {
                    pass.kinds[NEAR_VISIBLE].insert(k);
                    pass.near_visible += 1;
                    let w = self.radiosity_at_target(
                        strata,
                        k,
                        target,
                        target_uv,
                        &mut pass.field_hint,
                    );
                    // The point kernel at the jittered sample, times the
                    // stratum's area (zero behind either plane).
                    let point_factor = {
                        let (r2, cos_r) = (d.length_squared(), n.dot(d));
                        let cos_s = -self.normal.dot(d);
                        if cos_r > 0.0 && cos_s > 0.0 && r2 > 0.0 {
                            stratum.area * cos_r * cos_s / (std::f64::consts::PI * r2 * r2)
                        } else {
                            0.0
                        }
                    };
                    pass.near_samples.push((k, w, point_factor));
                    let d = target - x;
                    let r2 = d.length_squared();
                    let r = r2.sqrt();
                    let g =
                        disc_form_factor(stratum.area, n.dot(d) / r, -self.normal.dot(d) / r, r2)
                            .max(0.0);
                    pass.near_shape += w * g;
                    pass.near_weight += g;
                    pass.near_radiosity += w;
                } else {
                    pass.kinds[NEAR_HIDDEN].insert(k);
                    pass.near_hidden += 1;
                }
            } else {
                pass.kinds[FAR].insert(k);
                pass.far += 1;
                let r = r2.sqrt();
                let factor =
                    disc_form_factor(stratum.area, n.dot(d) / r, -self.normal.dot(d) / r, r2);
                if factor > 0.0 {
                    gathered.rays += u32::from(!receiver.clear);
                    gathered.known_visible += u32::from(receiver.clear);
                    let seen =
                        receiver.clear || self.is_visible(receiver, y, visibility, &mut *cache);
                    gathered.blocked += u32::from(!seen);
                    if seen {
                        pass.far_visible += strata.at(k, uv) * factor;
                    }
                }
            }
        }
        pass
    }

    /// The second pass of a `Mixed` gather: the visible near strata's
    /// irradiance, each by its control variate where that takes fewer
    /// exact factors, else as the patch's exact factor less the far and
    /// the hidden near strata's, shared out by their disc terms.
    fn near_visible_irradiance(
        &self,
        receiver: &Receiver,
        strata: &Strata,
        pass: &mut StrataPass,
    ) -> Rgb {
        let (x, n) = (receiver.position, receiver.normal);
        let in_set = |set: usize| {
            let kinds = &pass.kinds;
            strata
                .cells
                .iter()
                .enumerate()
                .filter(move |(k, _)| kinds[set].contains(*k))
        };
        let lambert = |set: usize| -> f64 {
            in_set(set)
                .map(|(_, stratum)| polygon_form_factor(x, n, stratum.polygon()))
                .sum()
        };
        if pass.near_visible == 0 {
            Rgb::ZERO
        } else if pass.near_visible <= 1 + pass.far + pass.near_hidden {
            // Each visible near stratum's Σ_y ΔB(y) F(x, dy) by a control
            // variate: its mean radiosity W̄ times its exact factor, plus the
            // deviation at the jittered sample weighted by the point kernel,
            //   W̄ F_k + A_k k(y) (W(y) − W̄),
            // whose expectation is ∫ W k over the stratum. W(y) F_k alone
            // would weight ΔB evenly over a stratum seen from nearby, and
            // shift light from the patch's bright part to receivers beside
            // its dark part.
            //
            // A_k k(y) estimates F_k, which no stratum's factor exceeds: a
            // sample with A_k k(y) > 1 lies in the kernel's 1/r² spike right
            // beside the receiver, where the correction's variance is
            // unbounded (a sample a millimetre from a vertex in the corner
            // of a bookcase lit the shelf round it); it is capped at 1.
            //
            // Beside the stratum (closer than its size), the spike holds most
            // of ∫ k and the cap drops most of the correction, so the
            // baseline is W where the spike stands, at the stratum's point
            // nearest the receiver, rather than the mean: beside an object
            // standing on the patch, whose footprint the mean counts dark,
            // the mean lost a fifth of the light.
            let field_hint = &mut pass.field_hint;
            pass.near_samples
                .iter()
                .map(|&(k, w, point_factor)| {
                    let stratum = &strata.cells[k];
                    let baseline = self
                        .spike_radiosity(strata, k, x, field_hint)
                        .unwrap_or(strata.radiosity[k]);
                    let exact = polygon_form_factor(x, n, stratum.polygon());
                    (baseline * exact + (w - baseline) * point_factor.min(1.0)).max(Rgb::ZERO)
                })
                .sum()
        } else {
            let far_factor = if pass.far > 0 { lambert(FAR) } else { 0.0 };
            let hidden_factor = if pass.near_hidden > 0 {
                lambert(NEAR_HIDDEN)
            } else {
                0.0
            };
            let total =
                (polygon_form_factor(x, n, self.cell.polygon()) - far_factor - hidden_factor)
                    .max(0.0);
            let mean_radiosity = if pass.near_weight > 0.0 {
                pass.near_shape / pass.near_weight
            } else {
                pass.near_radiosity / f64::from(pass.near_visible)
            };
            mean_radiosity * total
        }
    }

    /// The radiosity a near stratum k shoots at its aimed point: the value
    /// of the sampled cell it falls in, unless that cell's centre found no
    /// element on a field shot, when ΔB is interpolated from the element
    /// under the point itself (nothing if none is). A cell's value is ΔB at
    /// its centre, and where an object stands on the patch a cell whose
    /// centre is under it reads nothing, though part of it is lit: a
    /// receiver on the object's side, just above the patch, sees mostly the
    /// patch within a few of its heights, and lost a twelfth of its light
    /// there.
    // Kept out of the strata pass's loop, whose far strata are the hot
    // path: inlined, this and `spike_radiosity` slowed the solve.
    #[inline(never)]
    fn radiosity_at_target(
        &self,
        strata: &Strata,
        k: usize,
        target: DVec3,
        uv: DVec2,
        hint: &mut usize,
    ) -> Rgb {
        match (&self.radiosity, self.exact_scale) {
            (ShotRadiosity::Field(field), Some(scale)) if !strata.found_at(k, uv) => field
                .unshot_at(target, hint)
                .map_or(Rgb::ZERO, |unshot| scale.apply(unshot)),
            _ => strata.at(k, uv),
        }
    }

    /// A field shot's radiosity at the point of stratum k nearest the
    /// receiver at x, when x is closer to the stratum than the stratum's
    /// size and an element lies under that point; `None` otherwise, or for
    /// a uniform shot.
    #[inline(never)]
    fn spike_radiosity(
        &self,
        strata: &Strata,
        k: usize,
        x: DVec3,
        hint: &mut usize,
    ) -> Option<Rgb> {
        let (ShotRadiosity::Field(field), Some(scale)) = (&self.radiosity, self.exact_scale) else {
            return None;
        };
        let stratum = &strata.cells[k];
        // Most near strata are several sizes away: rule them out by the
        // sphere round the stratum before looking for its nearest point.
        let (centre, beside) = strata.beside[k];
        if centre.distance_squared(x) >= beside * beside {
            return None;
        }
        let nearest = nearest_point_of(stratum, x);
        if (nearest - x).length_squared() >= stratum.area {
            return None;
        }
        field
            .unshot_at(nearest, hint)
            .map(|unshot| scale.apply(unshot))
    }
}

/// The sets of strata a `Mixed` gather sorts into (strata wholly behind the
/// receiver's plane are in none): near with an unblocked shadow ray, near
/// with a blocked one, and far (disc term, already counted).
const NEAR_VISIBLE: usize = 0;
const NEAR_HIDDEN: usize = 1;
const FAR: usize = 2;

/// What the first pass of a `Mixed` gather found: its rays, the far
/// strata's visible irradiance, and the near strata, sorted, for the
/// second pass.
struct StrataPass {
    gathered: Gathered,
    far_visible: Rgb,
    /// Which strata were near and visible, near and hidden, far.
    kinds: [StrataSet; 3],
    near_visible: i32,
    near_hidden: i32,
    far: i32,
    /// The visible near strata's Σ W_k g_k and Σ g_k, g_k their disc terms
    /// (how W varies over them, to share out their exact total factor),
    /// and their Σ W_k.
    near_shape: Rgb,
    near_weight: f64,
    near_radiosity: Rgb,
    /// The visible near strata and the radiosity each shoots at its sample.
    near_samples: Vec<(usize, Rgb, f64)>,
    /// The element of a field shot's patch that the last near sample fell in.
    field_hint: usize,
}

/// A set of stratum indices, one bit each, on the stack up to 256 strata.
struct StrataSet {
    small: [u64; 4],
    large: Vec<u64>,
}

impl StrataSet {
    fn new(len: usize) -> StrataSet {
        let large = if len > 256 {
            vec![0; len.div_ceil(64)]
        } else {
            Vec::new()
        };
        StrataSet {
            small: [0; 4],
            large,
        }
    }

    fn insert(&mut self, k: usize) {
        let words = if self.large.is_empty() {
            &mut self.small[..]
        } else {
            &mut self.large[..]
        };
        words[k / 64] |= 1 << (k % 64);
    }

    fn contains(&self, k: usize) -> bool {
        let words = if self.large.is_empty() {
            &self.small[..]
        } else {
            &self.large[..]
        };
        words[k / 64] & (1 << (k % 64)) != 0
    }
}

/// The point of a near stratum a shadow ray aims at, and its parameters in
/// the stratum: its jittered sample `y` (at `uv`) if above the receiver's
/// plane, else its centre or a corner that is; none when the whole stratum
/// is behind the plane (its factor is then zero). The stratum's radiosity
/// is read there too: a sample behind the plane may lie under the object
/// the receiver belongs to, where the shooter has no light.
fn near_target(x: DVec3, n: DVec3, stratum: &Cell, y: DVec3, uv: DVec2) -> Option<(DVec3, DVec2)> {
    let above = |p: &DVec3| n.dot(*p - x) > 0.0;
    if above(&y) {
        return Some((y, uv));
    }
    let corners: &[DVec2] = if stratum.is_triangle {
        &[DVec2::ZERO, DVec2::X, DVec2::Y]
    } else {
        &[DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y]
    };
    let centre_uv = if stratum.is_triangle {
        DVec2::splat(1.0 / 3.0)
    } else {
        DVec2::splat(0.5)
    };
    std::iter::once((stratum.centre(), centre_uv))
        .chain(
            stratum
                .polygon()
                .iter()
                .copied()
                .zip(corners.iter().copied()),
        )
        .find(|(p, _)| above(p))
}
