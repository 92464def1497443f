//! Scenes built in code for the integration tests.
#![allow(dead_code)]

use glam::{DVec2, DVec3};
use isorad::{Material, Rgb, Scene, mesh::PlaneTriangulation, scene::Surface};

/// An N × N grid over the square [−half, half]², with `value` at its
/// points, each quad split along the diagonal whose ends' values are closer
/// (as the renderer splits it).
pub fn square_grid_mesh(
    half: f64,
    n: usize,
    value: &dyn Fn(DVec2) -> f64,
) -> (PlaneTriangulation, Vec<f64>) {
    let step = 2.0 * half / n as f64;
    let points: Vec<DVec2> = (0..=n)
        .flat_map(|j| {
            (0..=n).map(move |i| DVec2::new(-half + step * i as f64, -half + step * j as f64))
        })
        .collect();
    let values: Vec<f64> = points.iter().map(|&p| value(p)).collect();
    let id = |i: usize, j: usize| j * (n + 1) + i;
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (values[a] - values[c]).abs() <= (values[b] - values[d]).abs() {
                triangles.extend([[a, b, c], [a, c, d]]);
            } else {
                triangles.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    (PlaneTriangulation { points, triangles }, values)
}

/// A scene builder: materials by name, polygons oriented as given.
#[derive(Default)]
pub struct SceneBuilder {
    pub scene: Scene,
}

impl SceneBuilder {
    pub fn material(&mut self, name: &str, reflectance: f64, emitted_radiance: f64) -> usize {
        self.scene.materials.push(Material {
            name: name.into(),
            reflectance: Rgb::splat(reflectance),
            emitted_radiance: Rgb::splat(emitted_radiance),
            transmittance: 0.0,
        });
        self.scene.materials.len() - 1
    }

    pub fn polygon(&mut self, name: &str, material: usize, vertices: Vec<DVec3>) {
        let surface = Surface::new(name, material, vertices).expect("valid test polygon");
        self.scene.surfaces.push(surface);
    }

    /// A polygon whose front faces `towards`.
    pub fn polygon_facing(
        &mut self,
        name: &str,
        material: usize,
        mut vertices: Vec<DVec3>,
        towards: DVec3,
    ) {
        let normal = isorad::internals::newell_normal(&vertices);
        let centre = vertices.iter().copied().sum::<DVec3>() / vertices.len() as f64;
        if normal.dot(towards - centre) < 0.0 {
            vertices.reverse();
        }
        self.polygon(name, material, vertices);
    }
}

/// The six faces of the box [0, size], each facing inwards.
pub fn box_faces(size: DVec3) -> Vec<Vec<DVec3>> {
    let mut faces = Vec::new();
    for axis in 0..3 {
        for side in [0.0, 1.0] {
            let corner = |s: f64, t: f64| {
                let mut p = [0.0; 3];
                p[axis] = side;
                p[(axis + 1) % 3] = s;
                p[(axis + 2) % 3] = t;
                DVec3::from_array(p) * size
            };
            let mut quad = vec![
                corner(0.0, 0.0),
                corner(1.0, 0.0),
                corner(1.0, 1.0),
                corner(0.0, 1.0),
            ];
            if isorad::internals::newell_normal(&quad).dot(size * 0.5 - quad[0]) < 0.0 {
                quad.reverse();
            }
            faces.push(quad);
        }
    }
    faces
}

/// Unit cube [0, 1]³, every face facing inwards with the same material.
pub fn closed_cube(reflectance: f64, emitted_radiance: f64) -> Scene {
    let mut b = SceneBuilder::default();
    let m = b.material("wall", reflectance, emitted_radiance);
    for quad in box_faces(DVec3::ONE) {
        b.polygon("face", m, quad);
    }
    b.scene
}

/// A regular n-gon of radius r centred at `centre` in the plane z = centre.z,
/// facing down (−z).
pub fn disc_facing_down(sides: usize, radius: f64, centre: DVec3) -> Vec<DVec3> {
    (0..sides)
        .rev()
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / sides as f64;
            centre + DVec3::new(radius * a.cos(), radius * a.sin(), 0.0)
        })
        .collect()
}

/// An axis-aligned square in the plane z = height, facing `up` or down.
pub fn square_z(min: f64, max: f64, height: f64, facing_up: bool) -> Vec<DVec3> {
    let mut v = vec![
        DVec3::new(min, min, height),
        DVec3::new(max, min, height),
        DVec3::new(max, max, height),
        DVec3::new(min, max, height),
    ];
    if !facing_up {
        v.reverse();
    }
    v
}

/// Parallel coaxial disc form factor (DESIGN.md).
pub fn coaxial_disc_form_factor(radius: f64, height: f64, x: f64) -> f64 {
    let (r2, h2, x2) = (radius * radius, height * height, x * x);
    0.5 * (1.0 - (x2 + h2 - r2) / ((x2 + h2 + r2).powi(2) - 4.0 * r2 * x2).sqrt())
}

