//! Shaft culling of a shot: the receiving patches that see all of the
//! shooter, whose vertices need no shadow rays.
//!
//! Before a shot, the solver asks, for each patch of the receiving zone,
//! whether any triangle reaches into the shaft between the shooter's cell
//! and the box of the patch's receiving points (Haines & Wallace 1991;
//! `Visibility::is_shaft_clear`). Where none does, every shadow ray from
//! those points to the shooter is unblocked, and the shot is gathered at
//! them with the same samples and factors but no rays. A vertex on the
//! border of two patches is clear when either patch is, since its
//! receiving point lies in both boxes.
//!
//! A shaft costs about what fifteen rays cost, so only patches whose
//! vertices would cast at least [`MIN_RAYS`] rays are tested, and the
//! elements of a blocked patch (one by one) only when each would cast
//! [`ELEMENT_RAYS`]: an emitter's shot, whose vertices cast 64 each.
//!
//! The irradiance is the rays' own but for one thing: a reflected shot's
//! shafts leave out a rim of the shooter as wide as its surface's
//! receivers' inset (a ten-thousandth of its room's diagonal,
//! `mesh/assembly.rs`), so that a wall meeting a ceiling patch at its edge
//! does not touch every shaft of it. A ray aimed into that rim and grazing
//! something there is then taken as unblocked (in the Cornell box, one
//! vertex of one shot, where the slightly bent ceiling meets a wall).
//! Emitters' shafts keep the whole cell: their shadow boundaries are
//! meshed, and a vertex on one sees an occluder's edge line up with the
//! emitter's.
//!
//! # References
//! E. A. Haines, J. R. Wallace, "Shaft Culling for Efficient Ray-Traced
//! Radiosity", Eurographics Workshop on Rendering, 1991.

use glam::DVec3;
use rayon::prelude::*;

use super::shooter::Shooter;
use crate::mesh::Mesh;
use crate::scene::{Scene, SurfaceId, Visibility};

/// A patch is tested only when its vertices would cast at least this many
/// shadow rays to the shooter in all (vertices times samples per vertex).
const MIN_RAYS: usize = 64;

/// A blocked patch's elements are tested one by one only when each would
/// cast at least this many rays: an element stands for about one vertex
/// (its four corners are each shared with three more), so this is the
/// samples per vertex.
const ELEMENT_RAYS: usize = 64;

/// Which vertices of the mesh see all of one shot's shooter: a flag per
/// vertex, of which only those set are unset before the next shot, so that
/// a shot in one room of a building touches that room's vertices alone.
#[derive(Clone, Debug, Default)]
pub(crate) struct ClearVertices {
    flags: Vec<bool>,
    /// The vertices whose flags are set.
    set: Vec<u32>,
}

impl ClearVertices {
    /// Unsets every flag, for a mesh of `vertices` vertices.
    pub(crate) fn reset(&mut self, vertices: usize) {
        for &v in &self.set {
            if let Some(flag) = self.flags.get_mut(v as usize) {
                *flag = false;
            }
        }
        self.set.clear();
        self.flags.resize(vertices, false);
    }

    /// Marks vertex `v` clear (a vertex beyond the mesh is ignored).
    fn mark(&mut self, v: u32) {
        if let Some(flag) = self.flags.get_mut(v as usize)
            && !*flag
        {
            *flag = true;
            self.set.push(v);
        }
    }

    /// Whether vertex `v` sees all of the shooter.
    #[must_use]
    pub(crate) fn is_clear(&self, v: usize) -> bool {
        self.flags.get(v).copied().unwrap_or(false)
    }
}

/// The box of each patch's receiving points, kept while the mesh keeps its
/// vertices and elements.
#[derive(Clone, Debug, Default)]
pub(crate) struct ReceivingBoxes {
    /// Per patch: the box round its elements' vertices' receiving points,
    /// and how many vertices it has.
    boxes: Vec<(DVec3, DVec3, usize)>,
    /// The mesh's vertex and element counts the boxes were made for.
    made_for: (usize, usize),
}

impl ReceivingBoxes {
    /// Makes the boxes again if the mesh has changed.
    pub(crate) fn refresh(&mut self, mesh: &Mesh) {
        let size = (mesh.vertices.len(), mesh.elements.len());
        if self.made_for == size && self.boxes.len() == mesh.patches.len() {
            return;
        }
        self.boxes = mesh
            .patches
            .par_iter()
            .map(|patch| {
                let mut min = DVec3::INFINITY;
                let mut max = DVec3::NEG_INFINITY;
                let mut count: usize = 0;
                for &e in &patch.elements {
                    for &v in mesh.elements[e as usize].corners() {
                        let p = mesh.vertices[v as usize].receiver_position;
                        min = min.min(p);
                        max = max.max(p);
                        count += 1;
                    }
                }
                // Corners are counted once per element: about four times
                // a quad grid's vertices.
                (min, max, count.div_ceil(4))
            })
            .collect();
        self.made_for = size;
    }

