//! The shooter's gathers against closed forms: a clear receiver's exact
//! factor, a near stratum's field weighted by the kernel, and the light at
//! the foot of an object standing on the shooting patch.

use glam::DVec3;

use super::*;
use crate::mesh::Cell;
use crate::radiometry::polygon_form_factor;
use crate::scene::{Material, Scene, ShadowCache, SurfaceId, Visibility};
use crate::solver::light::patch_field::{FieldElement, PatchField};
use crate::solver::settings::FormFactorKernel;

/// A 1 m square lamp 3 m over a 6 m floor, facing it: an empty scene,
/// so every ray is unblocked. From the floor its strata are far
/// (`NEAR_FIELD`), and the samples sum Wallace's disc terms.
fn lamp_over_floor() -> (Scene, Shooter) {
    let mut scene = Scene::new();
    let grey = scene
        .add_material(Material::diffuse("grey", Rgb::splat(0.5)))
        .unwrap();
    let at = DVec3::new;
    scene
        .add_polygon(
            "floor",
            grey,
            &[
                at(-2.0, 0.0, -2.0),
                at(-2.0, 0.0, 2.0),
                at(2.0, 0.0, 2.0),
                at(2.0, 0.0, -2.0),
            ],
        )
        .unwrap();
    let lamp = [
        at(-0.5, 3.0, -0.5),
        at(0.5, 3.0, -0.5),
        at(0.5, 3.0, 0.5),
        at(-0.5, 3.0, 0.5),
    ];
    scene.add_polygon("lamp", grey, &lamp).unwrap();
    let cell = Cell::quad(lamp[0], lamp[1], lamp[2], lamp[3]);
    let shooter = Shooter::new(
        cell,
        DVec3::NEG_Y,
        SurfaceId::new(1),
        8,
        16,
        ShotRadiosity::Uniform(Rgb::splat(2.0)),
    );
    (scene, shooter)
}

fn gather(
    shooter: &Shooter,
    visibility: &Visibility,
    x: DVec3,
    clear: bool,
    key: u64,
    kernel: FormFactorKernel,
) -> Gathered {
    let receiver = Receiver {
        position: x,
        normal: DVec3::Y,
        surface: SurfaceId::new(0),
        key,
        clear,
        occluders: None,
    };
    let mut cache = ShadowCache::default();
    shooter.gather(&receiver, 3.0, 1, kernel, visibility, &mut cache)
}

/// A receiver known to see all of a uniform shooter takes W times
/// Lambert's exact factor, without samples; the samples of one that
/// casts its rays estimate the same value. Wallace's kernel keeps its
/// samples' sum, rays or none.
#[test]
fn a_clear_receiver_of_a_uniform_shot_takes_the_exact_factor() {
    let (scene, shooter) = lamp_over_floor();
    let visibility = Visibility::new(&scene);
    for x in [
        DVec3::ZERO,
        DVec3::new(0.7, 0.0, 0.2),
        DVec3::new(1.9, 0.0, -1.5),
    ] {
        let exact = 2.0 * polygon_form_factor(x, DVec3::Y, shooter.cell.polygon());
        let clear = gather(&shooter, &visibility, x, true, 0, FormFactorKernel::Mixed);
        assert_eq!(clear.irradiance.g, exact, "at {x}");
        assert_eq!((clear.rays, clear.blocked), (0, 0));
        assert!(clear.known_visible >= 64);
        let trials = 64;
        let sampled: f64 = (0..trials)
            .map(|key| {
                let g = gather(
                    &shooter,
                    &visibility,
                    x,
                    false,
                    key,
                    FormFactorKernel::Mixed,
                );
                assert!(g.rays >= 64 && g.blocked == 0);
                g.irradiance.g
            })
            .sum::<f64>()
            / f64::from(trials as u32);
        assert!(
            (sampled / exact - 1.0).abs() < 0.01,
            "{sampled} against {exact} at {x}"
        );
        let wallace = |clear| {
            gather(
                &shooter,
                &visibility,
                x,
                clear,
                3,
                FormFactorKernel::Wallace,
            )
            .irradiance
        };
        assert_eq!(wallace(true), wallace(false));
    }
}

