//! Contact lines: where another surface meets a receiver's plane in front of
//! it, as a block standing on a floor or a partition against a wall, or
//! lies just in front of it, as a lamp panel under a ceiling.
//!
//! Light is discontinuous across such a line (bright on one side, nothing
//! under the block), which no interpolation across it can represent. The
//! meshers put element edges along contact lines instead.

use std::ops::RangeInclusive;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::mesh::data::topology::Mesh;
use crate::scene::{
    PlaneFrame, Scene, Surface, SurfaceBoxes, SurfaceId, clip_segment_to_polygon,
    distance_to_boundary, distance_to_segment, polygon_contains, segment_parameter,
};

/// How close to a plane, as a fraction of the scene's diagonal, another
/// surface's edge must lie to stand on it.
pub(crate) const CONTACT_TOLERANCE: f64 = 1e-3;

/// A contact segment in a receiver's plane coordinates, with the side the
/// touching surface faces (its normal projected into the receiver's plane):
/// the side a viewer can see, for a closed object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// End points, in the receiver's plane coordinates.
    pub ends: [DVec2; 2],
    /// The touching surface.
    pub surface: SurfaceId,
    /// The side the touching surface faces: its normal projected into the
    /// receiver's plane, unit length; for a parallel surface covering the
    /// receiver, away from its footprint.
    pub facing: DVec2,
    /// How far to its `facing` side the receiver's vertices on the line
    /// gather: 0 for a surface standing on the receiver (the dark corner
    /// beside a block's foot is real and as wide as the block is high),
    /// twice the gap for one covering it (see [`covering_outline`]), the
    /// gap for one a little farther off (see [`NEAR_OUTLINE_GAP`]).
    pub clearance: f64,
}

/// The rows of vertices a mesh puts beside a contact line, on the side the
/// touching surface faces, as fractions of the element spacing. Light
/// changes fastest right beside an object (its shadow and the corner's
/// darkening are a few centimetres wide where the grid is decimetres), and
/// the graded rows keep the linear interpolation from spreading that drop
/// over a whole element: on an office's desks, where a screen stands, and
/// its walls, under window frames, that lost 10–15 % of their light.
pub(crate) const BESIDE_CONTACT_ROWS: [f64; 2] = [0.125, 0.5];

/// The contact lines on a receiver's front, and whether a parallel surface
/// covers part of it ([`contact_segments`]).
#[derive(Clone, Debug, Default)]
pub struct ReceiverContacts {
    /// The contact segments, in the receiver's plane coordinates.
    pub lines: Vec<Contact>,
    /// Whether a parallel surface lies over some of the receiver within its
    /// covering gap ([`covering_gap`]), even where its outline gives no
    /// line: a book's side wholly behind a taller, deeper neighbour's. The
    /// part under it is hidden, and meshing drops it.
    pub covered: bool,
    /// Points of the receiver's outline where a surface standing in front
    /// of it just beside its outline ends ([`outline_mark`]): the top of a
    /// neighbouring book that stands further forward, beside a spine.
    pub marks: Vec<DVec2>,
}

