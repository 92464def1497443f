//! Merging adjacent coplanar faces into polygons, for triangulated exports.
//!
//! CAD and modelling programs (SketchUp, Blender, Revit) export a flat wall
//! or floor as many small triangles. Meshed one by one, each triangle gets
//! its own grid of elements and its own patches: the mesh explodes and the
//! elements are slivers. [`merge_coplanar_faces`] puts them back together:
//!
//! 1. **Weld** vertex positions: the positions as the file gave them
//!    ([`Surface::occluder_vertices`]), quantised to
//!    [`WELD_RATIO`] × the scene's diagonal (two copies of a point that fall
//!    on either side of a cell border stay apart: the merge is then only
//!    less complete, never wrong).
//! 2. **Adjacency**: two faces are neighbours across an edge when one has the
//!    directed edge a → b and the other b → a, and no other face of the
//!    scene uses that edge (non-manifold edges are never merged across).
//! 3. **Regions**, grown from each unassigned face in file order: a
//!    neighbour joins when it has the same object name and material, faces
//!    the same way (normals within [`MAX_ANGLE`]) and all its vertices lie
//!    within [`PLANE_DISTANCE_RATIO`] × the diagonal of the *first* face's
//!    plane (so a gently curved surface cannot drift into one region).
//! 4. **Boundary**: the region's directed edges whose reverse is not in the
//!    region. It must form exactly one loop through distinct vertices.
//! 5. **Polygon**: that loop, without its collinear vertices, projected on
//!    its best-fit plane; it must be simple and have the area of the faces.
//!
//! A region whose boundary is several loops (a hole, such as a floor around
//! a column, or two parts touching at a corner) or fails a check of step 5
//! keeps its original faces: isorad's [`Surface`] is one simple polygon and
//! has no holes, and cutting a ring into simple pieces would add seams of
//! its own. Leaving such a region as it came is always correct, merely
//! slower to mesh; the count is reported.
//!
//! T-junctions (a vertex of one triangle in the middle of a neighbour's
//! edge) break adjacency too: those faces stay apart.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use glam::{DVec2, DVec3};

use crate::scene::geometry::polygon::{best_fit_plane, project_onto_plane};
use crate::scene::geometry::triangulate::signed_area_2d;
use crate::scene::surface::{PlaneFrame, Surface};
use crate::scene::{Scene, Warning};

/// Vertices closer than this fraction of the scene's diagonal are welded
/// (they fall in the same quantisation cell).
pub const WELD_RATIO: f64 = 1e-7;

/// Largest distance of a face's vertex from a region's plane, as a fraction
/// of the scene's diagonal, for the face to be coplanar with it.
pub const PLANE_DISTANCE_RATIO: f64 = 1e-5;

/// Largest angle between a face's normal and a region's, radians (0.57°).
pub const MAX_ANGLE: f64 = 0.01;

/// Largest relative difference between the merged polygon's area and the
/// sum of its faces' areas.
const AREA_TOLERANCE: f64 = 1e-6;

/// Sine of the largest turning angle at a vertex that counts as collinear.
const COLLINEAR_SINE: f64 = 1e-7;

/// Boundaries longer than this are not checked for self-intersection
/// (quadratic); their regions keep their faces.
const MAX_CHECKED_BOUNDARY: usize = 4096;

/// What [`merge_coplanar_faces`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MergeReport {
    /// Faces that were merged into polygons (regions of two or more).
    pub faces_merged: usize,
    /// Polygons they were merged into.
    pub polygons: usize,
    /// Coplanar regions of several faces kept as they were: holes,
    /// boundaries touching themselves, or a failed check.
    pub regions_kept: usize,
    /// Faces in those regions.
    pub faces_kept: usize,
}

