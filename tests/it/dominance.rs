//! AreaLight grouping and the dominant-small-emitter analysis on scenes
//! whose answer is known.

use crate::support::{SceneBuilder, square_z};
use glam::DVec3;
use isorad::{
    Rgb, Scene, SurfaceId,
    lighting::{DominanceSettings, analyse_receivers, area_lights},
    scene::Visibility,
};

/// A rectangle [x0, x1] × [y0, y1] at height z, facing up or down.
fn rectangle(x0: f64, x1: f64, y0: f64, y1: f64, z: f64, facing_up: bool) -> Vec<DVec3> {
    let mut v = vec![
        DVec3::new(x0, y0, z),
        DVec3::new(x1, y0, z),
        DVec3::new(x1, y1, z),
        DVec3::new(x0, y1, z),
    ];
    if !facing_up {
        v.reverse();
    }
    v
}

#[test]
fn the_two_triangles_of_a_quad_lamp_are_one_luminaire() {
    let mut b = SceneBuilder::default();
    let white = b.material("white", 0.5, 0.0);
    let light = b.material("light", 0.0, 2.0);
    b.polygon("floor", white, square_z(-2.0, 2.0, 0.0, true));
    let [p, q, r, s] =
        [(0.0, 0.0), (0.4, 0.0), (0.4, 0.2), (0.0, 0.2)].map(|(x, y)| DVec3::new(x, y, 1.0));
    // Facing down: clockwise seen from above.
    b.polygon("lamp", light, vec![p, r, q]);
    b.polygon("lamp", light, vec![p, s, r]);
    let lamps = area_lights(&b.scene);
    assert_eq!(lamps.len(), 1);
    let lamp = &lamps[0];
    assert_eq!(lamp.surfaces, vec![SurfaceId::new(1), SurfaceId::new(2)]);
    assert!((lamp.area - 0.08).abs() < 1e-15);
    assert!(
        (lamp.centre - DVec3::new(0.2, 0.1, 1.0)).length() < 1e-15,
        "{}",
        lamp.centre
    );
    assert!((lamp.radius - 0.05f64.sqrt()).abs() < 1e-12);
    assert!((lamp.normal - DVec3::NEG_Z).length() < 1e-15);
    assert!(
        (lamp.exitance - Rgb::splat(2.0 * std::f64::consts::PI))
            .abs()
            .max_element()
            < 1e-12
    );
}

#[test]
fn separate_lamps_and_unlike_neighbours_stay_apart() {
    let mut b = SceneBuilder::default();
    let light = b.material("light", 0.0, 1.0);
    let other = b.material("other light", 0.0, 1.0);
    // Two lamps apart; a third touching the second but of another material;
    // a fourth touching the first at a vertex only (joined); a fifth sharing
    // an edge with the first but tilted (apart).
    b.polygon("a", light, rectangle(0.0, 1.0, 0.0, 1.0, 3.0, false));
    b.polygon("b", light, rectangle(2.0, 3.0, 0.0, 1.0, 3.0, false));
    b.polygon("c", other, rectangle(3.0, 4.0, 0.0, 1.0, 3.0, false));
    b.polygon("d", light, rectangle(-1.0, 0.0, -1.0, 0.0, 3.0, false));
    b.polygon(
        "e",
        light,
        vec![
            DVec3::new(0.0, 1.0, 3.0),
            DVec3::new(0.0, 2.0, 3.5),
            DVec3::new(1.0, 2.0, 3.5),
            DVec3::new(1.0, 1.0, 3.0),
        ],
    );
    let groups: Vec<Vec<usize>> = area_lights(&b.scene)
        .into_iter()
        .map(|l| l.surfaces.iter().map(|id| id.index()).collect())
        .collect();
    assert_eq!(groups, vec![vec![0, 3], vec![1], vec![2], vec![4]]);
    assert!(area_lights(&Scene::default()).is_empty());
}

/// Analyses a scene with the default settings.
fn analyse(scene: &Scene) -> Vec<isorad::lighting::ReceiverAnalysis> {
    let visibility = Visibility::new(scene);
    analyse_receivers(
        scene,
        &visibility,
        &area_lights(scene),
        &DominanceSettings::default(),
    )
}

/// `analyse_receivers_among` pairs receivers only with the luminaires it is
/// given: all of them gives `analyse_receivers`' answer, none leaves every
/// receiver unlit.
#[test]
fn receivers_are_analysed_only_among_the_luminaires_allowed() {
    let mut b = SceneBuilder::default();
    let white = b.material("white", 0.5, 0.0);
    let bright = b.material("bright", 0.0, 10.0);
    b.polygon("floor", white, square_z(-5.0, 5.0, 0.0, true));
    b.polygon("lamp", bright, square_z(-0.1, 0.1, 3.0, false));
    let scene = b.scene;
    let visibility = Visibility::new(&scene);
    let lights = area_lights(&scene);
    let settings = DominanceSettings::default();
    let among = |allow: bool| {
        let room_of = |_| (&visibility, if allow { vec![0] } else { Vec::new() });
        isorad::lighting::analyse_receivers_among(&scene, &lights, &settings, &room_of)
    };
    assert_eq!(among(true), analyse(&scene));
    assert_eq!(analyse(&scene)[0].dominant, Some(0));
    let unlit = among(false);
    assert_eq!(unlit.len(), 1);
    assert!(
        unlit[0].lit_by.is_empty() && unlit[0].dominant.is_none(),
        "{unlit:?}"
    );
}