/// The contact segments on `receiver`'s front, found at `distances` (a
/// tolerance and an inset): for every other surface not
/// parallel to it, the part of its polygon lying within `tolerance` of the
/// receiver's plane (or crossing it), when the rest of that surface stands
/// in front of the receiver; clipped to the receiver's polygon. Segments
/// shorter than `tolerance` are dropped, and so are those running along the
/// polygon's boundary within `inset` (a wall meeting a floor at its edge):
/// a boundary vertex gathers `inset` inside its surface, beyond such a line.
/// A contact farther in, such as a screen's foot a centimetre from a desk's
/// edge, is kept however close: without it the desk's edge vertices would
/// gather under the screen, in the dark, and darken a whole row of elements.
/// A parallel surface just in front of the receiver adds its outline
/// ([`covering_outline`]): one lying on it, facing the same way (a ceiling
/// panel hung a centimetre below a ceiling), or one facing it across a
/// narrow slot (the sides of two books a millimetre apart on a shelf).
/// One a little farther off, up to [`near_outline_gap`] for elements of
/// `spacing`, adds its outline too, but hides nothing.
///
/// Only the surfaces whose bounding boxes come within `tolerance`, or
/// within the widest gap at which a parallel surface covers the receiver
/// or draws its outline on it, of the receiver's are looked at, found
/// through `boxes` (built once for the scene).
#[must_use]
pub fn contact_segments(
    scene: &Scene,
    boxes: &SurfaceBoxes,
    receiver: SurfaceId,
    distances: ContactDistances,
    spacing: f64,
) -> ReceiverContacts {
    let target = scene.surface(receiver);
    let frame = target.frame();
    let outline = target.plane_vertices();
    let plane = ReceiverPlane {
        surface: target,
        frame,
        outline: &outline,
    };
    let (min, max) = boxes.bounds(receiver);
    let mut contacts = ReceiverContacts::default();
    // Outlines of parallel surfaces too far in front to cover the receiver.
    let mut near = Vec::new();
    let largest_gap =
        (COVERING_GAP * target.area().sqrt()).max(near_outline_gap(target, target, spacing));
    for id in boxes.near(min, max, distances.tolerance.max(largest_gap)) {
        let other = scene.surface(id);
        if id == receiver {
            continue;
        }
        let alignment = other.normal().dot(target.normal());
        if alignment.abs() > 0.999 {
            match parallel_outline(&plane, other, id, alignment, distances, spacing) {
                Some(ParallelOutline::Covering(lines)) => {
                    contacts.lines.extend(lines);
                    contacts.covered = true;
                }
                Some(ParallelOutline::Near(lines)) => near.extend(lines),
                None => {}
            }
            continue;
        }
        match standing_contact(&plane, other, id, distances) {
            Some(Standing::Line(line)) => contacts.lines.push(line),
            Some(Standing::Mark(mark)) => contacts.marks.push(mark),
            None => {}
        }
    }
    let kept = near_outlines_kept(&contacts.lines, &near, distances.tolerance);
    contacts.lines.extend(kept);
    contacts
}

/// The distances at which contacts are found on one receiver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactDistances {
    /// How close to the receiver's plane another surface's edge must lie to
    /// stand on it ([`CONTACT_TOLERANCE`] of the room's diagonal); lines
    /// shorter than this are dropped.
    pub tolerance: f64,
    /// How far the receiver's boundary vertices gather inside it: lines
    /// along its outline within this distance are dropped.
    pub inset: f64,
}

/// A receiver in its own plane: its surface, plane frame and outline in
/// the frame's coordinates.
struct ReceiverPlane<'a> {
    surface: &'a Surface,
    frame: &'a PlaneFrame,
    outline: &'a [DVec2],
}

/// What a surface parallel to a receiver draws on it.
enum ParallelOutline {
    /// The contact lines of a surface covering it ([`covering_outline`]).
    Covering(Vec<Contact>),
    /// The outline of one a little farther in front, which hides nothing.
    Near(Vec<Contact>),
}

/// The outline that `other` (surface `id`), parallel to the receiver with
/// normals' dot product `alignment`, draws on it, if any: covering it, or
/// a little farther off ([`near_outline_gap`] for elements of `spacing`).
fn parallel_outline(
    receiver: &ReceiverPlane,
    other: &Surface,
    id: SurfaceId,
    alignment: f64,
    distances: ContactDistances,
    spacing: f64,
) -> Option<ParallelOutline> {
    let target = receiver.surface;
    let tolerance = distances.tolerance;
    // One lying on the receiver must be clear of its plane (nearer, it is a
    // decal); one facing it, across a slot however narrow, but not back to
    // back with it (the two sides of a partition).
    let (above, gap) = if alignment > 0.0 {
        (tolerance, covering_gap(target, other))
    } else {
        (
            FACING_CLEARANCE * tolerance,
            slot_gap(target, other, tolerance),
        )
    };
    let outline_within =
        |heights: RangeInclusive<f64>| covering_outline(receiver, other, id, heights, distances);
    if let Some(lines) = outline_within(above..=gap) {
        return Some(ParallelOutline::Covering(lines));
    }
    let lines = outline_within(gap..=near_outline_gap(target, other, spacing))?;
    // Its vertices gather one gap, not two, beyond the line: the dark band
    // behind it is as wide as the gap.
    Some(ParallelOutline::Near(
        lines
            .into_iter()
            .map(|line| Contact {
                clearance: 0.5 * line.clearance,
                ..line
            })
            .collect(),
    ))
}

