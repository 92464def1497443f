//! Scenes the solver's unit tests share.

use glam::DVec3;

use crate::rgb::Rgb;
use crate::scene::surface::newell_normal;
use crate::scene::{Material, Scene, Surface};

/// Two closed 4 × 3 × 4 m rooms 5 m apart, each with a lamp under its
/// ceiling and a block on its floor, every face towards the room; the
/// second room's lamp twice as bright as the first's.
pub(crate) fn two_closed_rooms() -> Scene {
    let mut scene = Scene::default();
    let materials = [
        ("wall", 0.6, 0.0),
        ("lamp", 0.0, 10.0),
        ("bright", 0.0, 20.0),
    ];
    for (name, reflectance, radiance) in materials {
        scene.materials.push(Material {
            name: name.into(),
            reflectance: Rgb::splat(reflectance),
            emitted_radiance: Rgb::splat(radiance),
            transmittance: 0.0,
        });
    }
    // A quad of a box's face, turned to face `towards`.
    let mut add = |material: usize, mut quad: Vec<DVec3>, towards: DVec3| {
        let centre = quad.iter().copied().sum::<DVec3>() / 4.0;
        if newell_normal(&quad).dot(towards - centre) < 0.0 {
            quad.reverse();
        }
        scene
            .surfaces
            .push(Surface::new("face", material, quad).expect("a valid quad"));
    };
    // The faces of the box [lo, hi], each facing `inwards` or out.
    let box_faces = |lo: DVec3, hi: DVec3| {
        (0..3).flat_map(move |axis| {
            [0.0, 1.0].map(move |side| {
                let corner = |s: f64, t: f64| {
                    let mut w = [0.0; 3];
                    w[axis] = side;
                    w[(axis + 1) % 3] = s;
                    w[(axis + 2) % 3] = t;
                    lo + (hi - lo) * DVec3::from_array(w)
                };
                vec![
                    corner(0.0, 0.0),
                    corner(1.0, 0.0),
                    corner(1.0, 1.0),
                    corner(0.0, 1.0),
                ]
            })
        })
    };
    for (x, lamp) in [(0.0, 1), (5.0, 2)] {
        let (lo, hi) = (DVec3::new(x, 0.0, 0.0), DVec3::new(x + 4.0, 3.0, 4.0));
        for quad in box_faces(lo, hi) {
            add(0, quad, (lo + hi) / 2.0);
        }
        let (block_lo, block_hi) = (
            lo + DVec3::new(1.0, 0.0, 1.0),
            lo + DVec3::new(2.0, 0.8, 2.0),
        );
        // The block's faces but its bottom (the third), facing out.
        let centre = (block_lo + block_hi) / 2.0;
        for (k, quad) in box_faces(block_lo, block_hi).enumerate() {
            let outwards = quad.iter().copied().sum::<DVec3>() / 2.0 - centre;
            if k != 2 {
                add(0, quad, outwards);
            }
        }
        let corners = [(1.7, 1.7), (2.3, 1.7), (2.3, 2.3), (1.7, 2.3)]
            .map(|(u, w)| lo + DVec3::new(u, 2.99, w))
            .to_vec();
        add(lamp, corners, lo + DVec3::new(2.0, 0.0, 2.0));
    }
    scene
}
