//! Shadow boundaries against their closed forms: plates' central
//! projections, umbrae that hide others, a box's silhouette.

use glam::{DVec2, DVec3};

use super::merge::merge_boundaries;
use super::*;
use crate::lighting::area_lights;
use crate::rgb::Rgb;
use crate::scene::{Material, SurfaceBoxes, distance_to_segment};

/// A 10 × 10 floor at y = 0, a 0.2 m square lamp facing down at
/// `lamp_height` over the origin, and an occluder given by its polygons.
fn scene_with(occluder: &[Vec<DVec3>], lamp_height: f64) -> Scene {
    let mut scene = Scene::new();
    let grey = scene
        .add_material(Material::diffuse("grey", Rgb::splat(0.5)))
        .unwrap();
    let lamp = scene
        .add_material(Material::emitter("lamp", Rgb::splat(10.0)))
        .unwrap();
    let floor = [(-5.0, -5.0), (-5.0, 5.0), (5.0, 5.0), (5.0, -5.0)];
    let floor: Vec<DVec3> = floor.iter().map(|&(x, z)| DVec3::new(x, 0.0, z)).collect();
    scene.add_polygon("floor", grey, &floor).unwrap();
    let h = lamp_height;
    let square = [(-0.1, -0.1), (0.1, -0.1), (0.1, 0.1), (-0.1, 0.1)];
    let lamp_polygon: Vec<DVec3> = square.iter().map(|&(x, z)| DVec3::new(x, h, z)).collect();
    scene.add_polygon("lamp", lamp, &lamp_polygon).unwrap();
    for polygon in occluder {
        scene.add_polygon("occluder", grey, polygon).unwrap();
    }
    scene
}

/// Parallel boundaries 2 m long at heights `ys`, the one at `longest`
/// a little longer (kept first).
fn parallel_lines(ys: &[f64], longest: f64) -> Vec<[DVec2; 2]> {
    ys.iter()
        .map(|&y| {
            let end = if y == longest { 2.01 } else { 2.0 };
            [DVec2::new(0.0, y), DVec2::new(end, y)]
        })
        .collect()
}

#[test]
fn a_cluster_wider_than_the_feature_size_keeps_its_outermost_boundaries() {
    let limits = BoundaryLimits {
        min_feature: 0.04,
        max_per_receiver: 100,
    };
    let heights = |kept: Vec<[DVec2; 2]>| {
        let mut ys: Vec<f64> = kept.iter().map(|s| s[0].y).collect();
        ys.sort_by(f64::total_cmp);
        ys
    };
    // A ledge's penumbra 4 cm wide: its two edges, not its middle.
    let wide = parallel_lines(&[0.855, 0.865, 0.875, 0.885, 0.895], 0.875);
    assert_eq!(heights(merge_boundaries(wide, limits)), [0.855, 0.895]);
    // Narrower than the feature size: one line.
    let narrow = parallel_lines(&[0.865, 0.875, 0.885], 0.875);
    assert_eq!(heights(merge_boundaries(narrow, limits)), [0.875]);
}

fn limits() -> BoundaryLimits {
    BoundaryLimits {
        min_feature: 1e-3,
        max_per_receiver: 1000,
    }
}

fn boundaries_on_floor(scene: &Scene) -> Vec<[DVec2; 2]> {
    let neighbours = EdgeNeighbours::new(scene);
    let lights = area_lights(scene);
    let boxes = SurfaceBoxes::new(scene);
    let occluders = |low, high| boxes.near(low, high, 0.0);
    let receiver = ShadowReceiver {
        surface: SurfaceId::new(0),
        occluders: &occluders,
    };
    let visibility = Visibility::new(scene);
    shadow_boundaries(
        scene,
        &visibility,
        &neighbours,
        receiver,
        &lights,
        &[],
        limits(),
    )
}

/// A horizontal plate, 1 m wide, at height 1, facing up (or down).
fn plate(up: bool) -> Vec<DVec3> {
    let mut p = vec![
        DVec3::new(0.5, 1.0, -0.5),
        DVec3::new(-0.5, 1.0, -0.5),
        DVec3::new(-0.5, 1.0, 0.5),
        DVec3::new(0.5, 1.0, 0.5),
    ];
    if !up {
        p.reverse();
    }
    p
}

