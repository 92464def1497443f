//! Objects standing on surfaces, or lying just in front of them: contact
//! lines in the mesh, nothing hidden kept, no darkness bleeding out from
//! under a block or from behind a ceiling panel.

use crate::support::*;
use glam::{DVec2, DVec3};
use isorad::{
    Ambient, Scene, Solver, SolverSettings, SurfaceId,
    mesh::{Mesh, SquareMeshSettings, mesh_square},
    phase::silent,
};

/// A 4 × 4 floor (z = 0) with a unit cube standing on it, centred at the
/// origin and turned by 20°, open at the bottom like the Cornell box's
/// blocks, under a light as large as the floor at z = 4.
fn block_on_floor() -> Scene {
    let mut b = SceneBuilder::default();
    let white = b.material("white", 0.5, 0.0);
    let light = b.material("light", 0.0, 20.0);
    b.polygon("floor", white, square_z(-2.0, 2.0, 0.0, true));
    let turn = 20f64.to_radians();
    let corner = |k: usize, z: f64| {
        let a = turn + std::f64::consts::FRAC_PI_2 * k as f64 + std::f64::consts::FRAC_PI_4;
        DVec3::new(a.cos() * 0.5f64.sqrt(), a.sin() * 0.5f64.sqrt(), z)
    };
    let centre = DVec3::new(0.0, 0.0, 0.5);
    for k in 0..4 {
        let side = vec![
            corner(k, 0.0),
            corner(k + 1, 0.0),
            corner(k + 1, 1.0),
            corner(k, 1.0),
        ];
        let outward = 2.0 * (0.5 * (corner(k, 0.5) + corner(k + 1, 0.5))) - centre;
        b.polygon_facing("block", white, side, outward);
    }
    b.polygon("block", white, (0..4).map(|k| corner(k, 1.0)).collect());
    b.polygon("light", light, square_z(-2.0, 2.0, 4.0, false));
    b.scene
}

/// Checks the mesh's invariants and returns the area of `surface`'s elements.
fn valid_area_of(scene: &Scene, mesh: &Mesh, surface: SurfaceId) -> f64 {
    let areas: Vec<f64> = scene.surfaces.iter().map(|s| s.area()).collect();
    mesh.validate(&areas).unwrap();
    mesh.elements
        .iter()
        .filter(|e| e.surface == surface)
        .map(|e| e.area)
        .sum()
}

/// A solver of `scene` on `mesh`, run to 0.1 % unshot power.
fn solved_to_a_thousandth(scene: Scene, mesh: Mesh) -> Solver {
    let mut settings = SolverSettings::default();
    settings.tolerance = 1e-3;
    let mut solver = Solver::with_mesh(scene, mesh, settings).unwrap();
    solver.run();
    solver
}

fn mesh_of(scene: &Scene) -> Mesh {
    let mut settings = SquareMeshSettings::for_scene(scene);
    settings.max_edge = 0.2;
    settings.patch_max_edge = 1.0;
    mesh_square(scene, &settings)
}

#[test]
fn the_floor_under_a_block_is_cut_out_along_the_contact_lines() {
    let scene = block_on_floor();
    let mesh = mesh_of(&scene);
    let floor = valid_area_of(&scene, &mesh, SurfaceId::new(0));
    assert!(
        (floor - (16.0 - 1.0)).abs() < 1e-9,
        "floor elements cover {floor}"
    );
    // No floor vertex strictly inside the block's footprint (|rotated x|, |y| < 0.5).
    let turn = -20f64.to_radians();
    for v in mesh
        .vertices
        .iter()
        .filter(|v| v.surface == SurfaceId::new(0))
    {
        let p = v.position;
        let (x, y) = (
            p.x * turn.cos() - p.y * turn.sin(),
            p.x * turn.sin() + p.y * turn.cos(),
        );
        assert!(
            x.abs().max(y.abs()) > 0.5 - 1e-9,
            "vertex under the block at {p}"
        );
    }
    // The block's own faces are untouched grids.
    assert!(
        mesh.elements
            .iter()
            .filter(|e| e.surface != SurfaceId::new(0))
            .all(|e| !e.is_triangle())
    );
}

