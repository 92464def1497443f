//! Integration tests of the rasterizer, tone mapping and image files,
//! against values computed independently here (ray casting, the sRGB curve).

use std::path::Path;

use glam::DVec3;
use isorad::{
    Camera, Error, Image, RenderSettings, Rgb, ToneMap,
    render::{ShadedTriangle, rasterize, read_exr},
    write_exr, write_png,
};

/// A camera of the given size looking from `position` at `look_at`, y up.
fn camera(position: DVec3, look_at: DVec3, width: u32, height: u32, vfov_deg: f64) -> Camera {
    Camera {
        position,
        look_at,
        up: DVec3::Y,
        vfov_deg,
        width,
        height,
    }
}

/// The direction of the ray through image point (u, v), per DESIGN.md:
/// forward + (2u − 1)·tan(vfov/2)·(W/H)·right + (1 − 2v)·tan(vfov/2)·up.
fn ray_direction(camera: &Camera, u: f64, v: f64) -> DVec3 {
    let frame = camera.frame();
    let tan_half = (0.5 * camera.vfov_deg.to_radians()).tan();
    let aspect = f64::from(camera.width) / f64::from(camera.height);
    frame.forward
        + (2.0 * u - 1.0) * tan_half * aspect * frame.right
        + (1.0 - 2.0 * v) * tan_half * frame.up
}

/// Where the ray through the centre of pixel (i, j) meets the plane of
/// `positions`: the hit point and its barycentric coordinates, or `None`
/// when the plane is behind the eye or parallel to the ray.
fn pixel_hit(camera: &Camera, positions: &[DVec3; 3], i: u32, j: u32) -> Option<(DVec3, [f64; 3])> {
    let u = (f64::from(i) + 0.5) / f64::from(camera.width);
    let v = (f64::from(j) + 0.5) / f64::from(camera.height);
    let direction = ray_direction(camera, u, v);
    let [p0, p1, p2] = *positions;
    let normal = (p1 - p0).cross(p2 - p0);
    let t = normal.dot(p0 - camera.position) / normal.dot(direction);
    if !t.is_finite() || t <= 0.0 {
        return None;
    }
    let hit = camera.position + t * direction;
    // Barycentrics by sub-triangle areas along the normal.
    let area = normal.length_squared();
    let b0 = (p1 - hit).cross(p2 - hit).dot(normal) / area;
    let b1 = (p2 - hit).cross(p0 - hit).dot(normal) / area;
    Some((hit, [b0, b1, 1.0 - b0 - b1]))
}

/// `positions` reordered if needed so that the front faces `eye`.
fn facing(positions: [DVec3; 3], eye: DVec3) -> [DVec3; 3] {
    let [p0, p1, p2] = positions;
    if (p1 - p0).cross(p2 - p0).dot(eye - p0) > 0.0 {
        positions
    } else {
        [p0, p2, p1]
    }
}

/// A triangle of constant radiance.
fn flat(positions: [DVec3; 3], radiance: Rgb) -> ShadedTriangle {
    ShadedTriangle {
        positions,
        radiance: [radiance; 3],
    }
}

fn as_rgb(pixel: [f32; 3]) -> Rgb {
    Rgb::new(
        f64::from(pixel[0]),
        f64::from(pixel[1]),
        f64::from(pixel[2]),
    )
}

/// A linear radiance field L(x) = A x + d, one row of A per channel.
struct LinearField {
    gradient: [DVec3; 3],
    offset: Rgb,
}

impl LinearField {
    fn at(&self, x: DVec3) -> Rgb {
        Rgb::new(
            self.gradient[0].dot(x),
            self.gradient[1].dot(x),
            self.gradient[2].dot(x),
        ) + self.offset
    }

    fn shade(&self, positions: [DVec3; 3]) -> ShadedTriangle {
        ShadedTriangle {
            positions,
            radiance: positions.map(|p| self.at(p)),
        }
    }
}

fn field() -> LinearField {
    LinearField {
        gradient: [
            DVec3::new(0.3, -0.2, 0.5),
            DVec3::new(-0.1, 0.4, 0.2),
            DVec3::new(0.05, 0.05, -0.3),
        ],
        offset: Rgb::new(2.0, 3.0, 4.0),
    }
}