/// A scene of grey polygons, in order (surface k is polygon k), and
/// its shadow-ray structure.
fn grey_scene(polygons: &[&[DVec3]]) -> (Scene, Visibility) {
    let mut scene = Scene::new();
    let grey = scene
        .add_material(Material::diffuse("grey", Rgb::splat(0.5)))
        .unwrap();
    for (k, polygon) in polygons.iter().enumerate() {
        scene.add_polygon(&format!("p{k}"), grey, polygon).unwrap();
    }
    let visibility = Visibility::new(&scene);
    (scene, visibility)
}

/// A receiver at x with unit `normal` on `surface`, jitter key 0.
fn receiver_at(x: DVec3, normal: DVec3, surface: SurfaceId) -> Receiver<'static> {
    Receiver {
        position: x,
        normal,
        surface,
        key: 0,
        clear: false,
        occluders: None,
    }
}

/// The red irradiance one gather of a shooter gives `receiver`.
fn gather_once(shooter: &Shooter, visibility: &Visibility, receiver: &Receiver) -> f64 {
    let mut cache = ShadowCache::default();
    shooter
        .gather(
            receiver,
            3.0,
            7,
            FormFactorKernel::Mixed,
            visibility,
            &mut cache,
        )
        .irradiance
        .r
}

/// [`gather_once`] averaged over `trials` jitter keys.
fn mean_gather(shooter: &Shooter, visibility: &Visibility, at: Receiver, trials: u64) -> f64 {
    let total: f64 = (0..trials)
        .map(|key| gather_once(shooter, visibility, &Receiver { key, ..at }))
        .sum();
    total / trials as f64
}

/// A floor patch whose unshot radiosity rises fourfold across it, shot
/// with one stratum to points of a ceiling 1.2 above: on average over
/// the jitter, each point receives the integral of ΔB times the point
/// kernel over the patch (checked by a 400 × 400 midpoint sum). Read as
/// ΔB at the sample times the patch's exact factor, a near stratum
/// weighted ΔB evenly: 17 % too much beside the patch's dark edge.
#[test]
fn a_near_stratum_shoots_its_field_weighted_by_the_kernel() {
    let at = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    let floor = [
        at(-3.0, 0.0, -3.0),
        at(-3.0, 0.0, 3.0),
        at(3.0, 0.0, 3.0),
        at(3.0, 0.0, -3.0),
    ];
    let ceiling: Vec<DVec3> = floor.iter().rev().map(|p| *p + at(0.0, 1.2, 0.0)).collect();
    let (scene, visibility) = grey_scene(&[&floor, &ceiling]);
    let (floor, ceiling) = (SurfaceId::new(0), SurfaceId::new(1));
    let up = scene.surface(floor).normal();
    let down = scene.surface(ceiling).normal();

    // The patch [0, 1] × [0, 1] of the floor, 2 × 2 elements, ΔB = 1 + 3x.
    let p = |x: f64, z: f64| at(x, 0.0, z);
    let cell = Cell::quad(p(0.0, 0.0), p(0.0, 1.0), p(1.0, 1.0), p(1.0, 0.0));
    let delta = |q: DVec3| 1.0 + 3.0 * q.x;
    let mut elements = Vec::new();
    for (x0, z0) in [(0.0, 0.0), (0.5, 0.0), (0.0, 0.5), (0.5, 0.5)] {
        let c = Cell::quad(
            p(x0, z0),
            p(x0, z0 + 0.5),
            p(x0 + 0.5, z0 + 0.5),
            p(x0 + 0.5, z0),
        );
        elements.push(FieldElement::new(
            c,
            c.corners.map(|q| Rgb::splat(delta(q))),
        ));
    }
    let field = PatchField::new(elements, Rgb::splat(2.5), up);
    let shooter = Shooter::new(cell, up, floor, 1, 1, ShotRadiosity::Field(field));
    for x in [at(0.5, 1.2, 0.5), at(-0.5, 1.2, 0.5), at(2.0, 1.2, 0.2)] {
        let m = 400;
        let mut exact = 0.0;
        for j in 0..m {
            for i in 0..m {
                let y = cell.point((i as f64 + 0.5) / m as f64, (j as f64 + 0.5) / m as f64);
                let d = y - x;
                let r2 = d.length_squared();
                exact += delta(y) * down.dot(d) * -up.dot(d) / (std::f64::consts::PI * r2 * r2);
            }
        }
        exact /= (m * m) as f64;
        let mean = mean_gather(&shooter, &visibility, receiver_at(x, down, ceiling), 20_000);
        let error = mean / exact - 1.0;
        assert!(
            error.abs() < 0.01,
            "at {x}: {mean} against {exact} ({error:+.4})"
        );
    }
    // A millimetre over the patch, where the point kernel's 1/r² spike
    // (A k(y) > 1 within about 2 cm) catches one jittered sample in
    // five hundred: no gather may exceed the brightest ΔB (4) times the
    // patch's factor (under 1). With the point factor uncapped, one
    // gave 66.
    let x = at(0.5, 0.001, 0.5);
    let brightest = (0..20_000)
        .map(|key| {
            gather_once(
                &shooter,
                &visibility,
                &Receiver {
                    key,
                    ..receiver_at(x, down, ceiling)
                },
            )
        })
        .fold(0.0, f64::max);
    assert!(brightest <= 4.0, "a gather gave {brightest}");
}

