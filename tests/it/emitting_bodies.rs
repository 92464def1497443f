//! Emitting bodies: a lamp modelled as faces on many planes (a tessellated
//! globe, a lens) is one luminaire whose light is that of a diffuse body.
//!
//! The reference is independent of the tessellation's details: a convex
//! body of surface area S and uniform exitance M sends, on average over
//! directions, the intensity (M/π)(S/4) (Cauchy: the mean projected area of
//! a convex body is a quarter of its area), and a Lambertian sphere lights
//! a point at distance d whose plane does not cut it exactly as a point
//! source would: E = M R² cos θ / d² (Lambert). A finely tessellated sphere
//! is such a sphere with R² = S/(4π), to the anisotropy of its facets.

use std::f64::consts::PI;

use glam::DVec3;
use isorad::lighting::area_lights;
use isorad::scene::{Material, Scene, Visibility};
use isorad::{Ambient, Rgb, Settings, Solver, phase::silent};

use crate::support::gather_at;

/// Emitted radiance of the globes, W/(m²·sr) per channel.
const RADIANCE: f64 = 100.0;

/// A UV sphere of `segments` around and `segments / 2` rings, every
/// triangle its own polygon, as an exporter writes one.
fn globe_triangles(centre: DVec3, radius: f64, segments: usize) -> Vec<Vec<DVec3>> {
    let rings = segments / 2;
    let point = |i: usize, j: usize| {
        let (polar, azimuth) = (
            PI * i as f64 / rings as f64,
            2.0 * PI * j as f64 / segments as f64,
        );
        centre
            + DVec3::new(
                polar.sin() * azimuth.cos(),
                polar.cos(),
                polar.sin() * azimuth.sin(),
            ) * radius
    };
    let mut triangles = Vec::new();
    for i in 0..rings {
        for j in 0..segments {
            let (p00, p01, p10, p11) = (
                point(i, j),
                point(i, j + 1),
                point(i + 1, j),
                point(i + 1, j + 1),
            );
            if i > 0 {
                triangles.push(vec![p00, p01, p11]);
            }
            if i + 1 < rings {
                triangles.push(vec![p00, p11, p10]);
            }
        }
    }
    triangles
}

/// A 40 m grey floor facing up and a globe of radius 0.1 m centred 0.3 m
/// above it, its triangles joined into one luminaire.
fn globe_over_floor(segments: usize) -> Scene {
    let mut scene = Scene::new();
    let grey = scene
        .add_material(Material::diffuse("grey", Rgb::splat(0.5)))
        .unwrap();
    let lamp = scene
        .add_material(Material::emitter("lamp", Rgb::splat(RADIANCE)))
        .unwrap();
    let h = 20.0;
    scene
        .add_polygon(
            "floor",
            grey,
            &[
                DVec3::new(-h, 0.0, -h),
                DVec3::new(-h, 0.0, h),
                DVec3::new(h, 0.0, h),
                DVec3::new(h, 0.0, -h),
            ],
        )
        .unwrap();
    for triangle in globe_triangles(DVec3::new(0.0, 0.3, 0.0), 0.1, segments) {
        scene.add_polygon("globe", lamp, &triangle).unwrap();
    }
    assert_eq!(scene.join_emitting_bodies(), 1);
    scene
}

/// E = M S/(4π d²) cos θ at floor point (x, 0, 0): the sphere's law.
fn sphere_law(scene: &Scene, x: f64) -> f64 {
    let body = scene.luminaires[0].body.as_ref().unwrap();
    let d = DVec3::new(0.0, 0.3, 0.0) - DVec3::new(x, 0.0, 0.0);
    PI * RADIANCE * body.area / (4.0 * PI * d.length_squared()) * (d.y / d.length())
}

#[test]
fn a_tessellated_globe_is_one_luminaire_with_the_power_of_its_faces() {
    for segments in [32, 64] {
        let scene = globe_over_floor(segments);
        assert!(
            area_lights(&scene).is_empty(),
            "its faces are no area lights"
        );
        let luminaire = &scene.luminaires[0];
        let body = luminaire.body.as_ref().unwrap();
        assert_eq!(body.face_count(), segments * (segments - 2));
        // Φ = M Σ A_i, here from the web the faces' projected area makes.
        let exact = PI * RADIANCE * body.area;
        let ratio = luminaire.power().g / exact;
        assert!((ratio - 1.0).abs() < 2e-3, "{segments}: power ×{ratio}");
        // A second call finds nothing new.
        let mut again = scene.clone();
        assert_eq!(again.join_emitting_bodies(), 0);
    }
}

#[test]
fn a_globe_lights_the_floor_as_a_lambertian_sphere_near_and_far() {
    // 32 segments: 960 faces, the near field face by face; 64: 4,032
    // faces, the near field from area-stratified points.
    for segments in [32, 64] {
        let scene = globe_over_floor(segments);
        let visibility = Visibility::new(&scene);
        let luminaire = &scene.luminaires[0];
        let floor = isorad::scene::SurfaceId::new(0);
        // From under the globe (3 radii) through the blend (8 to 12
        // radii) to far away (45 radii).
        for x in [0.0, 0.2, 0.5, 0.8, 1.0, 1.2, 2.0, 4.5] {
            let point = DVec3::new(x, 0.0, 0.0);
            let e = luminaire.irradiance_at(point, DVec3::Y, floor, &visibility);
            let law = sphere_law(&scene, x);
            let error = e.g / law - 1.0;
            assert!(
                error.abs() < 0.01,
                "{segments} segments, x = {x}: ×{}",
                e.g / law
            );
            // Nothing blocks: every facing point of the globe is seen,
            // though the globe hides its own back.
            let share = luminaire.visible_share(point, DVec3::Y, floor, &visibility);
            assert_eq!(share, 1.0, "x = {x}");
        }
    }
}