fn assert_close(got: Rgb, expected: Rgb, relative: f64, what: &str) {
    let error = (got - expected).abs().max_element();
    assert!(
        error <= relative * expected.abs().max_element(),
        "{what}: got {got}, expected {expected}"
    );
}

/// Checks every pixel whose centre lies well inside `positions` against
/// `field` at the ray's hit point; returns how many were checked and the
/// largest relative error that affine screen-space interpolation would make.
fn check_linear_field(
    camera: &Camera,
    image: &Image,
    positions: [DVec3; 3],
    field: &LinearField,
) -> (usize, f64) {
    let project = |p: DVec3| {
        // Pixel coordinates of a point in front of the camera.
        let frame = camera.frame();
        let d = p - camera.position;
        let tan_half = (0.5 * camera.vfov_deg.to_radians()).tan();
        let aspect = f64::from(camera.width) / f64::from(camera.height);
        let x = d.dot(frame.right) / d.dot(frame.forward) / (tan_half * aspect);
        let y = d.dot(frame.up) / d.dot(frame.forward) / tan_half;
        (
            0.5 * (x + 1.0) * f64::from(camera.width),
            0.5 * (1.0 - y) * f64::from(camera.height),
        )
    };
    let screen = positions.map(project);
    let mut checked = 0;
    let mut affine_error: f64 = 0.0;
    for j in 0..camera.height {
        for i in 0..camera.width {
            let Some((hit, b)) = pixel_hit(camera, &positions, i, j) else {
                continue;
            };
            if b.iter().any(|&b| b < 1e-9) {
                continue;
            }
            let expected = field.at(hit);
            assert_close(
                as_rgb(image.pixel(i, j)),
                expected,
                1e-5,
                &format!("pixel ({i}, {j})"),
            );
            checked += 1;
            // What affine (screen-space) Gouraud would give at this centre.
            let (px, py) = (f64::from(i) + 0.5, f64::from(j) + 0.5);
            let edge =
                |a: (f64, f64), c: (f64, f64)| (c.0 - a.0) * (py - a.1) - (c.1 - a.1) * (px - a.0);
            let w = [
                edge(screen[1], screen[2]),
                edge(screen[2], screen[0]),
                edge(screen[0], screen[1]),
            ];
            let sum = w[0] + w[1] + w[2];
            let affine = (0..3).fold(Rgb::ZERO, |l, k| l + field.at(positions[k]) * (w[k] / sum));
            affine_error = affine_error
                .max((affine - expected).abs().max_element() / expected.abs().max_element());
        }
    }
    (checked, affine_error)
}

#[test]
fn linear_radiance_is_interpolated_perspective_correctly() {
    let camera = camera(
        DVec3::new(0.3, 0.5, -2.0),
        DVec3::new(0.0, 0.0, 3.0),
        64,
        48,
        60.0,
    );
    // A triangle tilted steeply in depth: from 0.5 to 12 units away.
    let positions = facing(
        [
            DVec3::new(-1.5, -1.2, -1.0),
            DVec3::new(3.0, -0.5, 10.0),
            DVec3::new(-0.5, 2.5, 6.0),
        ],
        camera.position,
    );
    let field = field();
    let background = Rgb::new(0.25, 0.5, 0.75);
    let settings = RenderSettings::preview().with_background(background);
    let image = rasterize(&[field.shade(positions)], &camera, &settings);
    let (checked, affine_error) = check_linear_field(&camera, &image, positions, &field);
    assert!(checked > 500, "only {checked} pixels inside");
    // The test discriminates: affine interpolation is off by far more than 1e-5.
    assert!(
        affine_error > 1e-2,
        "affine interpolation error only {affine_error}"
    );
    // Pixel centres clearly outside show the background exactly.
    for j in 0..camera.height {
        for i in 0..camera.width {
            let outside = pixel_hit(&camera, &positions, i, j)
                .is_none_or(|(_, b)| b.iter().any(|&b| b < -1e-9));
            if outside {
                assert_eq!(image.pixel(i, j), background.to_f32_array());
            }
        }
    }
}