/// [`block_on_floor`] meshed by [`mesh_of`] and solved to 0.1 %.
fn solved_block_on_floor() -> Solver {
    let scene = block_on_floor();
    let mesh = mesh_of(&scene);
    solved_to_a_thousandth(scene, mesh)
}

#[test]
fn no_darkness_bleeds_out_from_under_a_block() {
    let solver = solved_block_on_floor();
    let solution = solver.solution(Ambient::Everywhere, &silent);
    // Just outside each side of the block, the rendered mesh agrees with an
    // exact gather: the dark floor under the block no longer exists.
    let mut points = Vec::new();
    for k in 0..4 {
        let a = 20f64.to_radians() + std::f64::consts::FRAC_PI_2 * k as f64;
        for along in [-0.3, 0.0, 0.3] {
            let (c, s) = (a.cos(), a.sin());
            points.push(DVec3::new(c * 0.52 - s * along, s * 0.52 + c * along, 0.0));
        }
    }
    let worst = worst_mesh_against_gather(&solution, &points);
    assert!(
        worst < 0.1,
        "mesh vs gather just outside the block: {worst}"
    );
}

/// The faces of an axis-aligned box from `lo` to `hi` facing out, without
/// its bottom (it stands on something).
fn open_box(b: &mut SceneBuilder, name: &str, material: usize, lo: DVec3, hi: DVec3) {
    let centre = 0.5 * (lo + hi);
    let corner = |x: bool, y: bool, z: bool| {
        DVec3::new(
            if x { hi.x } else { lo.x },
            if y { hi.y } else { lo.y },
            if z { hi.z } else { lo.z },
        )
    };
    let faces = [
        [
            corner(false, false, false),
            corner(true, false, false),
            corner(true, false, true),
            corner(false, false, true),
        ],
        [
            corner(false, true, false),
            corner(true, true, false),
            corner(true, true, true),
            corner(false, true, true),
        ],
        [
            corner(false, false, false),
            corner(false, true, false),
            corner(false, true, true),
            corner(false, false, true),
        ],
        [
            corner(true, false, false),
            corner(true, true, false),
            corner(true, true, true),
            corner(true, false, true),
        ],
        [
            corner(false, false, true),
            corner(true, false, true),
            corner(true, true, true),
            corner(false, true, true),
        ],
    ];
    for face in faces {
        let middle = face.iter().copied().sum::<DVec3>() / 4.0;
        b.polygon_facing(name, material, face.to_vec(), 2.0 * middle - centre);
    }
}

/// A 2 × 0.8 m desk with a 4 cm screen standing 1 cm from its far edge,
/// under a small lamp right above the screen, in a hall whose 20 m
/// diagonal makes the contact tolerance (a thousandth of it) wider than
/// that centimetre.
fn screen_on_desk() -> Scene {
    let mut b = SceneBuilder::default();
    let white = b.material("white", 0.5, 0.0);
    let light = b.material("light", 0.0, 10.0);
    b.polygon("floor", white, square_z(-7.0, 7.0, -0.75, true));
    b.polygon(
        "desk",
        white,
        vec![
            DVec3::new(-1.0, -0.4, 0.0),
            DVec3::new(1.0, -0.4, 0.0),
            DVec3::new(1.0, 0.4, 0.0),
            DVec3::new(-1.0, 0.4, 0.0),
        ],
    );
    open_box(
        &mut b,
        "screen",
        white,
        DVec3::new(-1.0, 0.39, 0.0),
        DVec3::new(1.0, 0.43, 0.4),
    );
    let lamp: Vec<DVec3> = [(-0.2, 0.2), (-0.2, 0.6), (0.2, 0.6), (0.2, 0.2)]
        .iter()
        .map(|&(x, y)| DVec3::new(x, y, 2.2))
        .collect();
    b.polygon("light", light, lamp);
    b.scene
}

