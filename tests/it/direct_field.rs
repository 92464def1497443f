//! The direct field of a luminaire on a receiver's plane against analytic
//! references: finite differences of its gradient, the coaxial disc, the
//! seed's closed-form maximum, and the kink line.
//!
//! Run with `--nocapture` to see the worst agreement of each check.

use crate::support::{Rng, SceneBuilder, coaxial_disc_form_factor, disc_facing_down, square_z};
use glam::{DVec2, DVec3};
use isorad::{
    Scene, SurfaceId,
    lighting::{AreaLight, DirectField, area_lights},
    radiometry::tilt_line_maximum,
};

/// A square of side `side` centred at `centre`, facing along the unit `normal`.
fn square_facing(centre: DVec3, normal: DVec3, side: f64) -> Vec<DVec3> {
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    let h = 0.5 * side;
    [(-h, -h), (h, -h), (h, h), (-h, h)]
        .iter()
        .map(|&(a, b)| centre + u * a + v * b)
        .collect()
}

/// A scene of one receiver (surface 0, reflectance 0.5) and one luminaire
/// polygon (Ke = 1, exitance π), and the field between them.
fn field(receiver: Vec<DVec3>, lamp: Vec<DVec3>) -> (Scene, AreaLight, DirectField) {
    let mut b = SceneBuilder::default();
    let white = b.material("white", 0.5, 0.0);
    let light = b.material("light", 0.0, 1.0);
    b.polygon("receiver", white, receiver);
    b.polygon("lamp", light, lamp);
    let scene = b.scene;
    let luminaire = area_lights(&scene).remove(0);
    let field = DirectField::new(&scene, SurfaceId::new(0), &luminaire)
        .expect("the lamp lights the receiver");
    (scene, luminaire, field)
}

/// A tilt of `degrees` about y: the normal of a lamp facing down, leaning
/// towards +x.
fn tilted_down(degrees: f64) -> DVec3 {
    let phi = degrees.to_radians();
    DVec3::new(phi.sin(), 0.0, -phi.cos())
}

#[test]
fn gradient_matches_central_differences() {
    let floor = square_z(-5.0, 5.0, 0.0, true);
    let tilted_floor = square_facing(DVec3::ZERO, DVec3::new(0.2, -0.3, 1.0).normalize(), 10.0);
    let configurations = [
        (
            floor.clone(),
            square_facing(DVec3::new(0.3, 0.1, 2.0), tilted_down(30.0), 0.5),
        ),
        (
            floor.clone(),
            square_facing(DVec3::new(-0.5, 0.4, 1.0), tilted_down(70.0), 1.0),
        ),
        (
            tilted_floor.clone(),
            square_facing(DVec3::new(0.0, 0.0, 1.5), tilted_down(45.0), 0.8),
        ),
        // A lamp whose lower half is behind the receiver's plane: clipped.
        (
            floor,
            square_facing(DVec3::new(0.0, 0.0, 0.1), tilted_down(80.0), 1.0),
        ),
    ];
    let mut rng = Rng(7);
    let mut worst: f64 = 0.0;
    for (receiver, lamp) in configurations {
        let (_, _, field) = field(receiver, lamp);
        let (point, direction) = field.kink_line().unwrap();
        let mut tested = 0;
        for _ in 0..100_000 {
            if tested == 100 {
                break;
            }
            let p = DVec2::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
            // Lit, and away from the kink where B is not differentiable.
            let from_kink = direction.perp_dot(p - point);
            let (value, gradient) = field.value_and_gradient(p);
            if from_kink < 0.05 || value <= 0.0 {
                continue;
            }
            let delta = 1e-5;
            let du = (field.value(p + DVec2::X * delta) - field.value(p - DVec2::X * delta))
                / (2.0 * delta);
            let dv = (field.value(p + DVec2::Y * delta) - field.value(p - DVec2::Y * delta))
                / (2.0 * delta);
            let difference = (gradient - DVec2::new(du, dv)).length();
            let relative = difference / gradient.length();
            assert!(
                relative < 1e-5,
                "at {p}: {gradient} vs ({du}, {dv}), B = {value}"
            );
            worst = worst.max(relative);
            tested += 1;
        }
        assert_eq!(tested, 100, "too few lit points");
    }
    println!("worst relative gradient error vs central differences: {worst:.2e}");
}

