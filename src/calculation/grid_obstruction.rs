//! Which calculation-grid points are no place to read light, and whether
//! they count: points inside or touching an object, and points closer than
//! a clearance to another surface (a contact shadow), are left out of a
//! grid's statistics by default, as lighting-design programs leave out
//! the points under furniture: a point inside a cabinet reads no light,
//! and one such point makes U₀ = Emin / Eavg zero.
//!
//! The rule, for a point x of the grid's plane (on the surface itself, x is
//! lifted a hair off it first, so that an object standing there encloses
//! it):
//!
//! 1. **Inside an object.** Five probe rays leave x, along the plane's
//!    normal and along ±u and ±v in the plane, each leaning about 1° off
//!    its axis. Surfaces are one-sided and face out of the solids they
//!    bound, so a ray from inside a solid first meets a surface from
//!    behind. x is inside an object when at least four of the five rays
//!    first meet a back: one ray may find a front, the wall a cabinet
//!    without its back face stands against (models leave out the faces
//!    that touch), or a wall face coinciding with the cabinet's back (the
//!    two tie). The ray down to the surface under the plane is not cast:
//!    an object's base lies on that surface. A point under a table top sees
//!    the top's underside from its front; a point in open air whose rays
//!    escape is not inside.
//! 2. **Near a surface.** Short rays of length `clearance` leave x: along
//!    ±u, ±v and the four diagonals between them, each also 45° above the
//!    plane, and along the normal; above the surface, where the plane lies
//!    in free space, also 45° below it and straight down. x is near a
//!    surface when one of them meets any surface, front or back: the foot
//!    of a cabinet, the gap between a cabinet and the wall behind it, a
//!    work plane grazing a desk top.
//!
//! Both tests are rays against the scene's surfaces only; the solution is
//! not read, so a point's status does not depend on the light.
//!
//! # References
//! - EN 12464-1:2021, *Light and lighting: lighting of work places, part 1*:
//!   the grid over the task area and its uniformity U₀ = Emin / Eavg.

use glam::DVec3;

use crate::error::{Error, Result};
use crate::scene::{PlaneFrame, Scene, SurfaceId, Visibility};

/// The default clearance, in scene units (metres): 1 cm.
pub const DEFAULT_CLEARANCE: f64 = 0.01;

/// How a grid treats points that are no place to read light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObstructionRule {
    /// A point closer than this to another surface is near a surface,
    /// in scene units; 0 turns the test off. Default
    /// [`DEFAULT_CLEARANCE`].
    pub clearance: f64,
    /// Read and count the obstructed points too (their status still says
    /// what they are). Default false: they are left out.
    pub keep_obstructed: bool,
}

impl Default for ObstructionRule {
    fn default() -> ObstructionRule {
        ObstructionRule {
            clearance: DEFAULT_CLEARANCE,
            keep_obstructed: false,
        }
    }
}

impl ObstructionRule {
    /// Refuses a clearance that is negative or not finite
    /// ([`Error::InvalidSetting`] naming `clearance`).
    ///
    /// # Errors
    /// As above.
    pub fn validate(&self) -> Result<()> {
        if !(self.clearance.is_finite() && self.clearance >= 0.0) {
            return Err(Error::InvalidSetting {
                name: "clearance".into(),
                message: format!("{} must be ≥ 0", self.clearance),
            });
        }
        Ok(())
    }
}

/// Why a grid point is no place to read light.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Obstruction {
    /// Inside or touching an object (four of five probe rays on backs).
    InsideObject,
    /// Another surface closer than the clearance.
    NearSurface,
}

impl Obstruction {
    /// The name the CSV and the summary use: `inside_object`,
    /// `near_surface`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Obstruction::InsideObject => "inside_object",
            Obstruction::NearSurface => "near_surface",
        }
    }
}

/// A grid's points sorted by the rule: which are obstructed and why, and
/// whether those count.
#[derive(Clone, Debug, PartialEq)]
pub struct GridSelection {
    /// Row-major like the grid's points: the obstruction at each point,
    /// `None` for a clear point or one outside the outline.
    pub obstructions: Vec<Option<Obstruction>>,
    /// The rule the points were sorted by.
    pub rule: ObstructionRule,
}

impl GridSelection {
    /// Whether point `index` is read and counted in the statistics.
    #[must_use]
    pub fn counts(&self, index: usize) -> bool {
        self.rule.keep_obstructed || self.obstructions[index].is_none()
    }

    /// The CSV's status of point `index` (inside the outline), given
    /// whether it was read: `kept`; `left_out_inside_object` or
    /// `left_out_near_surface`; with the obstructed points kept,
    /// `kept_inside_object` or `kept_near_surface`; `unread` for a counted
    /// point the solution could not read.
    #[must_use]
    pub fn status(&self, index: usize, read: bool) -> String {
        match (self.obstructions[index], self.counts(index), read) {
            (_, true, false) => "unread".to_owned(),
            (None, _, _) => "kept".to_owned(),
            (Some(why), true, _) => format!("kept_{}", why.name()),
            (Some(why), false, _) => format!("left_out_{}", why.name()),
        }
    }

    /// How many points have obstruction `why`.
    #[must_use]
    pub fn count(&self, why: Obstruction) -> usize {
        self.obstructions
            .iter()
            .filter(|o| **o == Some(why))
            .count()
    }