impl MergeReport {
    /// A one-line summary, e.g. "merged 1,204 coplanar faces into 37
    /// polygons", or `None` when nothing was merged or kept.
    #[must_use]
    pub fn summary(&self) -> Option<String> {
        if self.faces_merged == 0 && self.regions_kept == 0 {
            return None;
        }
        let mut parts = Vec::new();
        if self.faces_merged > 0 {
            parts.push(format!(
                "merged {} coplanar faces into {} polygon{}",
                thousands(self.faces_merged),
                thousands(self.polygons),
                if self.polygons == 1 { "" } else { "s" }
            ));
        }
        if self.regions_kept > 0 {
            parts.push(format!(
                "{} coplanar region{} with a hole or a pinched outline kept as {} faces",
                thousands(self.regions_kept),
                if self.regions_kept == 1 { "" } else { "s" },
                thousands(self.faces_kept)
            ));
        }
        Some(parts.join("; "))
    }
}

/// Merges adjacent coplanar faces of one object and material into single
/// polygons (see the module documentation), keeping the order of first
/// appearance. `diagonal` is the scene's length scale.
#[must_use]
pub fn merge_coplanar_faces(surfaces: Vec<Surface>, diagonal: f64) -> (Vec<Surface>, MergeReport) {
    let mut report = MergeReport::default();
    if surfaces.len() < 2 || !(diagonal > 0.0 && diagonal.is_finite()) {
        return (surfaces, report);
    }
    let loops = welded_loops(&surfaces, WELD_RATIO * diagonal);
    let edges = directed_edges(&loops);
    let mut region_of: Vec<Option<usize>> = vec![None; surfaces.len()];
    let mut merged: Vec<Option<Surface>> = Vec::new();
    let mut output_slot: Vec<Option<usize>> = vec![None; surfaces.len()];
    for seed in 0..surfaces.len() {
        if region_of[seed].is_some() {
            continue;
        }
        let region = grow_region(seed, &surfaces, &loops, &edges, diagonal, &mut region_of);
        if region.len() < 2 {
            continue;
        }
        match merge_region(&region, &surfaces, &loops) {
            Some(surface) => {
                report.faces_merged += region.len();
                report.polygons += 1;
                output_slot[seed] = Some(merged.len());
                merged.push(Some(surface));
                for &face in &region[1..] {
                    output_slot[face] = Some(usize::MAX);
                }
            }
            None => {
                report.regions_kept += 1;
                report.faces_kept += region.len();
            }
        }
    }
    // Each merged polygon takes its first face's place; its other faces go.
    let mut result = Vec::with_capacity(surfaces.len() - report.faces_merged + report.polygons);
    for (index, surface) in surfaces.into_iter().enumerate() {
        match output_slot[index] {
            None => result.push(surface),
            Some(usize::MAX) => {}
            Some(slot) => result.extend(merged[slot].take()),
        }
    }
    (result, report)
}

/// Merges a loaded scene's coplanar faces in place; what was merged goes
/// into [`Scene::warnings`] as one line naming `path`.
pub(crate) fn merge_scene_faces(path: &Path, scene: &mut Scene) {
    let diagonal = scene.diagonal();
    let surfaces = std::mem::take(&mut scene.surfaces);
    let (surfaces, report) = merge_coplanar_faces(surfaces, diagonal);
    scene.surfaces = surfaces;
    if let Some(summary) = report.summary() {
        scene.warnings.push(Warning {
            message: format!("{}: {summary}", path.display()),
        });
    }
}

/// Each face's vertices as welded vertex ids, consecutive repeats removed,
/// with one position per id.
struct WeldedLoops {
    ids: Vec<Vec<u32>>,
    positions: Vec<DVec3>,
}