/// What a surface standing on a receiver's plane gives it.
enum Standing {
    /// A contact line inside its outline.
    Line(Contact),
    /// A point of its outline where the surface ends beside it
    /// ([`outline_mark`]).
    Mark(DVec2),
}

/// The contact line that `other` (surface `id`), not parallel to the
/// receiver, makes on it where it touches or crosses its plane and stands
/// in front of it, or the mark it makes beside its outline.
fn standing_contact(
    receiver: &ReceiverPlane,
    other: &Surface,
    id: SurfaceId,
    distances: ContactDistances,
) -> Option<Standing> {
    let ContactDistances { tolerance, inset } = distances;
    let (frame, outline) = (receiver.frame, receiver.outline);
    let heights: Vec<f64> = other.vertices().iter().map(|&p| frame.height(p)).collect();
    // It must touch the plane, and stand in front of the receiver.
    let touches = heights.iter().any(|h| h.abs() <= tolerance);
    let crosses = heights.iter().any(|&h| h < -tolerance) && heights.iter().any(|&h| h > tolerance);
    if !(touches || crosses) || heights.iter().all(|&h| h <= tolerance) {
        return None;
    }
    let ends = plane_section(other, &heights, tolerance, frame)?;
    let Some(clipped) = clip_segment_to_polygon(ends, outline) else {
        return outline_mark(ends, outline, tolerance).map(Standing::Mark);
    };
    // A wall standing on the floor's edge makes no line inside it.
    let along_outline = [clipped[0], clipped[1], clipped[0].lerp(clipped[1], 0.5)]
        .iter()
        .all(|&p| distance_to_boundary(outline, p) <= inset);
    if clipped[0].distance(clipped[1]) > tolerance && !along_outline {
        let origin = frame.to_plane(DVec3::ZERO);
        let facing = (frame.to_plane(other.normal()) - origin).normalize_or_zero();
        return Some(Standing::Line(Contact {
            ends: clipped,
            surface: id,
            facing,
            clearance: 0.0,
        }));
    }
    None
}

/// The near outlines worth adding to the contact `lines`. A near outline's
/// edge adds nothing along another line within `tolerance`: along the
/// whole of a contact (the board a book stands on), or beside another near
/// outline's edge that faces the other way (the next book's side, a
/// millimetre off: dark on both sides; its middle is enough, so that only
/// the taller of two neighbours' sides is looked at again). Of two facing
/// the same way along each other's whole length (the back and front of a
/// panel hung in front of a wall), the one nearer the receiver is kept.
fn near_outlines_kept(lines: &[Contact], near: &[Contact], tolerance: f64) -> Vec<Contact> {
    let near_line = |p: DVec2, other: &Contact| {
        distance_to_segment(p, other.ends[0], other.ends[1]) <= tolerance
    };
    let whole_along = |line: &Contact, other: &Contact| {
        let middle = line.ends[0].lerp(line.ends[1], 0.5);
        other.surface != line.surface
            && [line.ends[0], line.ends[1], middle]
                .iter()
                .all(|&p| near_line(p, other))
    };
    near.iter()
        .filter(|line| {
            let middle = line.ends[0].lerp(line.ends[1], 0.5);
            let along_contact = lines.iter().any(|other| whole_along(line, other));
            let along_near = near.iter().any(|other| {
                if other.facing.dot(line.facing) < 0.0 {
                    other.surface != line.surface && near_line(middle, other)
                } else {
                    whole_along(line, other)
                        && (other.clearance, other.surface.index())
                            < (line.clearance, line.surface.index())
                }
            });
            !(along_contact || along_near)
        })
        .copied()
        .collect()
}

