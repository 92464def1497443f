//! The landing scale: how a reflected shot into a closed zone that keeps
//! its light is made to land whole on the zone's elements.

use crate::rgb::Rgb;

/// The least and the most a reflected shot's element powers in a closed
/// zone are scaled by to land whole (see [`landing_scale`]): wide enough
/// for the shots of furnished rooms, narrow enough that a shooter whose
/// light falls mostly where no element is keeps the rest as escaped power.
const LANDING_SCALE: (f64, f64) = (0.5, 2.0);

/// The factor, channel by channel, by which the elements of a reflected
/// shot's closed zone (or the whole scene) scale the power they took
/// from the shot's irradiance, `received` in all, so that together they
/// receive exactly the shot's power P (`shot_power`):
///
/// ```text
///   s = P / Σ_e A_e mean_corners(H),
/// ```
///
/// Σ over the elements a shot gives power to. In a closed zone the form
/// factors from any point of the shooter to the zone sum to 1 (the
/// summation relation of form factors: Cohen & Wallace 1993), so all of P
/// lands; the corners' mean over an element misses some of it where light
/// falls off concavely into a junction, and counts some twice where a
/// stratum's kernel peaks beside a vertex. Most shots land within a few
/// percent of P, but the shortfall, compounded over the bounces, leaves
/// furnished rooms dark against a path tracer. Only the elements' powers
/// (what their patches shoot next, and the energy ledger) are scaled: the
/// vertices keep the irradiance they gathered, the point values that
/// images show; scaling those as well would spread each shot's local
/// errors over its whole zone. The factor is held to [`LANDING_SCALE`]: a
/// shooter whose light falls mostly where no element is keeps the rest as
/// escaped power. Only zones whose surfaces' fronts see fronts are scaled
/// (`ZoneLabels::is_lossless`): light that falls on the black back of a
/// one-sided plate is lost for real. Shots of emitting patches are left
/// alone, reflected light included, and so is the light new vertices of an
/// adaptive mesh gather (`Solver::refine` books the difference in the
/// ledger).
///
/// # References
/// M. F. Cohen, J. R. Wallace, *Radiosity and Realistic Image
/// Synthesis*, Academic Press 1993.
pub(crate) fn landing_scale(shot_power: Rgb, received: Rgb) -> Rgb {
    let scale = |shot: f64, got: f64| {
        if got > 0.0 {
            (shot / got).clamp(LANDING_SCALE.0, LANDING_SCALE.1)
        } else {
            1.0
        }
    };
    Rgb::new(
        scale(shot_power.r, received.r),
        scale(shot_power.g, received.g),
        scale(shot_power.b, received.b),
    )
}