/// The desk's received power as the default mesh carries it matches the
/// integral of exact gathers over its visible part to 3 % (2.1 % short when
/// this was written), and the centimetre under the screen is not meshed.
/// Before contact lines this close to an outline were kept, and rows of
/// vertices put beside them, the desk's edge vertices gathered under the
/// screen, in the dark, and the desk received 27 % less (an office's desks
/// 15 % less).
#[test]
fn a_desk_keeps_its_light_beside_a_screen_standing_near_its_edge() {
    let scene = screen_on_desk();
    // Solved to 1 %: the mesh's light, without the ambient term, is
    // compared with gathers of the same shots.
    let mut settings = isorad::Settings::default();
    settings.solver.tolerance = 0.01;
    let mut solver = Solver::new(scene, settings).unwrap();
    solver.run();
    let solution = solver.solution(Ambient::Omitted, &silent);
    let desk = SurfaceId::new(1);
    let meshed = solution.surface_totals()[desk.index()];
    // The gathers: a jittered 24 × 24 grid over the desk beside the screen.
    let (n, width, depth) = (24, 2.0, 0.79);
    let mut random = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        random ^= random << 13;
        random ^= random >> 7;
        random ^= random << 17;
        (random >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut sum = 0.0;
    for j in 0..n {
        for i in 0..n {
            let x = -1.0 + width * (i as f64 + next()) / n as f64;
            let y = -0.4 + depth * (j as f64 + next()) / n as f64;
            sum += gather_at(&solution, DVec3::new(x, y, 0.0), None)
                .irradiance
                .r;
        }
    }
    let gathered = sum / (n * n) as f64 * width * depth;
    let ratio = meshed.received_power.r / gathered;
    println!(
        "desk beside a screen: meshed area {:.4} m², received {:.4} W, gathered {gathered:.4} W, ratio {ratio:.4}",
        meshed.area, meshed.received_power.r
    );
    assert!(
        (meshed.area - width * depth).abs() < 1e-6,
        "meshed area {}",
        meshed.area
    );
    assert!((ratio - 1.0).abs() < 0.03, "received / gathered = {ratio}");
}

/// A closed 6 × 3 × 6 m room (z up) lit by a ceiling panel, with four
/// 0.6 × 0.6 m plates 5 cm tall (a chair's base) standing on its floor, each
/// across the corner of floor patches.
fn plates_in_a_closed_room() -> Scene {
    let mut b = SceneBuilder::default();
    let white = b.material("white", 0.6, 0.0);
    let light = b.material("light", 0.0, 5.0);
    let size = DVec3::new(6.0, 6.0, 3.0);
    for face in box_faces(size) {
        b.polygon_facing("room", white, face, 0.5 * size);
    }
    for (x, y) in [(1.2, 1.2), (4.2, 1.5), (1.5, 4.2), (3.0, 3.0)] {
        let lo = DVec3::new(x - 0.3, y - 0.3, 0.0);
        open_box(&mut b, "plate", white, lo, lo + DVec3::new(0.6, 0.6, 0.05));
    }
    let panel: Vec<DVec3> = [(2.5, 2.5), (2.5, 3.5), (3.5, 3.5), (3.5, 2.5)]
        .iter()
        .map(|&(x, y)| DVec3::new(x, y, 2.99))
        .collect();
    b.polygon_facing("light", light, panel, DVec3::new(3.0, 3.0, 0.0));
    b.scene
}

/// In a closed room every shot lands somewhere: a floor patch with a plate
/// standing on part of it shoots its light from the floor around the plate,
/// not from under it, where the plate's inside would swallow it. Escaped
/// power under 1.2 % of the emitted at tolerance 10⁻³ (0.78 % when this was
/// written; 2.45 % when each stratum shot the radiosity at its centre along
/// all its rays).
#[test]
fn floor_shots_beside_plates_in_a_closed_room_land() {
    let scene = plates_in_a_closed_room();
    let mut settings = isorad::Settings::default();
    settings.solver.tolerance = 1e-3;
    let mut solver = Solver::new(scene, settings).unwrap();
    solver.run();
    let balance = solver.energy_balance();
    let escaped = balance.escaped.element_sum() / balance.emitted.element_sum();
    println!(
        "plates in a closed room: escaped {:.3} % of the emitted power",
        100.0 * escaped
    );
    assert!(escaped.abs() < 0.012, "escaped {escaped}");
}

/// Shadow boundaries are cast only where a light reaches: two closed rooms
/// side by side, each with a block on its floor, the lamp in the first.
/// The first floor follows the block's shadow; the second, in the dark,
/// gets no boundaries (the lamp's silhouettes would project onto its plane
/// through the walls).
#[test]
fn shadow_boundaries_stay_in_the_room_the_light_reaches() {
    let mut b = SceneBuilder::default();
    let wall = b.material("wall", 0.5, 0.0);
    let lamp = b.material("lamp", 0.0, 10.0);
    for (room, offset) in [("a", DVec3::ZERO), ("b", DVec3::new(5.0, 0.0, 0.0))] {
        room_with_block(&mut b, wall, room, offset);
    }
    ceiling_lamp(&mut b, lamp, DVec3::ZERO);
    let scene = b.scene;
    let visibility = isorad::scene::Visibility::new(&scene);
    let lights = isorad::lighting::area_lights(&scene);
    let boundaries = isorad::meshing::scene_shadow_boundaries(
        &scene,
        &visibility,
        &lights,
        &isorad::MeshSettings::default().resolve(&scene),
        &isorad::phase::silent,
    );
    let count = |name: &str| -> usize {
        scene
            .surfaces_with_ids()
            .filter(|(_, s)| s.name == name)
            .map(|(id, _)| boundaries[id.index()].len())
            .sum()
    };
    assert!(
        count("floor_a") >= 4,
        "{} on the lit floor",
        count("floor_a")
    );
    assert_eq!(count("floor_b"), 0);
    assert_eq!(count("wall_b") + count("block_b"), 0);
    // `max_shadow_boundaries` keeps the longest.
    let mut settings = isorad::MeshSettings::default();
    settings.max_shadow_boundaries = 2;
    let capped = isorad::meshing::scene_shadow_boundaries(
        &scene,
        &visibility,
        &lights,
        &settings.resolve(&scene),
        &isorad::phase::silent,
    );
    let floor_a = scene
        .surfaces_with_ids()
        .find(|(_, s)| s.name == "floor_a")
        .map(|(id, _)| id.index())
        .unwrap();
    let length = |s: &[DVec2; 2]| s[0].distance(s[1]);
    let mut lengths: Vec<f64> = boundaries[floor_a].iter().map(length).collect();
    lengths.sort_by(|a, b| b.total_cmp(a));
    let kept: Vec<f64> = capped[floor_a].iter().map(length).collect();
    assert_eq!(kept.len(), 2);
    assert!(
        kept.iter().all(|&l| l >= lengths[1] - 1e-12),
        "{kept:?} of {lengths:?}"
    );
    assert!(capped.iter().all(|b| b.len() <= 2));
}

/// The surface grid that meshing asks what stands on a surface finds
/// exactly the surfaces whose bounding boxes come within the margin, as
/// checking every surface does: small triangles scattered in a box, a
/// floor and a wall spanning it, boxes queried small and large.
#[test]
fn surface_boxes_find_what_brute_force_finds() {
    let mut b = SceneBuilder::default();
    let grey = b.material("grey", 0.5, 0.0);
    let mut random = Rng(17);
    for k in 0..400 {
        let centre = random.point(5.0);
        let size = if k % 50 == 0 { 3.0 } else { 0.2 };
        let (u, v) = (random.direction(), random.direction());
        let triangle = vec![centre, centre + u * size, centre + v * size];
        if u.cross(v).length() > 0.1 {
            b.polygon(&format!("t{k}"), grey, triangle);
        }
    }
    b.polygon("floor", grey, square_z(-6.0, 6.0, -5.0, true));
    let scene = b.scene;
    let boxes = isorad::scene::SurfaceBoxes::new(&scene);
    let bounds: Vec<(DVec3, DVec3)> = scene
        .surfaces
        .iter()
        .map(|s| {
            let v = s.vertices();
            let min = v.iter().copied().fold(DVec3::INFINITY, DVec3::min);
            let max = v.iter().copied().fold(DVec3::NEG_INFINITY, DVec3::max);
            (min, max)
        })
        .collect();
    for query in 0..200 {
        let centre = random.point(6.0);
        let half = DVec3::splat(if query % 20 == 0 { 4.0 } else { 0.3 });
        let margin = 0.05;
        let (min, max) = (centre - half, centre + half);
        let expected: Vec<SurfaceId> = bounds
            .iter()
            .enumerate()
            .filter(|(_, (a, b))| {
                a.cmple(max + DVec3::splat(margin)).all()
                    && b.cmpge(min - DVec3::splat(margin)).all()
            })
            .map(|(k, _)| SurfaceId::new(k))
            .collect();
        assert_eq!(boxes.near(min, max, margin), expected, "query {query}");
    }
}

/// A 4 × 4 m floor and ceiling 3 m apart, with a 0.6 m lamp panel hung
/// 1 cm below the ceiling off the grid's lines (the contact tolerance, a
/// thousandth of the 6.4 m diagonal, is narrower than that centimetre).
fn panel_under_a_ceiling() -> Scene {
    let mut b = SceneBuilder::default();
    let white = b.material("white", 0.7, 0.0);
    let light = b.material("light", 0.0, 10.0);
    b.polygon("floor", white, square_z(-2.0, 2.0, 0.0, true));
    b.polygon("ceiling", white, square_z(-2.0, 2.0, 3.0, false));
    let panel = square_z(-0.3, 0.3, 2.99, false)
        .into_iter()
        .map(|p| p + DVec3::new(0.13, 0.07, 0.0))
        .collect();
    b.polygon("panel", light, panel);
    b.scene
}

#[test]
fn a_ceiling_is_cut_out_round_a_panel_hung_just_below_it() {
    let scene = panel_under_a_ceiling();
    let mesh = mesh_of(&scene);
    let ceiling = valid_area_of(&scene, &mesh, SurfaceId::new(1));
    assert!(
        (ceiling - (16.0 - 0.36)).abs() < 1e-6,
        "the ceiling keeps {ceiling} m² of elements"
    );
    let solver = solved_to_a_thousandth(scene, mesh);
    let solution = solver.solution(Ambient::Everywhere, &silent);
    // Just round the panel, the rendered ceiling agrees with an exact
    // gather: the dark gap behind the panel no longer spreads (a whole
    // element's width, -30 % at 1 cm, before the panel's outline was cut;
    // 14 % with the vertices on the outline gathering in the dark band
    // right beside it).
    let points = [
        (0.45, 0.07),
        (-0.19, 0.07),
        (0.13, 0.39),
        (0.13, -0.25),
        (0.45, 0.39),
    ]
    .map(|(x, y)| DVec3::new(x, y, 3.0));
    let worst = worst_mesh_against_gather(&solution, &points);
    assert!(worst < 0.08, "mesh vs gather round the panel: {worst}");
}

/// Two closed rooms side by side, each with a block on its floor and a
/// lamp of its own (or the first alone).
fn lit_rooms(both: bool) -> Scene {
    let mut b = SceneBuilder::default();
    let wall = b.material("wall", 0.5, 0.0);
    let lamp = b.material("lamp", 0.0, 10.0);
    let rooms: &[(&str, DVec3)] = if both {
        &[("a", DVec3::ZERO), ("b", DVec3::new(5.0, 0.0, 0.0))]
    } else {
        &[("a", DVec3::ZERO)]
    };
    for &(room, offset) in rooms {
        room_with_block(&mut b, wall, room, offset);
    }
    for &(room, offset) in rooms {
        b.polygon_facing(
            &format!("lamp_{room}"),
            lamp,
            [(1.7, 1.7), (2.3, 1.7), (2.3, 2.3), (1.7, 2.3)]
                .map(|(x, z)| DVec3::new(x, 2.99, z) + offset)
                .to_vec(),
            DVec3::new(2.0, 0.0, 2.0) + offset,
        );
    }
    b.scene
}

/// Meshing pairs each receiver only with the luminaires and occluders of
/// its own closed room: the first room's shadow boundaries and receiver
/// analyses come out the same whether the second room, with its own lamp,
/// stands beside it or not, and none of the second room's receivers is
/// lit by the first room's lamp.
#[test]
fn a_room_meshes_the_same_among_closed_rooms() {
    let analyse = |scene: &Scene| {
        let visibility = isorad::scene::Visibility::new(scene);
        let lights = isorad::lighting::area_lights(scene);
        let settings = isorad::MeshSettings::default();
        let boundaries = isorad::meshing::scene_shadow_boundaries(
            scene,
            &visibility,
            &lights,
            &settings.resolve(scene),
            &isorad::phase::silent,
        );
        let analyses = isorad::meshing::scene_receiver_analyses(
            scene,
            &visibility,
            &lights,
            &settings.dominance,
            &isorad::phase::silent,
        );
        (lights, boundaries, analyses)
    };
    let alone = lit_rooms(false);
    let both = lit_rooms(true);
    let (lights_alone, boundaries_alone, analyses_alone) = analyse(&alone);
    let (lights, boundaries, analyses) = analyse(&both);
    assert_eq!((lights_alone.len(), lights.len()), (1, 2));
    // Room a's surfaces come first in both scenes, the lamps last.
    let room_a = alone.surfaces.len() - 1;
    assert_eq!(boundaries[..room_a], boundaries_alone[..room_a]);
    assert!(boundaries_alone[..room_a].iter().any(|b| !b.is_empty()));
    let first_lamp = |a: &isorad::lighting::ReceiverAnalysis| a.lit_by.iter().all(|&k| k == 0);
    for (with, without) in analyses.iter().zip(&analyses_alone).take(room_a) {
        assert_eq!(with.receiver, without.receiver);
        assert_eq!(with.lit_by, without.lit_by);
        assert!(
            (with.share - without.share).abs() < 1e-12,
            "{with:?} {without:?}"
        );
        assert!(first_lamp(with), "{with:?}");
    }
    // Room b is lit by its own lamp (luminaire 1) only.
    let lamp_b = |a: &isorad::lighting::ReceiverAnalysis| a.lit_by.iter().all(|&k| k == 1);
    let room_b = &analyses[room_a..];
    assert!(room_b.iter().any(|a| !a.lit_by.is_empty()));
    assert!(room_b.iter().all(lamp_b), "{room_b:?}");
}

/// Two books 6 cm thick standing side by side `gap` apart on a 4 × 4 m
/// floor under a light as large as the floor, 4 m up: the first 30 cm
/// tall, the second 25 cm, both 20 cm deep.
fn books_on_a_floor(gap: f64) -> Scene {
    let mut b = SceneBuilder::default();
    let white = b.material("white", 0.5, 0.0);
    let light = b.material("light", 0.0, 10.0);
    b.polygon("floor", white, square_z(-2.0, 2.0, 0.0, true));
    b.polygon("light", light, square_z(-2.0, 2.0, 4.0, false));
    let (lo, hi) = (
        DVec3::new(-0.06 - gap, -0.1, 0.0),
        DVec3::new(-gap, 0.1, 0.3),
    );
    open_box(&mut b, "tall book", white, lo, hi);
    let (lo, hi) = (DVec3::new(0.0, -0.1, 0.0), DVec3::new(0.06, 0.1, 0.25));
    open_box(&mut b, "short book", white, lo, hi);
    b.scene
}

#[test]
fn the_sides_of_books_a_millimetre_apart_keep_only_what_the_slot_leaves_open() {
    let scene = books_on_a_floor(0.001);
    // The faces of `open_box`: -y, +y, -x, +x, top; the tall book's first.
    let (tall_side, short_side) = (SurfaceId::new(2 + 3), SurfaceId::new(7 + 2));
    let mesh = mesh_of(&scene);
    // The tall book's side keeps the 5 cm strip above the short book; the
    // short book's side, wholly behind the tall one's, keeps nothing.
    let tall = valid_area_of(&scene, &mesh, tall_side);
    let short = valid_area_of(&scene, &mesh, short_side);
    assert!(
        (tall - 0.2 * 0.05).abs() < 1e-9,
        "the tall side keeps {tall} m²"
    );
    assert!(short.abs() < 1e-12, "the short side keeps {short} m²");
    let solver = solved_to_a_thousandth(scene, mesh);
    let solution = solver.solution(Ambient::Everywhere, &silent);
    // The power the two sides receive is what exact gathers find over the
    // tall side's open strip (a 10 × 10 grid), plus at most what enters
    // the slot's two 1 mm × 25 cm mouths at the brightest irradiance on
    // the floor: the slot's light dies within a few millimetres of them.
    // Before the slot was cut out, its vertices gathered the room's light
    // at the mouths, and the sides received 4.9 times the strip's power.
    let received: f64 = [tall_side, short_side]
        .iter()
        .map(|id| solution.surface_totals()[id.index()].received_power.r)
        .sum();
    let mut strip = 0.0;
    for i in 0..10 {
        for j in 0..10 {
            let y = -0.1 + 0.2 * (f64::from(i) + 0.5) / 10.0;
            let z = 0.25 + 0.05 * (f64::from(j) + 0.5) / 10.0;
            let probe = gather_at(&solution, DVec3::new(-0.001, y, z), Some(DVec3::X));
            strip += probe.irradiance.r * 0.2 * 0.05 / 100.0;
        }
    }
    let brightest = gather_at(&solution, DVec3::new(0.0, 0.5, 0.0), Some(DVec3::Z))
        .irradiance
        .r;
    let mouths = 2.0 * 0.001 * 0.25 * brightest;
    assert!(
        received > 0.85 * strip && received < 1.15 * strip + mouths,
        "the books' facing sides receive {received} W; their open strip {strip} W, \
         the slot's mouths at most {mouths} W"
    );
}

#[test]
fn books_farther_apart_than_the_contact_tolerance_keep_their_sides() {
    // 2 cm apart, three times the contact tolerance (a thousandth of the
    // 6.9 m diagonal): a viewer can look into the slot, and would see
    // through dropped faces into the books.
    let scene = books_on_a_floor(0.02);
    let mesh = mesh_of(&scene);
    let tall = valid_area_of(&scene, &mesh, SurfaceId::new(2 + 3));
    let short = valid_area_of(&scene, &mesh, SurfaceId::new(7 + 2));
    assert!(
        (tall - 0.2 * 0.3).abs() < 1e-9,
        "the tall side keeps {tall} m²"
    );
    assert!(
        (short - 0.2 * 0.25).abs() < 1e-9,
        "the short side keeps {short} m²"
    );
}

#[test]
fn a_mesh_probe_under_a_block_reads_the_dark_the_mesh_dropped() {
    let solver = solved_block_on_floor();
    let solution = solver.solution(Ambient::Everywhere, &silent);
    let probe = |x: f64, mode| {
        let point = isorad::scene::ProbePoint {
            position: DVec3::new(x, 0.0, 0.0),
            normal: None,
            line: 1,
        };
        solution.probe(&point, mode).unwrap()
    };
    // Under the block's middle no element is left: no light, as a gather
    // finds (before, the nearest element beside the block answered, lit).
    for mode in [isorad::ProbeMode::Mesh, isorad::ProbeMode::Gather] {
        let under = probe(0.0, mode);
        assert!(
            under.irradiance.r < 1e-6,
            "{mode:?}: {:?}",
            under.irradiance
        );
    }
    // Beside it the mesh is read as before.
    let beside = probe(1.2, isorad::ProbeMode::Mesh);
    let gathered = probe(1.2, isorad::ProbeMode::Gather);
    assert!(beside.irradiance.r > 1.0);
    let off = (beside.irradiance.r / gathered.irradiance.r - 1.0).abs();
    assert!(
        off < 0.05,
        "mesh {:?} against gather {:?}",
        beside.irradiance,
        gathered.irradiance
    );
}

/// A 4 × 4 m floor under a light as large as it, 4 m up, and a wall
/// (surface 2) standing on it at y = 0.3, facing −y; and the white
/// material's index.
fn floor_and_wall() -> (SceneBuilder, usize) {
    let mut b = SceneBuilder::default();
    let white = b.material("white", 0.5, 0.0);
    let light = b.material("light", 0.0, 10.0);
    b.polygon("floor", white, square_z(-2.0, 2.0, 0.0, true));
    b.polygon("light", light, square_z(-2.0, 2.0, 4.0, false));
    let wall = vec![
        DVec3::new(-2.0, 0.3, 0.0),
        DVec3::new(2.0, 0.3, 0.0),
        DVec3::new(2.0, 0.3, 3.0),
        DVec3::new(-2.0, 0.3, 3.0),
    ];
    b.polygon_facing("wall", white, wall, DVec3::new(0.0, -1.0, 0.0));
    (b, white)
}

/// [`floor_and_wall`] with a book 6 cm thick, 30 cm tall and 20 cm deep
/// standing on the floor, its back 2 cm in front of the wall.
fn book_before_a_wall() -> Scene {
    let (mut b, white) = floor_and_wall();
    let (lo, hi) = (DVec3::new(-0.03, 0.08, 0.0), DVec3::new(0.03, 0.28, 0.3));
    open_box(&mut b, "book", white, lo, hi);
    b.scene
}

/// Further from the wall than the contact tolerance, the book hides none
/// of it, but its outline is drawn on the wall as element edges: the wall
/// behind the book is dark and the wall just above it lit, a step that an
/// element 20 cm across spread over the wall above the book.
#[test]
fn a_book_two_centimetres_before_a_wall_draws_its_outline_on_the_wall() {
    let scene = book_before_a_wall();
    let wall = SurfaceId::new(2);
    let mesh = mesh_of(&scene);
    let on_wall = |p: DVec3| {
        mesh.vertices
            .iter()
            .any(|v| v.surface == wall && v.position.distance(p) < 1e-6)
    };
    for x in [-0.03, 0.03] {
        assert!(
            on_wall(DVec3::new(x, 0.3, 0.3)),
            "no wall vertex at the book's top corner x = {x}"
        );
    }
    assert!(
        (valid_area_of(&scene, &mesh, wall) - 12.0).abs() < 1e-9,
        "the wall keeps all of its area"
    );
    let solver = solved_to_a_thousandth(scene, mesh);
    let solution = solver.solution(Ambient::Everywhere, &silent);
    // Just above the book, the mesh reads what a gather finds there.
    for z in [0.32, 0.36] {
        let point = isorad::scene::ProbePoint {
            position: DVec3::new(0.0, 0.3, z),
            normal: None,
            line: 1,
        };
        let mesh_probe = solution.probe(&point, isorad::ProbeMode::Mesh).unwrap();
        let gathered = gather_at(&solution, point.position, None);
        let ratio = mesh_probe.irradiance.r / gathered.irradiance.r;
        assert!(
            (ratio - 1.0).abs() < 0.05,
            "{z}: mesh {:?} against gather {:?}",
            mesh_probe.irradiance,
            gathered.irradiance
        );
    }
}

/// A panel 1 cm thick, 50 × 40 cm, hung with its back 1.5 cm in front of
/// the wall of [`floor_and_wall`]: its back faces the wall across the gap,
/// and its front, 2.5 cm out, faces the room. Both draw the same outline
/// on the wall, and one of them must stay.
#[test]
fn a_panel_hung_before_a_wall_draws_its_outline_once() {
    let (mut b, white) = floor_and_wall();
    let face = |y: f64| {
        vec![
            DVec3::new(-0.25, y, 1.0),
            DVec3::new(0.25, y, 1.0),
            DVec3::new(0.25, y, 1.4),
            DVec3::new(-0.25, y, 1.4),
        ]
    };
    b.polygon_facing("panel back", white, face(0.285), DVec3::Y);
    b.polygon_facing("panel front", white, face(0.275), -DVec3::Y);
    let scene = b.scene;
    let mesh = mesh_of(&scene);
    let wall = SurfaceId::new(2);
    for corner in [DVec3::new(-0.25, 0.3, 1.0), DVec3::new(0.25, 0.3, 1.4)] {
        assert!(
            mesh.vertices
                .iter()
                .any(|v| v.surface == wall && v.position.distance(corner) < 1e-6),
            "no wall vertex at the panel's corner {corner}"
        );
    }
}
