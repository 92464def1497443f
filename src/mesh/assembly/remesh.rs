//! Re-triangulating one surface's square grid so that element edges follow
//! its contact lines, the rows of vertices beside them, the shadow
//! boundaries and, when given, a contour layout.

use glam::DVec2;

use super::contacts::{BESIDE_CONTACT_ROWS, Contact};
use crate::mesh::data::patch::Cell;
use crate::mesh::data::topology::Mesh;
use crate::mesh::meshers::constrained::{PlaneTriangulation, triangulate_constrained};
use crate::mesh::meshers::contour::ContourLayout;
use crate::scene::{
    PlaneFrame, Surface, SurfaceId, clip_segment_to_polygon, distance_to_boundary,
    distance_to_segment, polygon_contains,
};

/// The rows of [`BESIDE_CONTACT_ROWS`] beside every contact at least one
/// element long (shorter ones, a table leg's or a book's, cast shadows as
/// small as themselves): each contact moved that far along its `facing`
/// side, clipped to the receiver's outline.
fn rows_beside_contacts(contacts: &[Contact], spacing: f64, outline: &[DVec2]) -> Vec<[DVec2; 2]> {
    let mut rows = Vec::new();
    for contact in contacts {
        let [a, b] = contact.ends;
        let along = b - a;
        if along.length() < spacing || contact.facing == DVec2::ZERO {
            continue;
        }
        let normal = along.perp().normalize();
        let side = if normal.dot(contact.facing) >= 0.0 {
            normal
        } else {
            -normal
        };
        for fraction in BESIDE_CONTACT_ROWS {
            let offset = side * (fraction * spacing);
            if let Some(row) = clip_segment_to_polygon([a + offset, b + offset], outline) {
                rows.push(row);
            }
        }
    }
    rows
}

/// Grid points closer than this fraction of the element spacing to a shadow
/// boundary give way to the points along it (no slivers beside the line).
const BOUNDARY_CLEARANCE: f64 = 0.25;

/// Re-triangulates a surface's regular grid so that element edges follow
/// the contact lines, the shadow `boundaries` and, when given, a contour
/// layout: the layout's points and contour pieces (or, without one, the
/// grid's vertices less those within 0.6 `spacing` of a contact line or
/// 0.25 of a boundary), points along the contact lines and boundaries about
/// `spacing` apart, and the grid's patch cells as constraints so that every
/// triangle lies in one patch. A boundary lying along a contact line (the
/// shadow of an object's foot) is the contact. Uses
/// [`triangulate_constrained`].
#[must_use]
pub fn remesh_surface(
    surface: &Surface,
    grid: &Mesh,
    contacts: &[Contact],
    boundaries: &[[DVec2; 2]],
    spacing: f64,
    layout: Option<&ContourLayout>,
) -> Mesh {
    let frame = surface.frame();
    let outline = surface.plane_vertices();
    let segments: Vec<[DVec2; 2]> = contacts.iter().map(|c| c.ends).collect();
    let beside = rows_beside_contacts(contacts, spacing, &outline);
    let boundaries = boundaries_off_contacts(boundaries, &segments, spacing);
    let lines = GuideLines {
        contacts: &segments,
        beside: &beside,
        boundaries: &boundaries,
    };
    let points = remesh_points(grid, frame, &outline, &lines, spacing, layout);
    // Patch cells as constraints, so that no triangle straddles two patches.
    let cells: Vec<Vec<DVec2>> = grid
        .patches
        .iter()
        .map(|p| {
            p.cell
                .polygon()
                .iter()
                .map(|&q| frame.to_plane(q))
                .collect()
        })
        .collect();
    let mut constraints = segments.clone();
    constraints.extend_from_slice(&beside);
    constraints.extend_from_slice(&boundaries);
    if let Some(layout) = layout {
        constraints.extend_from_slice(&layout.constraints);
    }
    for cell in &cells {
        constraints.extend((0..cell.len()).map(|k| [cell[k], cell[(k + 1) % cell.len()]]));
    }
    let triangulation = triangulate_constrained(&outline, &points, &constraints);
    mesh_in_patches(&triangulation, grid, &cells, frame)
}

/// The lines element edges follow on a surface being remeshed, in its
/// plane coordinates.
struct GuideLines<'a> {
    /// The contact lines.
    contacts: &'a [[DVec2; 2]],
    /// The rows of vertices beside them ([`rows_beside_contacts`]).
    beside: &'a [[DVec2; 2]],
    /// The shadow boundaries not along a contact line.
    boundaries: &'a [[DVec2; 2]],
}

