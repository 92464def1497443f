//! The ambient term for the light not yet shot, for scenes open or closed.
//!
//! Progressive shooting leaves unshot power U at any moment. Cohen et al.
//! (1988, §4) spread it evenly over the scene's area A as an ambient
//! irradiance U / A · 1 / (1 − ρ̄), ρ̄ the area-weighted mean reflectance:
//! right for a closed scene, where every shot lands somewhere. In an open
//! scene (a lamp over a floor, the Cornell box's open front) much of what is
//! shot leaves, and the closed-scene term adds light the path tracer never
//! sees, most visibly where the direct light is dim.
//!
//! isorad measures instead of assuming. The ledger counts, per channel, the
//! power shot and the part of it that landed on some element. The landing
//! fraction f of *reflected* light (shots of patches whose emission, if any,
//! has been shot: what the unshot power is made of) stands for what the
//! unshot power will do: a share f of it lands, is reflected by ρ̄, lands
//! again by f, and so on:
//!
//! ```text
//!   A_mb = f · U / A · Σ_k (f ρ̄)^k = f · U / A / (1 − f ρ̄)
//! ```
//!
//! A closed scene has f = 1 and gets Cohen's term; a floor under a lamp, whose
//! reflected light escapes upwards, gets almost none. Before any reflected
//! light has been shot, f is the landing fraction of the emitters' shots.
//!
//! # References
//! M. F. Cohen, S. E. Chen, J. R. Wallace, D. P. Greenberg, "A Progressive
//! Refinement Approach to Fast Radiosity Image Generation", SIGGRAPH 1988, §4.

use crate::scene::Rgb;

/// The power shot and the part of it that landed on the scene's elements,
/// per channel, for emitted light (each emitter patch's first shot) and for
/// reflected light (every other shot).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct LandingLedger {
    /// Power of the emitters' first shots, W.
    emitted_shot: Rgb,
    /// What of it landed, W.
    emitted_landed: Rgb,
    /// Power of all other shots, W.
    reflected_shot: Rgb,
    /// What of it landed, W.
    reflected_landed: Rgb,
}

impl LandingLedger {
    /// Records a shot of power `shot` of which `landed` reached some
    /// element; `emitted` when it was an emitter patch's first shot.
    pub(crate) fn record(&mut self, emitted: bool, shot: Rgb, landed: Rgb) {
        if emitted {
            self.emitted_shot += shot;
            self.emitted_landed += landed;
        } else {
            self.reflected_shot += shot;
            self.reflected_landed += landed;
        }
    }

    /// The share of shot power that lands, per channel, in [0, 1]: that of
    /// reflected light once any has been shot, else that of emitted light,
    /// else 1 (nothing shot yet: assume a closed scene).
    #[must_use]
    pub(crate) fn landing_fraction(&self) -> Rgb {
        let channel = |reflected_shot: f64, reflected_landed: f64, shot: f64, landed: f64| {
            if reflected_shot > 0.0 {
                (reflected_landed / reflected_shot).clamp(0.0, 1.0)
            } else if shot > 0.0 {
                (landed / shot).clamp(0.0, 1.0)
            } else {
                1.0
            }
        };
        let [rs, gs, bs] = self.reflected_shot.to_array();
        let [rl, gl, bl] = self.reflected_landed.to_array();
        let [es_r, es_g, es_b] = self.emitted_shot.to_array();
        let [el_r, el_g, el_b] = self.emitted_landed.to_array();
        Rgb::new(
            channel(rs, rl, es_r, el_r),
            channel(gs, gl, es_g, el_g),
            channel(bs, bl, es_b, el_b),
        )
    }
}

/// The ambient irradiance A_mb = f · U / A / (1 − f ρ̄) (see the module
/// docs) for unshot power `unshot` (W), total area `area`, area-weighted
/// mean reflectance `mean_reflectance` and landing fraction `landing`.
#[must_use]
pub(crate) fn ambient_irradiance(
    unshot: Rgb,
    area: f64,
    mean_reflectance: Rgb,
    landing: Rgb,
) -> Rgb {
    if area <= 0.0 {
        return Rgb::ZERO;
    }
    let interreflection = (Rgb::ONE - landing * mean_reflectance)
        .max(Rgb::splat(1e-6))
        .recip();
    landing * unshot / area * interreflection
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_closed_scene_gets_cohens_term() {
        let unshot = Rgb::splat(2.0);
        let ambient = ambient_irradiance(unshot, 4.0, Rgb::splat(0.5), Rgb::ONE);
        // U / A / (1 − ρ̄) = 2 / 4 / 0.5.
        assert!((ambient.r - 1.0).abs() < 1e-15);
    }

    #[test]
    fn light_that_leaves_adds_nothing() {
        let ambient = ambient_irradiance(Rgb::splat(2.0), 4.0, Rgb::splat(0.5), Rgb::ZERO);
        assert_eq!(ambient, Rgb::ZERO);
    }

    #[test]
    fn the_landing_fraction_is_that_of_reflected_light_once_there_is_some() {
        let mut ledger = LandingLedger::default();
        assert_eq!(ledger.landing_fraction(), Rgb::ONE);
        ledger.record(true, Rgb::splat(10.0), Rgb::splat(9.0));
        assert!((ledger.landing_fraction().g - 0.9).abs() < 1e-15);
        ledger.record(false, Rgb::splat(4.0), Rgb::splat(1.0));
        ledger.record(false, Rgb::splat(4.0), Rgb::splat(0.0));
        assert!((ledger.landing_fraction().b - 0.125).abs() < 1e-15);
    }
}
