//! Per-call cost of isorad's form-factor kernels: Wallace's disc kernel,
//! Lambert's exact polygon factor (a quad and a 64-gon) and the factor with
//! Arvo's gradient.

use std::f64::consts::TAU;
use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::DVec3;
use isorad::radiometry::{
    disc_form_factor, polygon_form_factor, polygon_form_factor_with_gradient,
};

/// A regular `sides`-gon of radius 0.5 at height 1, facing down.
fn ceiling_polygon(sides: usize) -> Vec<DVec3> {
    (0..sides)
        .map(|i| {
            let angle = -TAU * i as f64 / sides as f64;
            DVec3::new(0.5 * angle.cos(), 1.0, 0.5 * angle.sin())
        })
        .collect()
}

fn kernels(c: &mut Criterion) {
    let mut group = c.benchmark_group("kernels");
    group.sample_size(50);
    // A receiver point off-centre on the floor, facing up.
    let point = DVec3::new(0.3, 0.0, -0.2);
    let normal = DVec3::Y;
    group.bench_function("disc_form_factor", |b| {
        b.iter(|| {
            disc_form_factor(
                black_box(0.01),
                black_box(0.8),
                black_box(0.7),
                black_box(1.3),
            )
        })
    });
    for (name, sides) in [("quad", 4), ("64-gon", 64)] {
        let polygon = ceiling_polygon(sides);
        group.bench_function(format!("polygon_form_factor/{name}"), |b| {
            b.iter(|| polygon_form_factor(black_box(point), black_box(normal), black_box(&polygon)))
        });
        group.bench_function(format!("polygon_form_factor_with_gradient/{name}"), |b| {
            b.iter(|| {
                polygon_form_factor_with_gradient(
                    black_box(point),
                    black_box(normal),
                    black_box(&polygon),
                )
            })
        });
    }
    group.finish();
}

criterion_group!(benches, kernels);
criterion_main!(benches);