    /// The summary's lines: the clearance, then how many points were left
    /// out (or kept) for each reason.
    #[must_use]
    pub fn summary_lines(&self) -> Vec<String> {
        let verb = if self.rule.keep_obstructed {
            "kept"
        } else {
            "left_out"
        };
        let mut lines = vec![format!("clearance = {}", self.rule.clearance)];
        for why in [Obstruction::InsideObject, Obstruction::NearSurface] {
            lines.push(format!("{verb}_{} = {}", why.name(), self.count(why)));
        }
        lines
    }
}

/// What obstructs grid point `x` of the plane `frame` under `rule`
/// (see the module's rule); `on_surface` when the grid lies on the surface
/// itself (height 0), where the point is lifted ten surface offsets first.
pub(super) fn obstruction_at(
    scene: &Scene,
    visibility: &Visibility,
    x: DVec3,
    frame: &PlaneFrame,
    on_surface: bool,
    clearance: f64,
) -> Option<Obstruction> {
    let lift = if on_surface {
        10.0 * visibility.surface_offset()
    } else {
        0.0
    };
    let x = x + frame.normal * lift;
    if inside_an_object(scene, visibility, x, frame) {
        return Some(Obstruction::InsideObject);
    }
    if clearance > 0.0 && near_a_surface(visibility, x, frame, on_surface, clearance) {
        return Some(Obstruction::NearSurface);
    }
    None
}

/// The leaning of each probe ray off its axis, about 1°: a grid point over
/// a quad's diagonal (where a symmetric grid often falls) then does not
/// send a ray along the crack between the quad's two triangles.
const LEAN: [f64; 2] = [0.0131, 0.0173];

/// Whether at least four of the five probe rays from `x` first meet a
/// surface from behind (rule 1).
fn inside_an_object(scene: &Scene, visibility: &Visibility, x: DVec3, frame: &PlaneFrame) -> bool {
    let reach = 2.0 * scene.diagonal();
    let (n, u, v) = (frame.normal, frame.u, frame.v);
    let backs = [
        n + u * LEAN[0] + v * LEAN[1],
        u + v * 0.0137 + n * 0.0119,
        -u - v * 0.0151 + n * 0.0113,
        v - u * 0.0127 + n * 0.0109,
        -v + u * 0.0157 + n * 0.0103,
    ]
    .into_iter()
    .map(DVec3::normalize)
    .filter(|&direction| {
        visibility
            .closest_hit(x, direction, reach, SurfaceId::NONE)
            .is_some_and(|(surface, _)| scene.surface(surface).normal().dot(direction) > 0.0)
    })
    .count();
    backs >= 4
}

/// Whether a surface lies within `clearance` of `x` along one of the
/// short rays of rule 2; on the surface itself the in-plane rays lean up,
/// away from it, and no ray goes below the plane.
fn near_a_surface(
    visibility: &Visibility,
    x: DVec3,
    frame: &PlaneFrame,
    on_surface: bool,
    clearance: f64,
) -> bool {
    let (n, u, v) = (frame.normal, frame.u, frame.v);
    let in_plane = [u, -u, v, -v, u + v, u - v, -u + v, -u - v].map(DVec3::normalize);
    // In the plane (leaning up by about 1°), then 45° above it.
    let mut directions: Vec<DVec3> = in_plane.iter().map(|&d| d + n * LEAN[0]).collect();
    directions.extend(in_plane.iter().map(|&d| d + n));
    directions.push(n + u * LEAN[0] + v * LEAN[1]);
    if !on_surface {
        // 45° below it, and straight down.
        directions.extend(in_plane.iter().map(|&d| d - n));
        directions.push(-n + u * LEAN[1] - v * LEAN[0]);
    }
    directions
        .into_iter()
        .map(DVec3::normalize)
        .any(|direction| {
            visibility
                .closest_hit(x, direction, clearance, SurfaceId::NONE)
                .is_some()
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bad_clearance_is_refused() {
        for clearance in [-0.01, f64::NAN, f64::INFINITY] {
            let rule = ObstructionRule {
                clearance,
                ..ObstructionRule::default()
            };
            assert!(rule.validate().is_err(), "{clearance}");
        }
        assert!(ObstructionRule::default().validate().is_ok());
    }

    #[test]
    fn statuses_say_why_and_whether_counted() {
        let mut selection = GridSelection {
            obstructions: vec![
                None,
                Some(Obstruction::InsideObject),
                Some(Obstruction::NearSurface),
            ],
            rule: ObstructionRule::default(),
        };
        let statuses: Vec<String> = (0..3).map(|k| selection.status(k, k == 0)).collect();
        assert_eq!(
            statuses,
            ["kept", "left_out_inside_object", "left_out_near_surface"]
        );
        assert_eq!(selection.status(0, false), "unread");
        assert_eq!(
            selection.summary_lines(),
            [
                "clearance = 0.01",
                "left_out_inside_object = 1",
                "left_out_near_surface = 1"
            ]
        );
        selection.rule.keep_obstructed = true;
        assert!(selection.counts(1));
        assert_eq!(selection.status(1, true), "kept_inside_object");
        assert_eq!(selection.summary_lines()[1], "kept_inside_object = 1");
    }
}