/// Where a surface standing in front of a receiver, whose section with the
/// receiver's plane (`ends`) lies just outside its `outline`, ends beside
/// the outline: the section's end within `tolerance` of the outline,
/// moved onto it, when the section leads away from the outline rather
/// than along it. A book standing 3 cm further forward than its neighbour,
/// a millimetre beside the neighbour's spine, shades the spine's edge up
/// to its own top and not above it: the spine's light changes from 0.45 to
/// 0.84 of its peak across its top's height, within millimetres, where the
/// spine's element is 15 cm tall (`bench/generate_building.py`'s cluttered
/// office, by `bench/mitsuba_probe.py`). The top face's section marks that
/// height on the spine's edge; its side's runs along the edge and marks
/// nothing. `None` for a section that marks no point, or only a corner of
/// the outline.
fn outline_mark(ends: [DVec2; 2], outline: &[DVec2], tolerance: f64) -> Option<DVec2> {
    let [near, far] =
        if distance_to_boundary(outline, ends[0]) <= distance_to_boundary(outline, ends[1]) {
            ends
        } else {
            [ends[1], ends[0]]
        };
    let leading = (far - near).normalize_or_zero();
    let (a, b) = (0..outline.len())
        .map(|k| (outline[k], outline[(k + 1) % outline.len()]))
        .min_by(|x, y| {
            distance_to_segment(near, x.0, x.1).total_cmp(&distance_to_segment(near, y.0, y.1))
        })?;
    let along = (b - a).normalize_or_zero();
    if distance_to_segment(near, a, b) > tolerance || leading.dot(along).abs() > 0.5 {
        return None;
    }
    // At a corner of the outline a mark makes no row.
    let t = segment_parameter(near, a, b);
    (t > 0.0 && t < 1.0).then(|| a.lerp(b, t))
}

/// How far in front of a receiver, as a fraction of the smaller one's size
/// (√area), a parallel surface beyond [`covering_gap`] or [`slot_gap`]
/// still draws its outline on the receiver, as element edges, without
/// hiding what lies under it: a book standing 2 cm in front of a wall.
/// Light reaches into the gap only about as far as the gap is wide, so the
/// wall behind the book is dark and the wall just above it lit, a step the
/// wall's elements, decimetres across, spread over a whole element (its
/// vertices above the books of `bench/generate_building.py`'s cluttered
/// office read 0.84 of a path tracer's irradiance where a gather at the
/// same points reads 0.99). A cable tray 40 cm under a ceiling casts a
/// soft shadow there, not a step, and stays clear of the bound.
///
/// The outline's vertices gather on the lit side, so an element behind
/// the book whose corners all lie on the outline reads that light too: no
/// viewer sees it, and in a closed zone each reflected shot's elements are
/// scaled to take exactly its power (the solver's landing scale), so the
/// light it takes is not made up.
const NEAR_OUTLINE_GAP: f64 = 0.2;

/// The largest gap at which `other`, parallel to `receiver` and in front
/// of it, draws its outline on it, for elements of `spacing`:
/// [`NEAR_OUTLINE_GAP`] of the smaller one's √area, and no more than the
/// first row beside a contact ([`BESIDE_CONTACT_ROWS`]), within which the
/// outline's vertices gather one gap beyond the line
/// ([`gather_beside_covering_outlines`]). A partition a metre in front of
/// a long wall casts a soft shadow on it, not a step.
fn near_outline_gap(receiver: &Surface, other: &Surface, spacing: f64) -> f64 {
    (NEAR_OUTLINE_GAP * receiver.area().min(other.area()).sqrt())
        .min(BESIDE_CONTACT_ROWS[0] * spacing)
}

/// How far in front of a receiver, as a fraction of the smaller one's size
/// (√area), a parallel surface covers it: a ceiling panel hung a centimetre
/// below a ceiling or a picture on a wall (facing the same way), the sides
/// of two books a millimetre apart (facing each other across a slot, no
/// wider than [`slot_gap`]).
const COVERING_GAP: f64 = 0.05;

/// How far in front of a receiver, as a fraction of the contact tolerance,
/// a parallel surface facing it must lie to cover it: a slot between two
/// books may be far narrower than the tolerance (a millimetre against a
/// thousandth of a room's diagonal), while the two sides of a partition
/// modelled without thickness lie back to back, at no height at all.
const FACING_CLEARANCE: f64 = 1e-3;

/// The largest gap at which `other`, parallel to `receiver` and in front of
/// it, covers it: [`COVERING_GAP`] of the smaller one's √area. Light
/// reaches into such a gap only about as far as the gap is wide, so the
/// part of the receiver under the other is dark; a table top over a floor
/// or two facing walls are far wider apart than that.
#[must_use]
pub fn covering_gap(receiver: &Surface, other: &Surface) -> f64 {
    COVERING_GAP * receiver.area().min(other.area()).sqrt()
}