#[test]
fn parallel_disc_matches_the_coaxial_formula_and_peaks_at_the_foot() {
    let (radius, height) = (0.5, 2.0);
    let centre = DVec3::new(0.3, -0.2, height);
    let (_, luminaire, field) = field(
        square_z(-5.0, 5.0, 0.0, true),
        disc_facing_down(64, radius, centre),
    );
    // The inscribed 64-gon's area is smaller than the disc's by 1 − sin(2π/64)/(2π/64) ≈ 1.6e-3.
    let angle = std::f64::consts::TAU / 64.0;
    let area_deficit = 1.0 - angle.sin() / angle;
    assert!(
        (luminaire.area / (std::f64::consts::PI * radius * radius) - (1.0 - area_deficit)).abs()
            < 1e-12
    );
    let scale = 0.5 * std::f64::consts::PI;
    assert!((field.scale() - scale).abs() < 1e-12);
    let frame = *field.frame();
    let foot = frame.to_plane(DVec3::new(centre.x, centre.y, 0.0));
    let mut worst: f64 = 0.0;
    for x in [0.0, 0.25, 0.5, 1.0, 2.0, 4.0] {
        for direction in [DVec2::X, DVec2::new(0.6, 0.8)] {
            let value = field.value(foot + direction * x);
            let reference = scale * coaxial_disc_form_factor(radius, height, x);
            let relative = (value / reference - 1.0).abs();
            assert!(
                relative < 1.5 * area_deficit,
                "x = {x}: {value} vs {reference}"
            );
            worst = worst.max(relative);
        }
    }
    let peak = field.maximum().unwrap();
    let offset = peak.distance(foot) / height;
    assert!(
        offset < 1e-6,
        "peak {peak} vs foot {foot}: {offset:.1e} of the height"
    );
    println!(
        "coaxial disc: worst relative error {worst:.2e} (area deficit {area_deficit:.2e}); peak off the foot by {offset:.1e} h"
    );
}

/// The maximum of `value` by nested grid searches: no gradient involved.
fn dense_maximum(field: &DirectField, mut centre: DVec2, mut half_width: f64) -> DVec2 {
    for _ in 0..8 {
        let mut best = (centre, field.value(centre));
        for i in -20..=20 {
            for j in -20..=20 {
                let p = centre + DVec2::new(i as f64, j as f64) * (half_width / 20.0);
                let value = field.value(p);
                if value > best.1 {
                    best = (p, value);
                }
            }
        }
        centre = best.0;
        half_width /= 8.0;
    }
    centre
}

#[test]
fn tilted_small_lamp_peaks_where_the_seed_says() {
    let (height, tilt, side) = (2.0, 30.0, 0.1);
    let centre = DVec3::new(0.2, 0.1, height);
    let (_, luminaire, field) = field(
        square_z(-5.0, 5.0, 0.0, true),
        square_facing(centre, tilted_down(tilt), side),
    );
    let frame = *field.frame();
    let peak = frame.to_world(field.maximum().unwrap());
    let dense = frame.to_world(dense_maximum(
        &field,
        frame.to_plane(DVec3::new(centre.x, centre.y, 0.0)),
        height,
    ));
    let against_dense = peak.distance(dense) / height;
    assert!(
        against_dense < 1e-4,
        "{peak} vs {dense}: {against_dense:.1e} h"
    );
    // Eq. 4.2: x* from the foot along +x; the lamp's finite size moves it by O((R/h)²) h.
    let seed = DVec3::new(
        centre.x + tilt_line_maximum(height, tilt.to_radians()).unwrap(),
        centre.y,
        0.0,
    );
    let size = luminaire.radius / height;
    let against_seed = peak.distance(seed) / height;
    assert!(
        against_seed < size * size,
        "{peak} vs eq. 4.2's {seed}: {against_seed:.1e} h"
    );
    println!(
        "tilted 30°: peak vs dense search {against_dense:.1e} h, vs eq. 4.2 {against_seed:.1e} h ((R/h)² = {:.1e})",
        size * size
    );
}

