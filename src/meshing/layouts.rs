//! The contour layouts of one receiver: the radial layout of a dominant
//! small emitter's direct light, and the level lines of the total direct
//! field of several lights, with the budget that keeps either no costlier
//! than a finer square grid.

use glam::DVec2;

use crate::lighting::{AreaLight, DirectField};
use crate::mesh::{
    ContourLayout, ContourSettings, SquareMeshSettings, contour_layout, level_line_layout,
};
use crate::scene::{Scene, SurfaceId, Visibility};

/// Receivers smaller than this many square elements keep the square grid
/// under the contour meshers.
pub(super) const MIN_CONTOUR_ELEMENTS: f64 = 16.0;

/// A contour layout with more points than this many times the square
/// grid's (plus 256) is dropped for the grid: near a light's plane,
/// where the light of several lamps fans out along the receiver's edge,
/// level lines can crowd without bound.
pub(super) const MAX_LAYOUT_GRID_RATIO: f64 = 4.0;

/// Points a contour layout may have beyond [`MAX_LAYOUT_GRID_RATIO`] times
/// its grid's: room for the levels on a receiver of a few elements.
pub(super) const LAYOUT_EXTRA_POINTS: f64 = 256.0;

/// Shadow rays per light polygon when looking for penumbrae.
const SHADOW_RAYS: usize = 16;

/// The contour layout of a light's direct light on a receiver: centred
/// on the light's maximum, the first ray along the light's tilt, the line
/// where its plane meets the receiver's kept as an edge, and penumbrae
/// (where 5 %, 50 % and 95 % of the light is hidden) given vertices.
#[must_use]
pub fn receiver_layout(
    scene: &Scene,
    visibility: &Visibility,
    receiver: SurfaceId,
    area_light: &AreaLight,
    settings: &ContourSettings,
) -> Option<ContourLayout> {
    let field = DirectField::new(scene, receiver, area_light)?;
    field_layout(scene, visibility, receiver, field, settings)
}

/// The contour layout of `field` (an area or a photometric luminaire's
/// direct light) on `receiver`, as [`receiver_layout`] builds it.
#[must_use]
pub fn field_layout(
    scene: &Scene,
    visibility: &Visibility,
    receiver: SurfaceId,
    field: DirectField,
    settings: &ContourSettings,
) -> Option<ContourLayout> {
    let centre = field.maximum()?;
    let outline = scene.surface(receiver).plane_vertices();
    let mut settings = settings.clone();
    settings.orientation = tilt_angle(&field, centre);
    let kink: Vec<[DVec2; 2]> = horizon_segment(&field, &outline).into_iter().collect();
    let value = |p: DVec2| field.value_and_gradient(p);
    let mut layout = contour_layout(&outline, &value, centre, &settings, &kink);
    layout.refine_shadows(&|p: DVec2| field.visible_fraction(visibility, p, SHADOW_RAYS));
    Some(layout)
}

/// The level-line layout of the total direct field of `fields` on
/// `receiver` (the sum of their values and gradients), with each field's
/// horizon kept as an edge and points at the square grid's spacing filling
/// regions no level line comes near (the indirect light needs them); None
/// for a receiver smaller than 16 elements, whose grid already follows its
/// light as well as lines would, and where the lines would need more points
/// than four times its square grid.
#[must_use]
pub fn total_field_layout(
    scene: &Scene,
    receiver: SurfaceId,
    fields: &[DirectField],
    settings: &ContourSettings,
    square: &SquareMeshSettings,
) -> Option<ContourLayout> {
    let surface = scene.surface(receiver);
    let spacing = square.max_edge;
    if fields.is_empty() || surface.area() < MIN_CONTOUR_ELEMENTS * spacing * spacing {
        return None;
    }
    let outline = surface.plane_vertices();
    let horizons: Vec<[DVec2; 2]> = fields
        .iter()
        .filter_map(|field| horizon_segment(field, &outline))
        .collect();
    let total = |p: DVec2| {
        fields
            .iter()
            .fold((0.0, DVec2::ZERO), |(value, gradient), field| {
                let (v, g) = field.value_and_gradient(p);
                (value + v, gradient + g)
            })
    };
    let budget = layout_budget(scene, receiver, spacing);
    level_line_layout(&outline, &total, settings, &horizons, spacing, budget)
}

/// The line where the light's plane cuts the receiver's, beyond which
/// its light ends, as a segment reaching past the receiver's `outline` on
/// both sides.
fn horizon_segment(field: &DirectField, outline: &[DVec2]) -> Option<[DVec2; 2]> {
    let (point, direction) = field.kink_line()?;
    let diameter = outline
        .iter()
        .flat_map(|a| outline.iter().map(move |b| a.distance(*b)))
        .fold(0.0, f64::max);
    Some([
        point - direction * 2.0 * diameter,
        point + direction * 2.0 * diameter,
    ])
}

/// The most points a contour layout of `receiver` may have:
/// [`MAX_LAYOUT_GRID_RATIO`] times its square grid's, plus
/// [`LAYOUT_EXTRA_POINTS`].
pub(super) fn layout_budget(scene: &Scene, receiver: SurfaceId, spacing: f64) -> usize {
    let area = scene.surface(receiver).area();
    (MAX_LAYOUT_GRID_RATIO * area / (spacing * spacing) + LAYOUT_EXTRA_POINTS).min(1e9) as usize
}

/// The direction, in the receiver's plane, from the foot of the light's
/// perpendicular to the light's maximum: where a tilted lamp leans.
fn tilt_angle(field: &DirectField, centre: DVec2) -> f64 {
    let foot = field.frame().to_plane(field.centre());
    let lean = centre - foot;
    if lean.length() > 1e-9 * field.length_scale() {
        lean.y.atan2(lean.x)
    } else {
        0.0
    }
}