/// The widest slot across which `other`, facing `receiver`, covers it:
/// the contact tolerance, or [`covering_gap`] if smaller. Two faces that
/// close touch, and the part of each behind the other is as hidden as the
/// floor under a block. A wider slot (two bookcases' sides 2 cm apart) is
/// left meshed: a viewer looking along it would see through the dropped
/// faces into the objects behind them.
#[must_use]
pub fn slot_gap(receiver: &Surface, other: &Surface, tolerance: f64) -> f64 {
    covering_gap(receiver, other).min(tolerance)
}

/// The contact lines of a parallel surface covering the receiver, or `None`
/// when it does not: its whole polygon in front of the receiver's plane by a
/// height `within`, its footprint on the receiver's polygon. Lines shorter
/// than the `distances`' tolerance, or along the receiver's outline within
/// their inset, are left out. It lies on the receiver, facing the same way, or
/// faces it across a slot. The receiver under it is hidden and unlit, like
/// the floor under a block, so its outline, projected onto the receiver's
/// plane and clipped to the receiver's outline, bounds the elements (none when the
/// footprint covers the receiver's whole polygon): without it, the vertices
/// in the gap behind a ceiling panel spread their darkness a whole element
/// round the panel, and those in the slots between books gathered the room's
/// light at the slots' mouths (2.8 times what a path tracer finds on the
/// books' sides of `bench/generate_building.py`'s cluttered office, over 27
/// m² of faces). Each side faces away from the footprint, where a viewer sees
/// the receiver. Right beside the footprint the receiver darkens over a band
/// as wide as the gap (half its light at the line, all of it a gap away), too
/// narrow to see where it is far narrower than an element: the vertices on
/// the line then gather two gaps out, so that the elements beside it are not
/// dimmed across their width ([`gather_beside_covering_outlines`]).
fn covering_outline(
    receiver: &ReceiverPlane,
    other: &Surface,
    id: SurfaceId,
    within: RangeInclusive<f64>,
    distances: ContactDistances,
) -> Option<Vec<Contact>> {
    let ContactDistances { tolerance, inset } = distances;
    let (frame, outline) = (receiver.frame, receiver.outline);
    let vertices = other.vertices();
    let heights: Vec<f64> = vertices.iter().map(|&p| frame.height(p)).collect();
    if !heights.iter().all(|h| within.contains(h)) {
        return None;
    }
    let height = heights.iter().copied().fold(0.0, f64::max);
    let footprint: Vec<DVec2> = vertices.iter().map(|&p| frame.to_plane(p)).collect();
    let centre = footprint.iter().sum::<DVec2>() / footprint.len() as f64;
    let mut contacts = Vec::new();
    // The footprint meets the receiver's polygon if an edge crosses it, or
    // if one holds the other.
    let mut crossed = false;
    for k in 0..footprint.len() {
        let (a, b) = (footprint[k], footprint[(k + 1) % footprint.len()]);
        let Some(clipped) = clip_segment_to_polygon([a, b], outline) else {
            continue;
        };
        crossed = true;
        let along_outline = [clipped[0], clipped[1], clipped[0].lerp(clipped[1], 0.5)]
            .iter()
            .all(|&p| distance_to_boundary(outline, p) <= inset);
        if clipped[0].distance(clipped[1]) <= tolerance || along_outline {
            continue;
        }
        let mut facing = (b - a).perp().normalize_or_zero();
        if facing.dot(a - centre) < 0.0 {
            facing = -facing;
        }
        contacts.push(Contact {
            ends: clipped,
            surface: id,
            facing,
            clearance: 2.0 * height,
        });
    }
    let overlaps = crossed
        || footprint.iter().any(|&p| polygon_contains(outline, p))
        || outline.iter().any(|&p| polygon_contains(&footprint, p));
    overlaps.then_some(contacts)
}