#[test]
fn nearer_triangle_hides_farther_in_either_order() {
    let eye = DVec3::ZERO;
    let camera = camera(eye, DVec3::Z, 32, 32, 60.0);
    let big = |z: f64| {
        facing(
            [
                DVec3::new(-9.0, -9.0, z),
                DVec3::new(9.0, -9.0, z),
                DVec3::new(0.0, 9.0, z),
            ],
            eye,
        )
    };
    let small = facing(
        [
            DVec3::new(-0.2, -0.2, 2.0),
            DVec3::new(0.2, -0.2, 2.0),
            DVec3::new(0.0, 0.2, 2.0),
        ],
        eye,
    );
    let red = Rgb::new(1.0, 0.0, 0.0);
    let near = flat(small, red);
    let far = flat(big(4.0), Rgb::new(0.0, 1.0, 0.0));
    let settings = RenderSettings::preview();
    for triangles in [[near, far], [far, near]] {
        let image = rasterize(&triangles, &camera, &settings);
        // The centre shows the near (red) triangle, a corner the far (green) one.
        assert_eq!(image.pixel(16, 16), [1.0, 0.0, 0.0]);
        assert_eq!(image.pixel(16, 15), [1.0, 0.0, 0.0]);
        assert_eq!(image.pixel(2, 29), [0.0, 1.0, 0.0]);
    }
    // A near triangle that is large hides the far one entirely.
    for triangles in [[flat(big(2.0), red), far], [far, flat(big(2.0), red)]] {
        let image = rasterize(&triangles, &camera, &settings);
        assert!(image.pixels().iter().all(|p| *p == [1.0, 0.0, 0.0]));
    }
}

#[test]
fn floor_crossing_behind_the_camera_is_clipped() {
    // Eye 1 unit above a floor that extends far behind it.
    let eye = DVec3::new(0.0, 1.0, 0.0);
    let camera = camera(eye, DVec3::new(0.0, 1.0, 5.0), 64, 64, 70.0);
    let field = field();
    for extent in [100.0, 1e5] {
        let floor = facing(
            [
                DVec3::new(-3.0 * extent, 0.0, -extent),
                DVec3::new(3.0 * extent, 0.0, -extent),
                DVec3::new(0.0, 0.0, 3.0 * extent),
            ],
            eye,
        );
        // A triangle entirely behind the camera must not show.
        let behind = flat(
            facing(
                [
                    DVec3::new(-5.0, -5.0, -1.0),
                    DVec3::new(5.0, -5.0, -1.0),
                    DVec3::new(0.0, 5.0, -1.0),
                ],
                eye,
            ),
            Rgb::splat(100.0),
        );
        let image = rasterize(
            &[field.shade(floor), behind],
            &camera,
            &RenderSettings::preview(),
        );
        assert!(image.pixels().iter().flatten().all(|v| v.is_finite()));
        let (checked, _) = check_linear_field(&camera, &image, floor, &field);
        assert_eq!(
            checked,
            64 * 32,
            "extent {extent}: the lower half sees the floor"
        );
        // The upper half sees the sky (background).
        assert!((0..32).all(|j| (0..64).all(|i| image.pixel(i, j) == [0.0; 3])));
    }
}

#[test]
fn back_face_is_black_and_occludes() {
    let eye = DVec3::ZERO;
    let camera = camera(eye, DVec3::Z, 16, 16, 60.0);
    let front = |z: f64| {
        facing(
            [
                DVec3::new(-9.0, -9.0, z),
                DVec3::new(9.0, -9.0, z),
                DVec3::new(0.0, 9.0, z),
            ],
            eye,
        )
    };
    let [p0, p1, p2] = front(2.0);
    let back = flat([p0, p2, p1], Rgb::splat(5.0));
    let far = flat(front(4.0), Rgb::splat(1.0));
    let settings = RenderSettings::preview().with_background(Rgb::splat(0.5));
    for triangles in [[back, far], [far, back]] {
        let image = rasterize(&triangles, &camera, &settings);
        assert_eq!(image.pixel(8, 8), [0.0; 3]);
        assert!(
            image
                .pixels()
                .iter()
                .all(|p| *p == [0.0; 3] || *p == [0.5; 3])
        );
    }
    // Alone, seen from its front, the same triangle carries its radiance.
    let image = rasterize(&[flat(front(2.0), Rgb::splat(5.0))], &camera, &settings);
    assert_eq!(image.pixel(8, 8), [5.0; 3]);
}