#[test]
fn kink_line_lies_on_both_planes_with_the_light_on_its_left() {
    for (degrees, receiver_normal) in [
        (30.0, DVec3::Z),
        (60.0, DVec3::new(0.2, -0.3, 1.0).normalize()),
        (100.0, DVec3::Z),
    ] {
        let lamp_normal = tilted_down(degrees);
        let centre = DVec3::new(0.4, -0.3, 1.5);
        let (_, luminaire, field) = field(
            square_facing(DVec3::ZERO, receiver_normal, 10.0),
            square_facing(centre, lamp_normal, 0.3),
        );
        let (point, direction) = field.kink_line().unwrap();
        assert!((direction.length() - 1.0).abs() < 1e-12);
        let frame = *field.frame();
        for t in [-2.0, 0.0, 3.0] {
            let world = frame.to_world(point + direction * t);
            assert!(
                frame.height(world).abs() < 1e-12,
                "off the receiver's plane"
            );
            let off_lamp = luminaire.normal.dot(world - luminaire.centre);
            assert!(
                off_lamp.abs() < 1e-12,
                "{degrees}°: {off_lamp} off the lamp's plane"
            );
        }
        let left = direction.perp();
        assert!(field.value(point + left * 0.1) > 0.0 && field.value(point - left * 0.1) == 0.0);
    }
    // Parallel planes: no kink.
    let (_, _, parallel) = field(
        square_z(-1.0, 1.0, 0.0, true),
        square_z(-0.1, 0.1, 1.0, false),
    );
    assert!(parallel.kink_line().is_none());
}

#[test]
fn lamps_that_cannot_light_the_receiver_give_no_field() {
    let mut b = SceneBuilder::default();
    let white = b.material("white", 0.5, 0.0);
    let light = b.material("light", 0.0, 1.0);
    b.polygon("floor", white, square_z(-1.0, 1.0, 0.0, true));
    b.polygon("under the floor", light, square_z(-0.1, 0.1, -1.0, true));
    b.polygon("facing up", light, square_z(-0.1, 0.1, 1.0, true));
    b.polygon("facing down", light, square_z(-0.1, 0.1, 2.0, false));
    let scene = b.scene;
    let lamps = area_lights(&scene);
    assert_eq!(lamps.len(), 3);
    assert!(DirectField::new(&scene, SurfaceId::new(0), &lamps[0]).is_none());
    assert!(DirectField::new(&scene, SurfaceId::new(0), &lamps[1]).is_none());
    assert!(
        DirectField::new(&scene, SurfaceId::new(7), &lamps[2]).is_none(),
        "no such receiver"
    );
    assert!(
        DirectField::new(&scene, SurfaceId::new(3), &lamps[2]).is_none(),
        "the lamp itself"
    );
    let field = DirectField::new(&scene, SurfaceId::new(0), &lamps[2]).unwrap();
    // Non-finite points: zero, never NaN.
    for p in [DVec2::NAN, DVec2::new(f64::INFINITY, 0.0)] {
        assert_eq!(field.value_and_gradient(p), (0.0, DVec2::ZERO));
    }
    // A luminaire with nothing in it, or a surface index out of range.
    let mut broken = lamps[2].clone();
    broken.surfaces = vec![SurfaceId::new(99)];
    assert!(DirectField::new(&scene, SurfaceId::new(0), &broken).is_none());
    broken.surfaces.clear();
    assert!(DirectField::new(&scene, SurfaceId::new(0), &broken).is_none());
}

#[test]
fn black_receiver_has_a_zero_field_but_a_peak() {
    let mut b = SceneBuilder::default();
    let black = b.material("black", 0.0, 0.0);
    let light = b.material("light", 0.0, 1.0);
    b.polygon("floor", black, square_z(-1.0, 1.0, 0.0, true));
    b.polygon("lamp", light, square_z(-0.1, 0.1, 1.0, false));
    let scene = b.scene;
    let field = DirectField::new(&scene, SurfaceId::new(0), &area_lights(&scene)[0]).unwrap();
    assert_eq!(field.value(DVec2::ZERO), 0.0);
    let peak = field.frame().to_world(field.maximum().unwrap());
    assert!(peak.length() < 1e-9, "{peak}");
}
