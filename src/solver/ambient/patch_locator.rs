//! Which patch a ray lands on ([`PatchLocator`]): each surface's patches'
//! cells in its plane, indexed on a surface of many patches.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::mesh::Mesh;
use crate::scene::{Scene, SurfaceId, Visibility, distance_to_boundary, polygon_contains};
use crate::solver::ambient::rays::MISS;
use crate::solver::light::element_index::{ElementIndex, padded_box};

/// Where an ambient ray leaves a surface: a point on it, the surface's unit
/// normal, and the surface (which the ray does not hit).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RayStart {
    pub(crate) origin: DVec3,
    pub(crate) normal: DVec3,
    pub(crate) surface: SurfaceId,
}

/// Which patch of a surface holds a point: each patch's cell in its
/// surface's plane coordinates, grouped by surface, and on a surface of
/// more than [`INDEXED_PATCHES`] patches a grid of them
/// ([`ElementIndex`]), so that a ray landing on a floor tries the few
/// patches there rather than all. Flat, 80 bytes a patch and 12 a
/// surface: a list of lists per surface would add an allocation each.
pub(crate) struct PatchLocator {
    /// Surface s's patches are `patches[starts[s]..starts[s + 1]]`.
    starts: Vec<u32>,
    /// Each patch's index and cell, surface by surface, each surface's in
    /// the mesh's order.
    patches: Vec<(u32, PlaneCell)>,
    /// Boxed: 8 bytes a surface without one (most of a building's).
    index: Vec<Option<Box<ElementIndex>>>,
    reach: f64,
}

/// A patch's cell in its surface's plane coordinates.
#[derive(Clone, Copy, Debug)]
struct PlaneCell {
    corners: [DVec2; 4],
    is_triangle: bool,
}

impl PlaneCell {
    fn polygon(&self) -> &[DVec2] {
        if self.is_triangle {
            &self.corners[..3]
        } else {
            &self.corners
        }
    }
}

/// Patches a surface may have before [`PatchLocator`] indexes them.
const INDEXED_PATCHES: usize = 8;

impl PatchLocator {
    /// The locator of every patch of `mesh`. Always all of them, also for
    /// one room's term: the rays it casts are kept for later images,
    /// which must not depend on which room was drawn first.
    pub(crate) fn new(scene: &Scene, mesh: &Mesh) -> PatchLocator {
        // Patches counted, then placed, surface by surface.
        let surfaces = scene.surfaces.len();
        let mut starts = vec![0u32; surfaces + 1];
        for patch in &mesh.patches {
            if let Some(count) = starts.get_mut(patch.surface.index() + 1) {
                *count += 1;
            }
        }
        for s in 0..surfaces {
            starts[s + 1] += starts[s];
        }
        let mut next = starts.clone();
        let mut order = vec![0u32; mesh.patches.len()];
        for (p, patch) in mesh.patches.iter().enumerate() {
            if let Some(slot) = next.get_mut(patch.surface.index()) {
                order[*slot as usize] = p as u32;
                *slot += 1;
            }
        }
        order.truncate(starts[surfaces] as usize);
        let patches: Vec<(u32, PlaneCell)> = order
            .par_iter()
            .map(|&p| {
                let cell = &mesh.patches[p as usize].cell;
                let frame = scene.surface(mesh.patches[p as usize].surface).frame();
                let corners = cell.corners.map(|q| frame.to_plane(q));
                let is_triangle = cell.is_triangle;
                (
                    p,
                    PlaneCell {
                        corners,
                        is_triangle,
                    },
                )
            })
            .collect();
        let index = (0..surfaces)
            .into_par_iter()
            .map(|s| {
                let listed = &order[starts[s] as usize..starts[s + 1] as usize];
                (listed.len() > INDEXED_PATCHES).then(|| {
                    let boxes: Vec<(DVec3, DVec3)> = listed
                        .iter()
                        .map(|&p| padded_box(mesh.patches[p as usize].cell.polygon()))
                        .collect();
                    Box::new(ElementIndex::new(&boxes, scene.surfaces[s].normal()))
                })
            })
            .collect();
        PatchLocator {
            starts,
            patches,
            index,
            reach: 2.0 * scene.diagonal(),
        }
    }