#[test]
fn of_two_faces_back_to_back_the_one_facing_the_eye_is_drawn() {
    // A shade or a panel modelled as a face each way: the two triangles
    // share their vertices, tilted and off-axis so that their depths tie
    // only up to rounding, and either may come first.
    let eye = DVec3::new(0.3, -0.2, 0.0);
    let camera = camera(eye, DVec3::new(0.1, 0.2, 3.0), 32, 32, 60.0);
    let positions = facing(
        [
            DVec3::new(-7.0, -6.0, 2.0),
            DVec3::new(8.0, -5.0, 3.5),
            DVec3::new(0.5, 9.0, 4.7),
        ],
        eye,
    );
    let [p0, p1, p2] = positions;
    let front = flat(positions, Rgb::splat(2.0));
    let back = flat([p0, p2, p1], Rgb::splat(9.0));
    let settings = RenderSettings::preview();
    for triangles in [[front, back], [back, front]] {
        let image = rasterize(&triangles, &camera, &settings);
        for j in 8..24 {
            for i in 8..24 {
                assert_eq!(image.pixel(i, j), [2.0; 3], "pixel ({i}, {j})");
            }
        }
    }
}

#[test]
fn quad_of_two_triangles_has_no_cracks() {
    // An oblique full-screen quad: its diagonal crosses many samples.
    let eye = DVec3::new(0.1, 0.2, -1.0);
    let camera = camera(eye, DVec3::new(0.0, 0.0, 1.0), 97, 61, 50.0);
    let corners = [
        DVec3::new(-7.0, -5.0, 0.0),
        DVec3::new(7.0, -5.0, 3.0),
        DVec3::new(7.0, 5.0, 2.0),
        DVec3::new(-7.0, 5.0, -0.5),
    ];
    // Both triangles front-facing, sharing the diagonal 0–2 in opposite directions.
    let [a, b, c, d] = corners;
    let (first, second) = if (b - a).cross(c - a).dot(eye - a) > 0.0 {
        ([a, b, c], [a, c, d])
    } else {
        ([a, c, b], [a, d, c])
    };
    let radiance = Rgb::splat(0.75);
    let background = Rgb::splat(1000.0);
    for supersampling in [1, 3, 4] {
        let settings = RenderSettings::default()
            .with_supersampling(supersampling)
            .with_background(background);
        let image = rasterize(
            &[flat(first, radiance), flat(second, radiance)],
            &camera,
            &settings,
        );
        assert!(
            image.pixels().iter().all(|p| *p == [0.75; 3]),
            "supersampling {supersampling}: background shows through"
        );
    }
}

/// A 20 × 10 camera at the origin looking along +z, and a white triangle
/// covering the image left of `x` pixels (a vertical edge there).
fn covered_left_of(x: f64) -> (Camera, ShadedTriangle) {
    let eye = DVec3::ZERO;
    let camera = camera(eye, DVec3::Z, 20, 10, 60.0);
    let tan_half = 30_f64.to_radians().tan();
    let x_edge = (2.0 * x / 20.0 - 1.0) * tan_half * 2.0;
    // right = forward × up = −x, so image x maps to world −x.
    let positions = facing(
        [
            DVec3::new(-x_edge, -50.0, 1.0),
            DVec3::new(50.0, -50.0, 1.0),
            DVec3::new(-x_edge, 50.0, 1.0),
        ],
        eye,
    );
    (camera, flat(positions, Rgb::ONE))
}

#[test]
fn supersampling_box_filters_partial_coverage() {
    // A vertical edge exactly through the centres of column 10: with 4 × 4
    // samples, pixels of that column are half covered.
    let (camera, triangle) = covered_left_of(10.5);
    let image = rasterize(&[triangle], &camera, &RenderSettings::final_quality());
    for j in 0..10 {
        assert_eq!(image.pixel(9, j), [1.0; 3]);
        assert_eq!(image.pixel(10, j), [0.5; 3]);
        assert_eq!(image.pixel(11, j), [0.0; 3]);
    }
    assert_close(image.mean(), Rgb::splat(10.5 / 20.0), 1e-12, "mean");
}