/// SplitMix64: a small seeded generator, so failures reproduce.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        (((z ^ (z >> 31)) >> 11) as f64) / (1u64 << 53) as f64
    }

    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }

    /// Uniform on the unit sphere.
    pub fn direction(&mut self) -> DVec3 {
        let z = self.range(-1.0, 1.0);
        let a = self.range(0.0, std::f64::consts::TAU);
        let s = (1.0 - z * z).sqrt();
        DVec3::new(s * a.cos(), s * a.sin(), z)
    }

    /// Uniform in the cube [−half_size, half_size]³.
    pub fn point(&mut self, half_size: f64) -> DVec3 {
        DVec3::new(
            self.range(-half_size, half_size),
            self.range(-half_size, half_size),
            self.range(-half_size, half_size),
        )
    }
}

/// A closed 4 × 3 × 4 room at `offset`, faces inwards (the floor named
/// `floor_{room}`, the rest `wall_{room}`), with a 0.5 m block standing in
/// the middle of its floor (`block_{room}`, faces outwards).
pub fn room_with_block(b: &mut SceneBuilder, wall: usize, room: &str, offset: DVec3) {
    for (k, quad) in box_faces(DVec3::new(4.0, 3.0, 4.0)).into_iter().enumerate() {
        let name = if k == 2 {
            format!("floor_{room}")
        } else {
            format!("wall_{room}")
        };
        b.polygon(&name, wall, quad.into_iter().map(|p| p + offset).collect());
    }
    for quad in box_faces(DVec3::splat(0.5)) {
        let mut quad: Vec<DVec3> = quad
            .into_iter()
            .map(|p| p + offset + DVec3::new(1.75, 0.0, 1.75))
            .collect();
        quad.reverse();
        b.polygon(&format!("block_{room}"), wall, quad);
    }
}

/// A 0.6 m square lamp of material `lamp` 1 cm under the ceiling of the
/// room [`room_with_block`] makes at `offset`, facing the block.
pub fn ceiling_lamp(b: &mut SceneBuilder, lamp: usize, offset: DVec3) {
    b.polygon_facing(
        "lamp",
        lamp,
        [(1.7, 1.7), (2.3, 1.7), (2.3, 2.3), (1.7, 2.3)]
            .map(|(x, z)| offset + DVec3::new(x, 2.99, z))
            .to_vec(),
        offset + DVec3::new(2.0, 0.0, 2.0),
    );
}

/// What a solve with or without the closed-zone cull found.
pub struct ZonedSolve {
    pub zones: usize,
    pub rays: u64,
    pub radiosity: Vec<isorad::Rgb>,
}

/// Solves `scene` to the settings' tolerance with the closed-zone cull on
/// or off: the zones it found, its shadow rays and its radiosity. Each shot
/// is the strongest patch of all (`zone_affinity` 1), so that the culled
/// solve shoots in the same order as the other.
pub fn solve_with_cull(scene: Scene, mut settings: isorad::Settings, cull: bool) -> ZonedSolve {
    settings.solver.cull_closed_zones = cull;
    settings.solver.zone_affinity = 1.0;
    let mut solver = isorad::Solver::new(scene, settings).unwrap();
    solver.run();
    ZonedSolve {
        zones: solver.closed_zones(),
        rays: solver.stats().rays,
        radiosity: solver.radiosity().to_vec(),
    }
}

/// Solves `scene` to 5 % with and without the closed-zone cull, and checks
/// that the cull found `zones` zones and left the radiosity the same, bit
/// for bit. Returns the culled solve and the other.
pub fn assert_cull_keeps_the_light(scene: Scene, zones: usize) -> (ZonedSolve, ZonedSolve) {
    let mut settings = isorad::Settings::default();
    settings.solver.tolerance = 0.05;
    let culled = solve_with_cull(scene.clone(), settings.clone(), true);
    let all = solve_with_cull(scene, settings, false);
    assert_eq!((culled.zones, all.zones), (zones, 1));
    assert_eq!(culled.radiosity, all.radiosity, "the same radiosity");
    (culled, all)
}

/// What a gather probe reads at `position` on a surface (facing `normal`
/// when given).
pub fn gather_at(
    solution: &isorad::Solution<'_>,
    position: DVec3,
    normal: Option<DVec3>,
) -> isorad::Probe {
    let point = isorad::scene::ProbePoint {
        position,
        normal,
        line: 1,
    };
    solution.probe(&point, isorad::ProbeMode::Gather).unwrap()
}

/// The largest relative difference of radiosity (red) between the mesh's
/// interpolation and a gather, over `points` (no normals).
pub fn worst_mesh_against_gather(solution: &isorad::Solution<'_>, points: &[DVec3]) -> f64 {
    points
        .iter()
        .map(|&position| {
            let point = isorad::scene::ProbePoint {
                position,
                normal: None,
                line: 1,
            };
            let exact = gather_at(solution, position, None).radiosity.r;
            let shown = solution
                .probe(&point, isorad::ProbeMode::Mesh)
                .unwrap()
                .radiosity
                .r;
            (shown - exact).abs() / exact
        })
        .fold(0.0, f64::max)
}