/// A block stands on a floor patch whose light is even: the elements
/// cover the patch but for the block's footprint. A receiver on the
/// block's side, 1 cm above the floor, sees mostly the floor within a
/// few centimetres of the block: Lambert's factor of the floor in front
/// of the side, times the radiosity. The patch's sampled cells are an
/// eighth of it wide, and the column beside the block has its centres
/// under it (the block's side at x = 0.55, the centres at 0.5625):
/// read there, that column shot nothing, and the receiver got 0.55 of
/// its light.
#[test]
fn a_receiver_at_the_foot_of_an_object_standing_on_the_patch_sees_its_light() {
    let at = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    let floor = [
        at(0.0, 0.0, 0.0),
        at(0.0, 0.0, 1.0),
        at(1.0, 0.0, 1.0),
        at(1.0, 0.0, 0.0),
    ];
    // The block's side facing −x, over x = 0.55, z in [0.25, 0.75].
    let side = [
        at(0.55, 0.0, 0.25),
        at(0.55, 0.0, 0.75),
        at(0.55, 0.5, 0.75),
        at(0.55, 0.5, 0.25),
    ];
    let (scene, visibility) = grey_scene(&[&floor, &side]);
    let (floor, side) = (SurfaceId::new(0), SurfaceId::new(1));
    let up = scene.surface(floor).normal();
    let out = scene.surface(side).normal();
    assert!(out.x < -0.99, "{out}");

    let p = |x: f64, z: f64| at(x, 0.0, z);
    let cell = Cell::quad(p(0.0, 0.0), p(0.0, 1.0), p(1.0, 1.0), p(1.0, 0.0));
    let (xs, zs) = ([0.0, 0.275, 0.55, 0.775, 1.0], [0.0, 0.25, 0.5, 0.75, 1.0]);
    let mut elements = Vec::new();
    let mut power = 0.0;
    for i in 0..4 {
        for j in 0..4 {
            let under_block = i >= 2 && (1..3).contains(&j);
            if under_block {
                continue;
            }
            let c = Cell::quad(
                p(xs[i], zs[j]),
                p(xs[i], zs[j + 1]),
                p(xs[i + 1], zs[j + 1]),
                p(xs[i + 1], zs[j]),
            );
            power += c.area;
            elements.push(FieldElement::new(c, [Rgb::splat(1.0); 4]));
        }
    }
    let field = PatchField::new(elements, Rgb::splat(power), up);
    let shooter = Shooter::new(cell, up, floor, 1, 1, ShotRadiosity::Field(field));
    let x = at(0.55, 0.01, 0.5);
    let mean = mean_gather(&shooter, &visibility, receiver_at(x, out, side), 2000);
    let in_front = [p(0.0, 0.0), p(0.0, 1.0), p(0.55, 1.0), p(0.55, 0.0)];
    let exact = polygon_form_factor(x, out, &in_front);
    let error = mean / exact - 1.0;
    assert!(error.abs() < 0.02, "{mean} against {exact} ({error:+.4})");
}
