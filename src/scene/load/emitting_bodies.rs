//! Lamps modelled as faces on many planes, joined into one luminaire each.
//!
//! Emitting faces of one material that share a vertex belong to one lamp.
//! A lamp whose faces all lie in one plane stays a set of emitting faces,
//! shot patch by patch with exact kernels (`lighting::AreaLight` joins
//! them for the meshers). A lamp on more than one plane (a tessellated
//! lens, a globe, a faceted tube) becomes one
//! [`PhotometricLuminaire::of_body`], so that its cost follows the number
//! of lamps, not of faces (see `scene/emitting_body.rs`).

use std::collections::HashMap;

use glam::DVec3;

use crate::scene::{EmittingBody, PhotometricLuminaire, Scene, Surface, SurfaceId};
use crate::union_find::root;

/// Vertices closer than this fraction of the scene's diagonal are shared.
const WELD: f64 = 1e-6;

/// Normals of one plane differ by at most this (unit vectors).
const SAME_PLANE: f64 = 1e-6;

/// Vertices of one plane lie within this fraction of the diagonal of it,
/// as `lighting::AreaLight` joins coplanar lamps.
const PLANE_DISTANCE: f64 = 1e-5;

impl Scene {
    /// Joins each lamp modelled as emitting faces on more than one plane
    /// into one luminaire ([`PhotometricLuminaire::of_body`]), appended to
    /// [`Scene::luminaires`]; returns how many. The faces stay in the scene
    /// and are drawn with their emission; their emission is shot by the
    /// luminaire, not by their patches. The loaders call this; a scene
    /// built in code may too. Faces already in a body are left alone, so
    /// a second call adds nothing.
    pub fn join_emitting_bodies(&mut self) -> usize {
        let groups = emitting_groups(self);
        let before = self.luminaires.len();
        for surfaces in groups {
            let material = &self.materials[self.surface(surfaces[0]).material];
            let (name, exitance) = (material.name.clone(), material.emitted_radiosity());
            let faces: Vec<&Surface> = surfaces.iter().map(|&id| self.surface(id)).collect();
            let body = EmittingBody::new(surfaces.clone(), &faces, name, exitance);
            if let Some(luminaire) = body.and_then(PhotometricLuminaire::of_body) {
                self.luminaires.push(luminaire);
            }
        }
        self.luminaires.len() - before
    }

    /// Whether each surface's emission is shot by an emitting body's
    /// luminaire rather than by its own patches, by surface index.
    #[must_use]
    pub fn in_emitting_body(&self) -> Vec<bool> {
        let mut inside = vec![false; self.surfaces.len()];
        let bodies = self.luminaires.iter().filter_map(|l| l.body.as_ref());
        for id in bodies.flat_map(|b| &b.surfaces) {
            if let Some(flag) = inside.get_mut(id.index()) {
                *flag = true;
            }
        }
        inside
    }
}

/// The groups of emitting faces of one material joined by shared vertices
/// that span more than one plane, each ascending, in order of their first
/// face; faces already in a body are left out.
fn emitting_groups(scene: &Scene) -> Vec<Vec<SurfaceId>> {
    let taken = scene.in_emitting_body();
    let emitters: Vec<SurfaceId> = scene
        .surfaces_with_ids()
        .filter(|(id, s)| !taken[id.index()] && scene.material_of(s).is_emitter())
        .map(|(id, _)| id)
        .collect();
    let weld = WELD * scene.diagonal().max(f64::MIN_POSITIVE);
    let key = |v: DVec3| (v / weld).round().as_i64vec3().to_array();
    // Every vertex's cell, and the faces with a vertex in it.
    let mut cells: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (k, &id) in emitters.iter().enumerate() {
        for &v in scene.surface(id).vertices() {
            cells.entry(key(v)).or_default().push(k);
        }
    }
    let mut parent: Vec<usize> = (0..emitters.len()).collect();
    for (k, &id) in emitters.iter().enumerate() {
        let material = scene.surface(id).material;
        for &v in scene.surface(id).vertices() {
            let [x, y, z] = key(v);
            for neighbour in neighbour_cells(x, y, z) {
                for &other in cells.get(&neighbour).into_iter().flatten() {
                    if scene.surface(emitters[other]).material == material {
                        let (a, b) = (root(&mut parent, k), root(&mut parent, other));
                        parent[a.max(b)] = a.min(b);
                    }
                }
            }
        }
    }
    let mut groups: Vec<Vec<SurfaceId>> = Vec::new();
    let mut group_of_root: HashMap<usize, usize> = HashMap::new();
    for (k, &id) in emitters.iter().enumerate() {
        let r = root(&mut parent, k);
        let next = groups.len();
        let g = *group_of_root.entry(r).or_insert(next);
        if g == next {
            groups.push(Vec::new());
        }
        groups[g].push(id);
    }
    let tolerance = PLANE_DISTANCE * scene.diagonal();
    groups.retain(|g| spans_planes(scene, g, tolerance));
    groups
}

/// The 27 cells around and including (x, y, z).
fn neighbour_cells(x: i64, y: i64, z: i64) -> impl Iterator<Item = [i64; 3]> {
    (-1..=1)
        .flat_map(move |a| (-1..=1).flat_map(move |b| (-1..=1).map(move |c| [x + a, y + b, z + c])))
}

/// Whether the faces lie on more than one plane.
fn spans_planes(scene: &Scene, group: &[SurfaceId], tolerance: f64) -> bool {
    let first = scene.surface(group[0]);
    group.iter().skip(1).any(|&id| {
        let s = scene.surface(id);
        (s.normal() - first.normal()).length() > SAME_PLANE
            || s.vertices()
                .iter()
                .any(|&v| first.frame().height(v).abs() > tolerance)
    })
}