/// A pixel crossed by an outline is read in steps of 1/s of its width with
/// s × s samples; edge refinement reads it with the edge samples' grid.
#[test]
fn edge_refinement_reads_partial_coverage_finely() {
    // A vertical edge at 0.3 of the width of pixel column 10.
    let (camera, triangle) = covered_left_of(10.3);
    let triangles = [triangle];
    let coarse = RenderSettings::default().with_edge_supersampling(1);
    let refined = RenderSettings::default().with_edge_supersampling(16);
    let coarse = rasterize(&triangles, &camera, &coarse);
    let refined = rasterize(&triangles, &camera, &refined);
    for j in 0..10 {
        // Three sample columns at 1/6, 1/2, 5/6 of the pixel: one covered.
        assert_close(
            as_rgb(coarse.pixel(10, j)),
            Rgb::splat(1.0 / 3.0),
            1e-6,
            "3 × 3",
        );
        // Sixteen at (k + 1/2)/16: five lie left of 0.3.
        assert_eq!(refined.pixel(10, j), [5.0 / 16.0; 3], "row {j}");
        assert_eq!(refined.pixel(9, j), [1.0; 3]);
        assert_eq!(refined.pixel(11, j), [0.0; 3]);
    }
}

/// The refined pixels are exactly those of a render with e × e samples
/// everywhere, every pixel an outline crosses is refined, and a surface's
/// smooth shading is not.
#[test]
fn edge_refinement_matches_full_supersampling_where_outlines_cross() {
    let eye = DVec3::new(0.3, 0.2, -4.0);
    let camera = camera(eye, DVec3::new(0.0, 0.0, 0.0), 64, 48, 50.0);
    // A wall whose radiance rises gently from left to right, and two tilted
    // triangles in front of it, one bright and one dark, at odd angles.
    let wall = [
        [
            DVec3::new(-3.0, -3.0, 1.0),
            DVec3::new(3.0, -3.0, 1.0),
            DVec3::new(3.0, 3.0, 1.0),
        ],
        [
            DVec3::new(-3.0, -3.0, 1.0),
            DVec3::new(3.0, 3.0, 1.0),
            DVec3::new(-3.0, 3.0, 1.0),
        ],
    ];
    let shade = |p: DVec3| Rgb::splat(1.0 + 0.05 * p.x);
    let mut triangles: Vec<ShadedTriangle> = wall
        .iter()
        .map(|&positions| {
            let positions = facing(positions, eye);
            ShadedTriangle {
                positions,
                radiance: positions.map(shade),
            }
        })
        .collect();
    triangles.push(flat(
        facing(
            [
                DVec3::new(-1.3, -0.9, 0.2),
                DVec3::new(0.7, -1.1, 0.0),
                DVec3::new(-0.2, 1.3, 0.4),
            ],
            eye,
        ),
        Rgb::splat(4.0),
    ));
    triangles.push(flat(
        facing(
            [
                DVec3::new(0.1, -0.3, -0.3),
                DVec3::new(1.7, 0.2, -0.1),
                DVec3::new(0.9, 1.6, -0.2),
            ],
            eye,
        ),
        Rgb::splat(0.2),
    ));
    let render = |s: u32, e: u32| {
        let settings = RenderSettings::default()
            .with_supersampling(s)
            .with_edge_supersampling(e);
        rasterize(&triangles, &camera, &settings)
    };
    let (coarse, fine, refined) = (render(3, 1), render(16, 1), render(3, 16));
    let mut refined_count = 0;
    let (mut coarse_error, mut refined_error) = (0.0, 0.0);
    for ((c, f), r) in coarse
        .pixels()
        .iter()
        .zip(fine.pixels())
        .zip(refined.pixels())
    {
        assert!(
            r == f || r == c,
            "refined {r:?}, 3 × 3 {c:?}, 16 × 16 {f:?}"
        );
        if r == f && r != c {
            refined_count += 1;
        }
        // Where the 3 × 3 samples miss an outline's coverage by more than a
        // percent, the pixel was refined.
        if (c[0] - f[0]).abs() > 0.01 * f[0].max(1e-6) {
            assert_eq!(r, f);
        }
        coarse_error += f64::from((c[0] - f[0]).abs());
        refined_error += f64::from((r[0] - f[0]).abs());
    }
    let pixels = coarse.pixels().len();
    assert!(refined_count > 40, "{refined_count} pixels refined");
    assert!(
        refined_count < pixels / 4,
        "{refined_count} of {pixels} refined"
    );
    assert!(
        refined_error < 0.01 * coarse_error,
        "off the 16 × 16 render: {refined_error} refined, {coarse_error} at 3 × 3"
    );
}