/// Welds the file positions of every face on a grid of cell `cell`.
fn welded_loops(surfaces: &[Surface], cell: f64) -> WeldedLoops {
    let mut index: HashMap<[i64; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let ids = surfaces
        .iter()
        .map(|surface| {
            let mut ids: Vec<u32> = Vec::with_capacity(surface.vertices().len());
            for &p in surface.occluder_vertices() {
                let key = (p / cell).round().as_i64vec3().to_array();
                let id = *index.entry(key).or_insert_with(|| {
                    positions.push(p);
                    (positions.len() - 1) as u32
                });
                if ids.last() != Some(&id) {
                    ids.push(id);
                }
            }
            while ids.len() > 1 && ids.first() == ids.last() {
                ids.pop();
            }
            ids
        })
        .collect();
    WeldedLoops { ids, positions }
}

/// The faces along one directed edge: the first, and how many. Merging
/// asks only whether exactly one face uses an edge, and which; a list per
/// edge would be a memory allocation for each of a building's millions.
#[derive(Clone, Copy, Debug)]
struct EdgeUse {
    first: usize,
    count: u32,
}

/// Every directed edge (a, b) of every face, with the faces using it.
fn directed_edges(loops: &WeldedLoops) -> HashMap<(u32, u32), EdgeUse> {
    let mut edges: HashMap<(u32, u32), EdgeUse> = HashMap::new();
    for (face, ids) in loops.ids.iter().enumerate() {
        for (a, b) in loop_edges(ids) {
            edges
                .entry((a, b))
                .and_modify(|edge| edge.count += 1)
                .or_insert(EdgeUse {
                    first: face,
                    count: 1,
                });
        }
    }
    edges
}

/// The directed edges of a closed loop of ids.
fn loop_edges(ids: &[u32]) -> impl Iterator<Item = (u32, u32)> + '_ {
    (0..ids.len()).map(move |k| (ids[k], ids[(k + 1) % ids.len()]))
}

/// The coplanar region grown from `seed` across manifold edges (the seed
/// first, then in the order found); marks its faces in `region_of`.
fn grow_region(
    seed: usize,
    surfaces: &[Surface],
    loops: &WeldedLoops,
    edges: &HashMap<(u32, u32), EdgeUse>,
    diagonal: f64,
    region_of: &mut [Option<usize>],
) -> Vec<usize> {
    region_of[seed] = Some(seed);
    let mut region = vec![seed];
    if loops.ids[seed].len() < 3 {
        return region;
    }
    let reference = &surfaces[seed];
    let frame = reference.frame();
    let joins = |face: usize| {
        let s = &surfaces[face];
        loops.ids[face].len() >= 3
            && s.name == reference.name
            && s.material == reference.material
            && s.normal().angle_between(frame.normal) <= MAX_ANGLE
            && s.occluder_vertices()
                .iter()
                .all(|&p| frame.height(p).abs() <= PLANE_DISTANCE_RATIO * diagonal)
    };
    let mut next = 0;
    while next < region.len() {
        let face = region[next];
        next += 1;
        for (a, b) in loop_edges(&loops.ids[face]) {
            // Manifold: exactly this face along a → b, exactly one along b → a.
            let (Some(forward), Some(backward)) = (edges.get(&(a, b)), edges.get(&(b, a))) else {
                continue;
            };
            if forward.count != 1 || backward.count != 1 {
                continue;
            }
            let neighbour = backward.first;
            if region_of[neighbour].is_none() && joins(neighbour) {
                region_of[neighbour] = Some(seed);
                region.push(neighbour);
            }
        }
    }
    region
}