    /// Marks in `clear` (one flag per vertex; resized to the vertices)
    /// the vertices of the `patches` (all when `None`) that see all of
    /// `shooter`: those of a patch whose shaft to it no triangle of
    /// `visibility` reaches into (but the shooter's and the patch's own
    /// surfaces'), and, where a patch's shaft is blocked but its elements
    /// would each cast [`ELEMENT_RAYS`] rays or more (an emitter's shot),
    /// those of its elements whose own shafts are clear. A rim of the
    /// shooter `rim` wide is left out of the shafts (see the code). Returns
    /// how many shafts were tested and how many of them were clear.
    pub(crate) fn mark_clear(
        &self,
        (scene, mesh, visibility): (&Scene, &Mesh, &Visibility),
        (shooter, density, rim): (&Shooter, f64, f64),
        patches: Option<&[u32]>,
        clear: &mut ClearVertices,
    ) -> (usize, usize) {
        clear.reset(mesh.vertices.len());
        let offset = visibility.surface_offset();
        let lift = |(min, max): (DVec3, DVec3), normal: DVec3| {
            (min + normal * offset, max + normal * offset)
        };
        // The shooter's box less a rim as wide as its receivers' inset (or
        // none), so that a wall meeting the shooter at its edge,
        // which no ray to it crosses, does not touch the shaft. Rays aimed
        // at that rim are answered by the shaft as if they were inside; a
        // triangle would have to reach into the rim's sliver of the hull
        // alone to tell, as an occluder does whose edge lines up with the
        // shooter's as seen from a vertex on a shadow boundary.
        let source = {
            let (min, max) = bounds(shooter.cell.polygon().iter().copied());
            let wide = (max - min).cmpgt(DVec3::splat(2.0 * rim));
            let inset = DVec3::select(wide, DVec3::splat(rim), DVec3::ZERO);
            lift((min + inset, max - inset), shooter.normal)
        };
        let centre = shooter.cell.centre();
        // Whether the shaft to a box of receiving points on a surface of
        // `normal` is clear.
        let shaft_clear = |(min, max): (DVec3, DVec3), surface: SurfaceId, normal: DVec3| {
            visibility.is_shaft_clear(source, lift((min, max), normal), [surface, shooter.surface])
        };
        // About how many rays `vertices` receiving points round `at` cast.
        let rays = |vertices: usize, at: DVec3| {
            let side = shooter.side_at((at - centre).length(), density);
            vertices * side * side
        };
        let test = |p: usize| -> (usize, usize, Vec<u32>) {
            let patch = &mesh.patches[p];
            let (min, max, vertices) = self.boxes[p];
            let middle = 0.5 * (min + max);
            if patch.surface == shooter.surface
                || !min.cmple(max).all()
                || rays(vertices, middle) < MIN_RAYS
            {
                return (0, 0, Vec::new());
            }
            let normal = scene.surface(patch.surface).normal();
            // Patches wholly behind the shooter, or with all of it behind
            // them, receive nothing and cast no rays anyway.
            if corners(min, max).all(|q| shooter.normal.dot(q - centre) <= 0.0)
                || shooter
                    .cell
                    .polygon()
                    .iter()
                    .all(|&q| normal.dot(q - patch.cell.centre()) <= 0.0)
            {
                return (0, 0, Vec::new());
            }
            let vertices_of = |elements: &[u32]| {
                elements
                    .iter()
                    .flat_map(|&e| mesh.elements[e as usize].corners().iter().copied())
                    .collect::<Vec<u32>>()
            };
            if shaft_clear((min, max), patch.surface, normal) {
                return (1, 1, vertices_of(&patch.elements));
            }
            if rays(1, middle) < ELEMENT_RAYS {
                return (1, 0, Vec::new());
            }
            let (mut tested, mut cleared, mut seen) = (1, 0, Vec::new());
            for &e in &patch.elements {
                let element = &mesh.elements[e as usize];
                let points = element
                    .corners()
                    .iter()
                    .map(|&v| mesh.vertices[v as usize].receiver_position);
                let (min, max) = bounds(points);
                tested += 1;
                if shaft_clear((min, max), patch.surface, normal) {
                    cleared += 1;
                    seen.extend_from_slice(element.corners());
                }
            }
            (tested, cleared, seen)
        };
        let indices: Vec<usize> = match patches {
            Some(patches) => patches.iter().map(|&p| p as usize).collect(),
            None => (0..mesh.patches.len()).collect(),
        };
        let results: Vec<(usize, usize, Vec<u32>)> = indices.into_par_iter().map(test).collect();
        let (mut tested, mut cleared) = (0, 0);
        for (t, c, vertices) in results {
            tested += t;
            cleared += c;
            for v in vertices {
                clear.mark(v);
            }
        }
        (tested, cleared)
    }
}

/// The box round `points`.
fn bounds(points: impl IntoIterator<Item = DVec3>) -> (DVec3, DVec3) {
    points
        .into_iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(min, max), p| {
            (min.min(p), max.max(p))
        })
}

/// The eight corners of a box.
fn corners(min: DVec3, max: DVec3) -> impl Iterator<Item = DVec3> {
    (0..8).map(move |k| {
        DVec3::new(
            if k & 1 == 0 { min.x } else { max.x },
            if k & 2 == 0 { min.y } else { max.y },
            if k & 4 == 0 { min.z } else { max.z },
        )
    })
}