/// Moves the receivers of the vertices on the outlines of parallel
/// surfaces covering a receiver or lying a little in front of it
/// ([`covering_outline`], [`NEAR_OUTLINE_GAP`]; `covering`: per receiver,
/// those contacts) by each line's
/// `clearance` to its facing side (both sides' at a footprint's corner),
/// where that stays short of the first row of vertices beside the line
/// ([`BESIDE_CONTACT_ROWS`] of the element `spacing`). A wider dark band,
/// behind a window set 4 cm in front of a wall, is one the rows draw and
/// a viewer sees.
pub fn gather_beside_covering_outlines(
    mesh: &mut Mesh,
    scene: &Scene,
    covering: &[(SurfaceId, Vec<Contact>)],
    spacing: f64,
) {
    let first_row = BESIDE_CONTACT_ROWS[0] * spacing;
    let on_line = 1e-6 * scene.diagonal();
    let mut of_surface: Vec<Option<&[Contact]>> = vec![None; scene.surfaces.len()];
    for (id, contacts) in covering {
        of_surface[id.index()] = Some(contacts);
    }
    // Each vertex alone, in parallel: a building's floors carry hundreds
    // of contact lines each.
    mesh.vertices.par_iter_mut().for_each(|vertex| {
        let Some(contacts) = of_surface[vertex.surface.index()] else {
            return;
        };
        let frame = scene.surface(vertex.surface).frame();
        let p = frame.to_plane(vertex.position);
        let offset: DVec2 = contacts
            .iter()
            .filter(|c| c.clearance <= first_row)
            .filter(|c| distance_to_segment(p, c.ends[0], c.ends[1]) <= on_line)
            .map(|c| c.facing * c.clearance)
            .sum();
        let moved = vertex.receiver_position() + frame.u * offset.x + frame.v * offset.y;
        vertex.set_receiver_position(moved);
    });
}

/// Where a polygon meets a plane: the extreme points, along the line of
/// intersection, of its vertices on the plane and of its edges' crossings.
fn plane_section(
    surface: &Surface,
    heights: &[f64],
    tolerance: f64,
    frame: &PlaneFrame,
) -> Option<[DVec2; 2]> {
    let vertices = surface.vertices();
    let n = vertices.len();
    let mut points: Vec<DVec3> = Vec::new();
    for k in 0..n {
        let (a, b) = (vertices[k], vertices[(k + 1) % n]);
        let (ha, hb) = (heights[k], heights[(k + 1) % n]);
        if ha.abs() <= tolerance {
            points.push(a);
        }
        if (ha < -tolerance && hb > tolerance) || (ha > tolerance && hb < -tolerance) {
            points.push(a + (b - a) * (ha / (ha - hb)));
        }
    }
    let plane_points: Vec<DVec2> = points.iter().map(|&p| frame.to_plane(p)).collect();
    let direction = frame.normal.cross(surface.normal());
    let along = DVec2::new(direction.dot(frame.u), direction.dot(frame.v)).normalize_or_zero();
    let key = |p: &DVec2| p.dot(along);
    let first = plane_points
        .iter()
        .min_by(|a, b| key(a).total_cmp(&key(b)))?;
    let last = plane_points
        .iter()
        .max_by(|a, b| key(a).total_cmp(&key(b)))?;
    Some([*first, *last])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A section beside a 6 × 28 unit square's right edge (x = 6) marks
    /// where it ends when it leads away from the edge, not when it runs
    /// along it or ends too far from it.
    #[test]
    fn a_section_beside_the_outline_marks_where_it_ends() {
        let outline = [
            DVec2::new(0.0, 0.0),
            DVec2::new(6.0, 0.0),
            DVec2::new(6.0, 28.0),
            DVec2::new(0.0, 28.0),
        ];
        let tolerance = 0.5;
        // A neighbour's top, 0.1 to the right, leading away at height 12.
        let top = [DVec2::new(12.0, 12.0), DVec2::new(6.1, 12.0)];
        assert_eq!(
            outline_mark(top, &outline, tolerance),
            Some(DVec2::new(6.0, 12.0))
        );
        // Its side, along the edge.
        let side = [DVec2::new(6.1, 0.0), DVec2::new(6.1, 12.0)];
        assert_eq!(outline_mark(side, &outline, tolerance), None);
        // A top beyond the tolerance.
        let far = [DVec2::new(7.0, 12.0), DVec2::new(12.0, 12.0)];
        assert_eq!(outline_mark(far, &outline, tolerance), None);
    }
}