#[test]
fn a_plate_casts_each_edge_from_each_lamp_corner_at_its_central_projection() {
    // Lamp at 2 m, plate at 1 m: from corner (cx, cz), the plate's edge
    // x = 0.5 falls at x = cx + (0.5 − cx) · 2 / (2 − 1).
    for up in [true, false] {
        let scene = scene_with(&[plate(up)], 2.0);
        let frame = *scene.surface(SurfaceId::new(0)).frame();
        let found = boundaries_on_floor(&scene);
        // 4 corners × 4 edges, none closer than a millimetre to another.
        assert_eq!(found.len(), 16, "{found:?}");
        for cx in [-0.1, 0.1] {
            for cz in [-0.1, 0.1] {
                for (edge_x, edge_z) in [(0.5, cz), (-0.5, cz), (cx, 0.5), (cx, -0.5)] {
                    let x = cx + (edge_x - cx) * 2.0;
                    let z = cz + (edge_z - cz) * 2.0;
                    let expected = frame.to_plane(DVec3::new(x, 0.0, z));
                    let hit = found
                        .iter()
                        .any(|&[a, b]| distance_to_segment(expected, a, b) < 1e-9);
                    assert!(hit, "no boundary through {expected} (corner {cx}, {cz})");
                }
            }
        }
    }
}

/// A square plate of half-size `r` centred at `centre`, facing up.
fn plate_at(r: f64, centre: DVec3) -> Vec<DVec3> {
    [(r, -r), (-r, -r), (-r, r), (r, r)]
        .iter()
        .map(|&(dx, dz)| DVec3::new(centre.x + dx, centre.y, centre.z + dz))
        .collect()
}

#[test]
fn a_plate_in_another_plates_umbra_casts_no_boundary() {
    // Lamp at 3 m (corners at ±0.1), a 2 m plate at 2 m whose umbra on
    // the floor reaches |x| < 2.6, and a 0.5 m plate at 1 m whose shadow
    // (within 0.6 of the centre) falls wholly inside it: every shadow
    // ray from the small plate's shadow to its edges, or from them to
    // the lamp, is blocked by the big plate, so only the big plate's 16
    // (4 edges from 4 lamp corners) remain. (The small plate is off
    // centre: a ray through the big plate's diagonal, the seam of its
    // two triangles, may slip through in f32.)
    let big = plate_at(1.0, DVec3::new(0.0, 2.0, 0.0));
    let scene = scene_with(&[big, plate_at(0.25, DVec3::new(0.1, 1.0, 0.05))], 3.0);
    let found = boundaries_on_floor(&scene);
    assert_eq!(found.len(), 16, "{found:?}");
    for [a, b] in found {
        for p in [a, b] {
            assert!(p.x.abs().max(p.y.abs()) > 2.5, "{p}");
        }
    }
}

#[test]
fn a_box_casts_only_its_silhouette_edges() {
    // A closed 1 m cube from 0.5 to 1.5 m high: seen from a lamp corner
    // above it, only the top face's outline and the vertical edges on the
    // far side are silhouettes; the bottom face's edges are hidden behind
    // the sides, so fewer boundaries than edges × corners.
    let (lo, hi) = (DVec3::new(-0.5, 0.5, -0.5), DVec3::new(0.5, 1.5, 0.5));
    let corner = |x: bool, y: bool, z: bool| {
        DVec3::new(
            if x { hi.x } else { lo.x },
            if y { hi.y } else { lo.y },
            if z { hi.z } else { lo.z },
        )
    };
    let faces: Vec<Vec<DVec3>> = [
        [(0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)], // top, +y
        [(0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)], // bottom, −y
        [(0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)], // −z
        [(1, 0, 1), (1, 1, 1), (0, 1, 1), (0, 0, 1)], // +z
        [(0, 0, 1), (0, 1, 1), (0, 1, 0), (0, 0, 0)], // −x
        [(1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)], // +x
    ]
    .iter()
    .map(|face| {
        face.iter()
            .map(|&(x, y, z)| corner(x == 1, y == 1, z == 1))
            .collect()
    })
    .collect();
    let scene = scene_with(&faces, 3.0);
    let found = boundaries_on_floor(&scene);
    // From above the top face (the lamp is within the cube's footprint),
    // the silhouette is the top face's outline: 4 edges per corner.
    assert_eq!(found.len(), 16, "{found:?}");
    // Each lies outside the cube's footprint, none is the bottom's
    // outline (the shadow is wider than the cube).
    for [a, b] in found {
        for p in [a, b] {
            assert!(p.x.abs().max(p.y.abs()) > 0.5 + 1e-6, "{p}");
        }
    }
}

#[test]
fn nothing_above_the_lamp_or_behind_the_floor_casts_a_boundary() {
    // A plate above the lamp (lamp at 0.5 m), and one under the floor.
    let below: Vec<DVec3> = plate(true)
        .iter()
        .map(|p| DVec3::new(p.x, -1.0, p.z))
        .collect();
    let scene = scene_with(&[plate(true), below], 0.5);
    assert!(boundaries_on_floor(&scene).is_empty());
}