#[test]
fn a_small_bright_lamp_dominates_a_big_dim_panel() {
    let mut b = SceneBuilder::default();
    let white = b.material("white", 0.5, 0.0);
    let bright = b.material("bright", 0.0, 10.0);
    let dim = b.material("dim", 0.0, 0.002);
    b.polygon("floor", white, square_z(-5.0, 5.0, 0.0, true));
    b.polygon("panel", dim, square_z(-3.0, 3.0, 3.1, false));
    b.polygon("lamp", bright, square_z(-0.1, 0.1, 3.0, false));
    let analyses = analyse(&b.scene);
    assert_eq!(analyses.len(), 1);
    let floor = &analyses[0];
    assert_eq!(floor.dominant, Some(1), "{floor:?}");
    // Radius 0.1√2 at 3 above the floor.
    assert!(
        (floor.size_ratio - 0.02f64.sqrt() / 3.0).abs() < 1e-9,
        "{floor:?}"
    );
    assert!(
        floor.share > 0.75 && floor.share < 1.0 && floor.qualifies,
        "{floor:?}"
    );
}

#[test]
fn two_equal_lamps_far_apart_leave_a_long_floor_undominated() {
    let mut b = SceneBuilder::default();
    let white = b.material("white", 0.5, 0.0);
    let light = b.material("light", 0.0, 5.0);
    b.polygon("floor", white, rectangle(-10.0, 10.0, -2.0, 2.0, 0.0, true));
    b.polygon(
        "left lamp",
        light,
        rectangle(-8.1, -7.9, -0.1, 0.1, 2.0, false),
    );
    b.polygon(
        "right lamp",
        light,
        rectangle(7.9, 8.1, -0.1, 0.1, 2.0, false),
    );
    let floor = &analyse(&b.scene)[0];
    assert_eq!(floor.dominant, None, "{floor:?}");
    assert!(
        !floor.qualifies && (floor.share - 0.5).abs() < 0.1,
        "{floor:?}"
    );
}

#[test]
fn a_floor_in_a_lamps_full_shadow_is_not_dominated_by_it() {
    let mut b = SceneBuilder::default();
    let white = b.material("white", 0.5, 0.0);
    let bright = b.material("bright", 0.0, 10.0);
    let side = b.material("side light", 0.0, 2.0);
    b.polygon("floor", white, square_z(-1.0, 1.0, 0.0, true));
    // A plate at 1.5 hides the bright lamp at 3 from all of the floor.
    b.polygon("plate", white, square_z(-1.5, 1.5, 1.5, true));
    b.polygon("overhead lamp", bright, square_z(-0.1, 0.1, 3.0, false));
    // A wall lamp beside the floor, under the plate, facing +x.
    b.polygon_facing(
        "wall lamp",
        side,
        vec![
            DVec3::new(-3.0, -0.1, 0.4),
            DVec3::new(-3.0, 0.1, 0.4),
            DVec3::new(-3.0, 0.1, 0.6),
            DVec3::new(-3.0, -0.1, 0.6),
        ],
        DVec3::ZERO,
    );
    let scene = b.scene;
    let analyses = analyse(&scene);
    let floor = analyses
        .iter()
        .find(|a| a.receiver == SurfaceId::new(0))
        .unwrap();
    assert_eq!(floor.dominant, Some(1), "the wall lamp: {floor:?}");
    assert!(floor.share > 0.99, "{floor:?}");
    // Without the plate, the overhead lamp would win.
    let mut open = scene.clone();
    open.surfaces.remove(1);
    let floor = &analyse(&open)[0];
    assert_eq!(floor.dominant, Some(0), "{floor:?}");
}

#[test]
fn no_lamps_no_light_no_dominant() {
    let mut b = SceneBuilder::default();
    let white = b.material("white", 0.5, 0.0);
    b.polygon("floor", white, square_z(-1.0, 1.0, 0.0, true));
    let floor = &analyse(&b.scene)[0];
    assert_eq!(
        (floor.dominant, floor.share, floor.qualifies),
        (None, 0.0, false)
    );
    assert!(floor.size_ratio.is_infinite());
    assert!(analyse(&Scene::default()).is_empty());
}

#[test]
fn settings_are_validated() {
    assert!(DominanceSettings::default().validate().is_ok());
    for (share, ratio) in [
        (0.0, 0.25),
        (1.5, 0.25),
        (f64::NAN, 0.25),
        (0.6, 0.0),
        (0.6, f64::INFINITY),
    ] {
        let mut settings = DominanceSettings::default();
        settings.min_share = share;
        settings.max_size_ratio = ratio;
        assert!(settings.validate().is_err(), "{share} {ratio}");
    }
}