#[test]
fn camera_right_and_up_land_in_the_right_half_and_top_rows() {
    // The Cornell box camera: world −x is image right.
    let eye = DVec3::new(278.0, 273.0, -800.0);
    let camera = camera(eye, DVec3::new(278.0, 273.0, 0.0), 64, 64, 39.3);
    let frame = camera.frame();
    let marker = |centre: DVec3| {
        let s = 10.0;
        flat(
            facing(
                [
                    centre - s * frame.right - s * frame.up,
                    centre + s * frame.right - s * frame.up,
                    centre + s * frame.up,
                ],
                eye,
            ),
            Rgb::ONE,
        )
    };
    let lit = |image: &Image| -> Vec<(u32, u32)> {
        (0..64)
            .flat_map(|j| (0..64).map(move |i| (i, j)))
            .filter(|&(i, j)| image.pixel(i, j)[0] > 0.0)
            .collect()
    };
    let settings = RenderSettings::preview();
    let right = rasterize(&[marker(DVec3::new(178.0, 273.0, 0.0))], &camera, &settings);
    let on_right = lit(&right);
    assert!(
        !on_right.is_empty()
            && on_right
                .iter()
                .all(|&(i, j)| i >= 32 && (20..44).contains(&j))
    );
    let up = rasterize(&[marker(DVec3::new(278.0, 373.0, 0.0))], &camera, &settings);
    let on_top = lit(&up);
    assert!(!on_top.is_empty() && on_top.iter().all(|&(i, j)| j < 32 && (20..44).contains(&i)));
}

#[test]
fn degenerate_input_gives_background_and_no_nan() {
    let eye = DVec3::ZERO;
    let camera = camera(eye, DVec3::Z, 8, 8, 60.0);
    let settings = RenderSettings::default().with_background(Rgb::splat(0.5));
    // No triangles.
    assert!(
        rasterize(&[], &camera, &settings)
            .pixels()
            .iter()
            .all(|p| *p == [0.5; 3])
    );
    // Zero area, non-finite positions and radiance, a vertex at the eye.
    let p = [
        DVec3::new(-1.0, -1.0, 2.0),
        DVec3::new(1.0, -1.0, 2.0),
        DVec3::new(0.0, 1.0, 2.0),
    ];
    let junk = [
        flat([p[0], p[1], p[0]], Rgb::ONE),
        flat([p[0], 0.5 * (p[0] + p[1]), p[1]], Rgb::ONE),
        flat([p[0], p[1], DVec3::new(f64::NAN, 0.0, 1.0)], Rgb::ONE),
        flat(p, Rgb::new(f64::INFINITY, 0.0, 0.0)),
        flat([eye, p[1], p[2]], Rgb::ONE),
        flat(
            [
                DVec3::splat(1e300),
                DVec3::new(-1e300, 1e300, 1e300),
                DVec3::new(0.0, -1e300, 1e300),
            ],
            Rgb::ONE,
        ),
    ];
    let image = rasterize(&junk, &camera, &settings);
    assert!(image.pixels().iter().all(|p| *p == [0.5; 3]));
    // A camera that cannot see, and an empty image.
    let mut blind = camera.clone();
    blind.look_at = blind.position;
    assert!(
        rasterize(&[flat(facing(p, eye), Rgb::ONE)], &blind, &settings)
            .pixels()
            .iter()
            .all(|p| *p == [0.5; 3])
    );
    let mut empty = camera.clone();
    empty.width = 0;
    assert_eq!(rasterize(&[], &empty, &settings).pixels().len(), 0);
}