/// The shadow `boundaries` less those lying along a contact line (the
/// shadow of an object's foot is the contact), for elements of `spacing`.
fn boundaries_off_contacts(
    boundaries: &[[DVec2; 2]],
    contacts: &[[DVec2; 2]],
    spacing: f64,
) -> Vec<[DVec2; 2]> {
    let near_contact = |p: DVec2, distance: f64| {
        contacts
            .iter()
            .any(|&[a, b]| distance_to_segment(p, a, b) < distance)
    };
    boundaries
        .iter()
        .filter(|s| {
            let middle = s[0].lerp(s[1], 0.5);
            ![s[0], s[1], middle]
                .iter()
                .all(|&p| near_contact(p, BOUNDARY_CLEARANCE * spacing))
        })
        .copied()
        .collect()
}

/// The points a surface is remeshed through, in its plane coordinates: the
/// layout's points, or the grid's vertices less those crowding one of the
/// `lines` (outline points stay), and points about `spacing` apart along
/// every line.
fn remesh_points(
    grid: &Mesh,
    frame: &PlaneFrame,
    outline: &[DVec2],
    lines: &GuideLines,
    spacing: f64,
    layout: Option<&ContourLayout>,
) -> Vec<DVec2> {
    let scale = outline
        .iter()
        .map(|p| p.length())
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let near_contact = |p: DVec2, distance: f64| {
        lines
            .contacts
            .iter()
            .any(|&[a, b]| distance_to_segment(p, a, b) < distance)
    };
    // Grid points, except those crowding a contact line, a row beside one or
    // a boundary (outline points stay).
    let crowds = |p: DVec2| {
        near_contact(p, 0.6 * spacing)
            || lines
                .beside
                .iter()
                .any(|&[a, b]| distance_to_segment(p, a, b) < 0.3 * spacing)
            || lines
                .boundaries
                .iter()
                .any(|&[a, b]| distance_to_segment(p, a, b) < BOUNDARY_CLEARANCE * spacing)
    };
    let mut points: Vec<DVec2> = match layout {
        Some(layout) => layout.points.clone(),
        None => grid
            .vertices
            .iter()
            .map(|v| frame.to_plane(v.position))
            .filter(|&p| distance_to_boundary(outline, p) <= 1e-12 * scale || !crowds(p))
            .collect(),
    };
    // Points along each contact line, the rows beside it and the boundaries.
    for [a, b] in lines
        .contacts
        .iter()
        .chain(lines.beside)
        .chain(lines.boundaries)
    {
        let n = (a.distance(*b) / spacing).ceil().clamp(1.0, 4096.0) as usize;
        points.extend((1..n).map(|k| a.lerp(*b, k as f64 / n as f64)));
    }
    points
}

/// The mesh of a remeshed surface: the `grid`'s patches (whose `cells` are
/// in plane coordinates), each holding the triangles of `triangulation`
/// inside it.
fn mesh_in_patches(
    triangulation: &PlaneTriangulation,
    grid: &Mesh,
    cells: &[Vec<DVec2>],
    frame: &PlaneFrame,
) -> Mesh {
    let mut mesh = Mesh::default();
    let surface_id = grid
        .patches
        .first()
        .map_or(SurfaceId::new(0), |p| p.surface);
    for patch in &grid.patches {
        mesh.add_patch(surface_id, patch.cell);
    }
    let mut ids = vec![u32::MAX; triangulation.points.len()];
    for triangle in &triangulation.triangles {
        let centroid = triangle
            .iter()
            .map(|&k| triangulation.points[k])
            .sum::<DVec2>()
            / 3.0;
        let patch = (0..cells.len())
            .min_by(|&a, &b| {
                cell_distance(&cells[a], centroid).total_cmp(&cell_distance(&cells[b], centroid))
            })
            .unwrap_or(0);
        // A sliver whose area rounds to zero in world coordinates (a polygon
        // far from the origin against its size) adds nothing: left out.
        let [a, b, c] = triangle.map(|k| frame.to_world(triangulation.points[k]));
        let area = Cell::triangle(a, b, c).area;
        if area.is_nan() || area <= 0.0 {
            continue;
        }
        let corners = triangle.map(|k| {
            if ids[k] == u32::MAX {
                ids[k] = mesh.add_vertex(frame.to_world(triangulation.points[k]), surface_id);
            }
            ids[k]
        });
        mesh.add_element(&corners, patch as u32);
    }
    mesh
}

/// 0 inside a cell, else the distance to it.
fn cell_distance(cell: &[DVec2], p: DVec2) -> f64 {
    if polygon_contains(cell, p) {
        0.0
    } else {
        distance_to_boundary(cell, p)
    }
}