/// The region's faces as one simple polygon, or `None` when its boundary is
/// not one simple loop with the faces' area.
fn merge_region(region: &[usize], surfaces: &[Surface], loops: &WeldedLoops) -> Option<Surface> {
    // Boundary edges: directed edges whose reverse is not in the region.
    let inside: HashSet<(u32, u32)> = region
        .iter()
        .flat_map(|&f| loop_edges(&loops.ids[f]))
        .collect();
    let mut next: HashMap<u32, u32> = HashMap::new();
    for &(a, b) in &inside {
        if !inside.contains(&(b, a)) && next.insert(a, b).is_some() {
            return None; // two boundary edges leave one vertex: pinched
        }
    }
    // One loop through every boundary vertex, from the first welded (so
    // that the polygon, and so its mesh, is the same on every run).
    let &start = next.keys().min()?;
    let mut outline = vec![start];
    let mut at = next[&start];
    while at != start {
        if outline.len() > next.len() {
            return None;
        }
        outline.push(at);
        at = *next.get(&at)?;
    }
    if outline.len() != next.len() {
        return None; // several loops: a hole, or parts touching at a corner
    }
    // In the first face's plane: drop collinear vertices, check the shape.
    let frame = surfaces[region[0]].frame();
    let mut points: Vec<DVec3> = outline
        .iter()
        .map(|&id| loops.positions[id as usize])
        .collect();
    remove_collinear(&mut points, frame);
    let plane: Vec<DVec2> = points.iter().map(|&p| frame.to_plane(p)).collect();
    let faces_area: f64 = region.iter().map(|&f| surfaces[f].area()).sum();
    let area = signed_area_2d(&plane);
    if points.len() < 3
        || (area - faces_area).abs() > AREA_TOLERANCE * faces_area
        || !is_simple(&plane)
    {
        return None;
    }
    // Projected on its best-fit plane; the file's positions block light.
    let fit = best_fit_plane(&points)?;
    let projected = project_onto_plane(&points, &fit.frame);
    let first = &surfaces[region[0]];
    Surface::new(first.name.clone(), first.material, projected).map(|s| s.with_occluder(points))
}

/// Removes the vertices where the outline goes straight on (turning by less
/// than [`COLLINEAR_SINE`]), seen in `frame`'s plane.
fn remove_collinear(points: &mut Vec<DVec3>, frame: &PlaneFrame) {
    let straight = |a: DVec3, b: DVec3, c: DVec3| {
        let (u, v) = (
            frame.to_plane(b) - frame.to_plane(a),
            frame.to_plane(c) - frame.to_plane(b),
        );
        u.dot(v) > 0.0 && u.perp_dot(v).abs() <= COLLINEAR_SINE * u.length() * v.length()
    };
    while points.len() > 3 {
        let n = points.len();
        let found =
            (0..n).find(|&k| straight(points[(k + n - 1) % n], points[k], points[(k + 1) % n]));
        match found {
            Some(k) => {
                points.remove(k);
            }
            None => break,
        }
    }
}

/// Whether a closed outline is simple: no two non-adjacent edges meet, and
/// no vertex repeats. Quadratic; outlines over [`MAX_CHECKED_BOUNDARY`]
/// count as not simple.
fn is_simple(points: &[DVec2]) -> bool {
    let n = points.len();
    if n > MAX_CHECKED_BOUNDARY {
        return false;
    }
    let edge = |k: usize| (points[k], points[(k + 1) % n]);
    for i in 0..n {
        for j in i + 1..n {
            let adjacent = j == i + 1 || (i == 0 && j == n - 1);
            let (a, b) = edge(i);
            let (c, d) = edge(j);
            // Adjacent edges share a vertex; the loop's vertices are
            // distinct, so they cannot fold back over each other.
            if !adjacent && segments_meet(a, b, c, d) {
                return false;
            }
        }
    }
    true
}

/// Whether the closed segments [a, b] and [c, d] share a point.
fn segments_meet(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let orient = |p: DVec2, q: DVec2, r: DVec2| (q - p).perp_dot(r - p);
    let (d1, d2) = (orient(c, d, a), orient(c, d, b));
    let (d3, d4) = (orient(a, b, c), orient(a, b, d));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |p: DVec2, q: DVec2, r: DVec2, o: f64| {
        o == 0.0
            && r.x >= p.x.min(q.x)
            && r.x <= p.x.max(q.x)
            && r.y >= p.y.min(q.y)
            && r.y <= p.y.max(q.y)
    };
    on(c, d, a, d1) || on(c, d, b, d2) || on(a, b, c, d3) || on(a, b, d, d4)
}

/// 1204 → "1,204".
pub(crate) fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (k, ch) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k).is_multiple_of(3) {
            out.push(',');
        }
        out.push(ch);
    }
    out
}