fn test_image() -> Image {
    let pixels = (0..6 * 4)
        .map(|k| {
            let k = k as f32;
            [k * 0.1 + 1e-7, -k, (k * 1.618).sin() * 1e4]
        })
        .collect();
    Image::from_pixels(6, 4, pixels).expect("6 × 4 pixels")
}

fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("readable directory")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn exr_round_trip_is_exact_and_overwrites() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join("out.exr");
    let image = test_image();
    write_exr(&image, &path).expect("written");
    assert_eq!(read_exr(&path).expect("read back"), image);
    // Overwriting an existing file replaces it whole.
    let other = Image::filled(3, 2, [0.5, 0.25, 0.125]);
    write_exr(&other, &path).expect("overwritten");
    assert_eq!(read_exr(&path).expect("read back"), other);
    assert_eq!(entries(dir.path()), vec!["out.exr".to_string()]);
}

#[test]
fn unwritable_paths_are_errors_that_leave_nothing_behind() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let image = test_image();
    // A missing directory.
    let missing = dir.path().join("missing").join("out.exr");
    let error = write_exr(&image, &missing).expect_err("missing directory");
    assert!(
        matches!(error, Error::Io { ref path, .. } if *path == missing),
        "{error}"
    );
    assert!(error.to_string().contains("out.exr"));
    let error = write_png(&image, &ToneMap::default(), &missing.with_extension("png"))
        .expect_err("missing directory");
    assert!(matches!(error, Error::Io { .. }), "{error}");
    // A target that is a directory: the rename fails, the temporary file goes.
    let occupied = dir.path().join("occupied.exr");
    std::fs::create_dir(&occupied).expect("directory created");
    assert!(write_exr(&image, &occupied).is_err());
    assert!(write_png(&image, &ToneMap::default(), &occupied).is_err());
    assert_eq!(entries(dir.path()), vec!["occupied.exr".to_string()]);
    // Reading what is not there, or not an EXR.
    assert!(matches!(
        read_exr(&dir.path().join("none.exr")),
        Err(Error::Io { .. })
    ));
    let text = dir.path().join("text.exr");
    std::fs::write(&text, "not an image").expect("written");
    assert!(matches!(read_exr(&text), Err(Error::InvalidImage { .. })));
    // An empty image cannot be stored.
    assert!(matches!(
        write_exr(&Image::new(0, 3), &dir.path().join("e.exr")),
        Err(Error::Output { .. })
    ));
}

#[test]
fn png_follows_the_srgb_curve() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join("out.png");
    let values = [0.0, 1.0, 0.003_130_8, 0.5, 0.25, 2.0, -1.0, 0.001];
    let pixels = values.iter().map(|&v| [v, v, v]).collect();
    let image = Image::from_pixels(values.len() as u32, 1, pixels).expect("a row of pixels");
    write_png(&image, &ToneMap::default(), &path).expect("written");
    let png = ::image::open(&path).expect("readable PNG").to_rgb8();
    let got: Vec<u8> = png.pixels().map(|p| p[0]).collect();
    // 0.0031308 → 12.92 · 0.0031308 · 255 = 10.31; 0.5 → (1.055 · 0.5^(1/2.4) − 0.055) · 255 = 187.5;
    // 0.25 → 137.0; 0.001 → 12.92 · 0.001 · 255 = 3.29.
    assert_eq!(got, vec![0, 255, 10, 188, 137, 255, 0, 3]);
    assert!(png.pixels().all(|p| p[0] == p[1] && p[1] == p[2]));
    // One stop of exposure doubles the radiance: 0.25 is then shown as 0.5.
    write_png(&image, &ToneMap { exposure: 1.0 }, &path).expect("overwritten");
    let png = ::image::open(&path).expect("readable PNG").to_rgb8();
    assert_eq!(png.get_pixel(4, 0)[0], 188);
    assert_eq!(entries(dir.path()), vec!["out.png".to_string()]);
}