#[test]
fn a_solved_globe_lights_its_floor_and_keeps_its_ledger() {
    let scene = globe_over_floor(32);
    let mut solver = Solver::new(scene, Settings::default()).unwrap();
    solver.run();
    // One shot for the globe, none for its 960 faces' patches.
    let balance = solver.energy_balance();
    let total = balance.absorbed + balance.unshot + balance.escaped;
    let imbalance = ((total - balance.emitted).abs() / balance.emitted).max_element();
    assert!(imbalance < 1e-9, "ledger imbalance {imbalance}");
    let body_power = PI * RADIANCE * solver.scene().luminaires[0].body.as_ref().unwrap().area;
    let ratio = balance.emitted.g / body_power;
    assert!(
        (ratio - 1.0).abs() < 2e-3,
        "emitted ×{ratio} of the faces' power"
    );
    // The floor sees only the globe (black): its light is the sphere's law.
    let solution = solver.solution(Ambient::Everywhere, &silent);
    for x in [0.0, 0.5, 1.5, 3.0] {
        let probe = gather_at(&solution, DVec3::new(x, 0.0, 0.1), None);
        let law = sphere_law(solver.scene(), (x * x + 0.01).sqrt());
        let error = probe.irradiance.g / law - 1.0;
        assert!(
            error.abs() < 0.015,
            "x = {x}: ×{}",
            probe.irradiance.g / law
        );
    }
}

#[test]
fn a_plate_between_globe_and_floor_casts_its_shadow() {
    let mut scene = globe_over_floor(32);
    let black = scene
        .add_material(Material::diffuse("black", Rgb::ZERO))
        .unwrap();
    // A plate 0.15 m up, facing down, covering x < 0.
    let (y, h) = (0.15, 20.0);
    scene
        .add_polygon(
            "plate",
            black,
            &[
                DVec3::new(-h, y, -h),
                DVec3::new(0.0, y, -h),
                DVec3::new(0.0, y, h),
                DVec3::new(-h, y, h),
            ],
        )
        .unwrap();
    let visibility = Visibility::new(&scene);
    let luminaire = &scene.luminaires[0];
    let floor = isorad::scene::SurfaceId::new(0);
    let share =
        |x: f64| luminaire.visible_share(DVec3::new(x, 0.0, 0.0), DVec3::Y, floor, &visibility);
    // Umbra, open, and a penumbra between: the plate's edge, seen from
    // x, hides the globe's points whose x is below −x (1 − 0.3/0.15 = −1).
    assert_eq!(share(-0.5), 0.0);
    assert_eq!(share(0.5), 1.0);
    let half = share(0.0);
    assert!((0.2..0.8).contains(&half), "at the edge: {half}");
}

#[test]
fn an_obj_lamp_of_many_planes_loads_as_one_luminaire() {
    // An octahedron lamp (8 faces on 8 planes) over a floor.
    let dir = tempfile::tempdir().unwrap();
    let mut obj = String::from(
        "mtllib s.mtl\nusemtl grey\nv -4 0 -4\nv -4 0 4\nv 4 0 4\nv 4 0 -4\nf 1 2 3 4\nusemtl lamp\n",
    );
    for v in [
        [0.1, 1.0, 0.0],
        [-0.1, 1.0, 0.0],
        [0.0, 1.1, 0.0],
        [0.0, 0.9, 0.0],
        [0.0, 1.0, 0.1],
        [0.0, 1.0, -0.1],
    ] {
        obj.push_str(&format!("v {} {} {}\n", v[0], v[1], v[2]));
    }
    // Vertices 5..10: +x, −x, +y, −y, +z, −z; faces counter-clockwise
    // seen from outside.
    for f in [
        [5, 7, 9],
        [5, 10, 7],
        [5, 9, 8],
        [5, 8, 10],
        [6, 9, 7],
        [6, 7, 10],
        [6, 8, 9],
        [6, 10, 8],
    ] {
        obj.push_str(&format!("f {} {} {}\n", f[0], f[1], f[2]));
    }
    std::fs::write(dir.path().join("s.obj"), obj).unwrap();
    std::fs::write(
        dir.path().join("s.mtl"),
        "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 50 50 50\n",
    )
    .unwrap();
    let scene = isorad::load_scene(dir.path().join("s.obj").to_str().unwrap())
        .unwrap()
        .scene;
    assert_eq!(scene.luminaires.len(), 1);
    let body = scene.luminaires[0].body.as_ref().unwrap();
    assert_eq!(body.face_count(), 8);
    // Every face's normal points out: the octahedron's projected area
    // towards straight down is that of its four lower faces, a square of
    // diagonal 0.2: 0.02 m².
    let down = body.projected_area(DVec3::NEG_Y);
    assert!((down - 0.02).abs() < 1e-8, "{down}");
    assert!(area_lights(&scene).is_empty());
}