    /// The patch that a ray from `origin` on `surface` (unit `normal`)
    /// along `direction` hits first, or [`MISS`], and where (NaN for a
    /// miss).
    pub(crate) fn hit(
        &self,
        scene: &Scene,
        visibility: &Visibility,
        start: RayStart,
        direction: DVec3,
    ) -> (u32, DVec3) {
        const NONE: (u32, DVec3) = (MISS, DVec3::NAN);
        let RayStart {
            origin,
            normal,
            surface,
        } = start;
        let start = origin + normal * visibility.surface_offset();
        let Some((hit, distance)) = visibility.closest_hit(start, direction, self.reach, surface)
        else {
            return NONE;
        };
        let target = scene.surface(hit);
        // Light arriving from a surface's back: one-sided surfaces send none.
        if target.normal().dot(direction) >= 0.0 {
            return NONE;
        }
        let landed = start + direction * distance;
        let point = target.frame().to_plane(landed);
        self.patch_at(hit, landed, point)
            .map_or(NONE, |p| (p, landed))
    }

    /// The patch of `surface` that holds point `landed` on it (`point` in
    /// its plane coordinates): the first of its patches, in the mesh's
    /// order, whose cell contains the point, or else the nearest.
    fn patch_at(&self, surface: SurfaceId, landed: DVec3, point: DVec2) -> Option<u32> {
        let s = surface.index();
        let (&from, &to) = (self.starts.get(s)?, self.starts.get(s + 1)?);
        let candidates = &self.patches[from as usize..to as usize];
        let inside = |(_, cell): &&(u32, PlaneCell)| polygon_contains(cell.polygon(), point);
        let found = match self.index.get(s).and_then(Option::as_ref) {
            Some(index) => index
                .near(landed)
                .iter()
                .filter_map(|&k| candidates.get(k as usize))
                .find(inside),
            None => candidates.iter().find(inside),
        };
        let distance = |(_, cell): &(u32, PlaneCell)| distance_to_boundary(cell.polygon(), point);
        found
            .or_else(|| {
                candidates
                    .iter()
                    .min_by(|a, b| distance(a).total_cmp(&distance(b)))
            })
            .map(|&(p, _)| p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rgb::Rgb;

    /// On a floor of many patches, the grid finds the patch a scan of
    /// them all finds, first in the mesh's order, at points inside cells,
    /// on their shared edges and corners, and off the floor (the nearest).
    #[test]
    fn the_patch_grid_finds_what_a_scan_finds() {
        let mut scene = Scene::new();
        let white = scene
            .add_material(crate::Material::diffuse("white", Rgb::splat(0.5)))
            .unwrap();
        // A slanted 4 × 3 floor: cells are not aligned with the axes.
        let (o, u, v) = (
            DVec3::new(0.5, 0.2, -1.0),
            DVec3::new(4.0, 0.3, 0.0),
            DVec3::new(0.0, 0.2, 3.0),
        );
        let floor = [o, o + v, o + u + v, o + u];
        scene.add_polygon("floor", white, &floor).unwrap();
        let id = SurfaceId::new(0);
        let settings = crate::mesh::SquareMeshSettings {
            max_edge: 0.25,
            elements_per_side: None,
            patch_max_edge: 0.5,
        };
        let mesh = crate::mesh::mesh_square(&scene, &settings);
        let locator = PatchLocator::new(&scene, &mesh);
        assert!(mesh.patches.len() > 4 * INDEXED_PATCHES);
        assert!(locator.index[id.index()].is_some());
        let frame = scene.surface(id).frame();
        // Every patch's cell from the mesh itself, in its order.
        let cells: Vec<(u32, Vec<DVec2>)> = (mesh.patches.iter().enumerate())
            .filter(|(_, patch)| patch.surface == id)
            .map(|(p, patch)| {
                let cell = patch.cell.polygon().iter().map(|&q| frame.to_plane(q));
                (p as u32, cell.collect())
            })
            .collect();
        let scanned = |point: DVec2| {
            cells
                .iter()
                .find(|(_, cell)| polygon_contains(cell, point))
                .or_else(|| {
                    cells.iter().min_by(|a, b| {
                        distance_to_boundary(&a.1, point)
                            .total_cmp(&distance_to_boundary(&b.1, point))
                    })
                })
                .map(|&(p, _)| p)
        };
        // Points on an 8 × 6 lattice of the patches' corners, their
        // edges' midpoints, their centres, and a step beyond the floor.
        for i in -1..=17 {
            for j in -1..=13 {
                let (s, t) = (f64::from(i) / 16.0, f64::from(j) / 12.0);
                let landed = o + u * s + v * t;
                let point = frame.to_plane(landed);
                assert_eq!(
                    locator.patch_at(id, landed, point),
                    scanned(point),
                    "{s} {t}"
                );
            }
        }
    }
}
