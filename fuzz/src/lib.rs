//! Shared pieces of isorad's fuzz targets: a scratch folder for the files a
//! target writes, the invariants every loaded scene and every mesh must
//! hold, and the decoding of fuzz bytes into polygons.
//!
//! Every check panics on a broken invariant, which libFuzzer reports as a
//! crash with its input.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use glam::{DVec2, DVec3};
use isorad::{
    Scene,
    internals::estimate_square_elements,
    mesh::{
        ContourSettings, ElementHierarchy, Mesh, SquareMeshSettings, SurfaceGuides, contour_layout,
        mesh_square, mesh_surfaces,
    },
};

/// A folder of this process's own, for the files a target writes (in
/// memory under /dev/shm where there is one).
#[must_use]
pub fn scratch_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let base = Path::new("/dev/shm");
        let base = if base.is_dir() {
            base.to_path_buf()
        } else {
            std::env::temp_dir()
        };
        let dir = base.join(format!("isorad-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("scratch folder");
        dir
    })
}

/// Writes `bytes` to `name` in the scratch folder and returns its path.
pub fn write_scratch(name: &str, bytes: &[u8]) -> PathBuf {
    let path = scratch_dir().join(name);
    std::fs::write(&path, bytes).expect("scratch file");
    path
}

/// Splits fuzz input at its first NUL byte: (before, after).
#[must_use]
pub fn split_at_nul(data: &[u8]) -> (&[u8], &[u8]) {
    match data.iter().position(|&b| b == 0) {
        Some(at) => (&data[..at], &data[at + 1..]),
        None => (data, &[]),
    }
}

/// What a loaded scene promises: surfaces with finite vertices, positive
/// finite area, a unit normal and a known material; materials with
/// reflectance in [0, 1) and finite, non-negative emission; a finite
/// diagonal; and a finite, non-negative emitted power.
pub fn check_scene(scene: &Scene) {
    assert!(!scene.surfaces.is_empty(), "a loaded scene has surfaces");
    for surface in &scene.surfaces {
        assert!(surface.vertices().len() >= 3);
        assert!(surface.vertices().iter().all(|v| v.is_finite()));
        assert!(surface.area().is_finite() && surface.area() > 0.0);
        assert!((surface.normal().length() - 1.0).abs() < 1e-6);
        assert!(surface.material < scene.materials.len());
    }
    for material in &scene.materials {
        for rho in material.reflectance.to_array() {
            assert!((0.0..1.0).contains(&rho), "{material:?}");
        }
        for emission in material.emitted_radiance.to_array() {
            assert!(emission.is_finite() && emission >= 0.0, "{material:?}");
        }
    }
    assert!(scene.diagonal().is_finite());
    let power = scene.emitted_power();
    assert!(power.is_finite() && power.min_element() >= 0.0, "{power}");
}

/// Reads little-endian numbers off fuzz bytes; zeros when they run out.
pub struct Bytes<'a>(pub &'a [u8]);

impl Bytes<'_> {
    pub fn u8(&mut self) -> u8 {
        let (first, rest) = self.0.split_first().unwrap_or((&0, &[]));
        self.0 = rest;
        *first
    }

    pub fn i16(&mut self) -> i16 {
        i16::from_le_bytes([self.u8(), self.u8()])
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

/// Decodes fuzz bytes into a polygon in the plane: a scale byte (powers of
/// ten from 10⁻³² to 10³¹, so coordinates span tiny to huge), an offset
/// byte (moves the polygon up to 10⁶ of its size from the origin), then
/// vertices as pairs of 16-bit integers — concave, self-touching, collinear
/// or repeated as the bytes make them. At most `max_vertices`.
#[must_use]
pub fn decode_polygon(bytes: &mut Bytes, max_vertices: usize) -> Vec<DVec2> {
    let scale = 10f64.powi(i32::from(bytes.u8() as i8) / 4);
    let offset = f64::from(bytes.u8() as i8).powi(3) * 0.5;
    let mut points = Vec::new();
    while !bytes.is_empty() && points.len() < max_vertices {
        let x = f64::from(bytes.i16()) / 256.0 + offset;
        let y = f64::from(bytes.i16()) / 256.0;
        points.push(DVec2::new(x, y) * scale);
    }
    points
}

/// An OBJ scene, as text, of `floor` (a polygon in the plane y = 0, facing
/// up when counter-clockwise seen from above) under a square lamp facing it
/// at the polygon's size above it, with its MTL `fuzz.mtl`.
#[must_use]
pub fn floor_and_lamp_obj(floor: &[DVec2]) -> String {
    let (low, high) = floor.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let centre = 0.5 * (low + high);
    let size = (high - low).max_element().max(f64::MIN_POSITIVE);
    let mut text = String::from("mtllib fuzz.mtl\no lamp\nusemtl lamp\n");
    for (dx, dz) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        let p = DVec3::new(centre.x + 0.1 * size * dx, size, centre.y + 0.1 * size * dz);
        text += &format!("v {:e} {:e} {:e}\n", p.x, p.y, p.z);
    }
    text += "f 1 2 3 4\no floor\nusemtl white\n";
    for p in floor {
        // (x, y) in the plane → (x, 0, −y): counter-clockwise from above.
        text += &format!("v {:e} 0 {:e}\n", p.x, -p.y);
    }
    text += "f";
    for k in 0..floor.len() {
        text += &format!(" {}", k + 5);
    }
    text + "\n"
}

/// The materials of [`floor_and_lamp_obj`].
pub const FLOOR_AND_LAMP_MTL: &str =
    "newmtl white\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0.2 0.2 0.2\nKe 10 10 10\n";

/// Meshes no fuzz case may exceed, to keep executions fast.
pub const MAX_FUZZ_ELEMENTS: f64 = 20_000.0;

/// A mesher under test: its name and how it meshes a scene. To fuzz a new
/// mesher, add a function of this shape to [`MESHERS`].
pub type Mesher = fn(&Scene) -> Mesh;

/// Every mesher the `meshers` target runs on each decoded scene.
pub const MESHERS: &[(&str, Mesher)] = &[
    ("square", square),
    ("adaptive", adaptive),
    ("contour", contour),
];

/// Square settings with elements of a tenth of the scene's diagonal.
fn coarse(scene: &Scene) -> SquareMeshSettings {
    let mut settings = SquareMeshSettings::for_scene(scene);
    settings.max_edge = scene.diagonal() / 10.0;
    settings.patch_max_edge = scene.diagonal() / 4.0;
    settings
}

/// The square mesher.
fn square(scene: &Scene) -> Mesh {
    mesh_square(scene, &coarse(scene))
}

/// The adaptive mesher's element quadtrees: the square mesh, every element
/// split once, then every third leaf split again (hanging vertices on the
/// neighbours), with the hierarchy validated after each round.
fn adaptive(scene: &Scene) -> Mesh {
    let mut mesh = square(scene);
    let mut hierarchy = ElementHierarchy::new(&mesh);
    let areas: Vec<f64> = scene.surfaces.iter().map(|s| s.area()).collect();
    for round in 0..2 {
        let chosen: Vec<usize> = (0..mesh.elements.len())
            .filter(|e| round == 0 || e % 3 == 0)
            .collect();
        hierarchy.split(&mut mesh, &chosen);
        if let Err(e) = hierarchy.validate(&mesh, &areas) {
            panic!("adaptive: round {round}: {e}");
        }
    }
    mesh
}

/// The contour mesher on every non-emitting surface, for a unimodal field
/// peaked under the lamp, triangulated with constraints (spade).
fn contour(scene: &Scene) -> Mesh {
    let mut settings = ContourSettings::default();
    settings.directions = 8;
    settings.levels = 4;
    let layouts: Vec<_> = scene
        .surfaces
        .iter()
        .map(|surface| {
            if scene.material_of(surface).is_emitter() {
                return None;
            }
            let outline = surface.plane_vertices();
            let size = outline
                .iter()
                .map(|p| p.length())
                .fold(0.0, f64::max)
                .max(f64::MIN_POSITIVE);
            // B = 1 / (1 + |p − c|²/s²): one maximum, at the centre.
            let centre = outline.iter().copied().sum::<DVec2>() / outline.len() as f64;
            let field = move |p: DVec2| {
                let d = (p - centre) / size;
                let q = 1.0 + d.length_squared();
                (1.0 / q, -2.0 * d / (size * q * q))
            };
            Some(contour_layout(&outline, &field, centre, &settings, &[]))
        })
        .collect();
    mesh_surfaces(scene, &coarse(scene), &|surface| SurfaceGuides {
        layout: layouts[surface.index()].clone(),
        boundaries: Vec::new(),
        contact_scale: None,
    })
}

/// The `meshers` target: `data` decodes to a floor polygon (concave, nearly
/// degenerate, tiny or huge as the bytes make it), which goes through the
/// OBJ loader's clean-up as a user's face would (skipped, projected or
/// split), under a lamp; every mesher in [`MESHERS`] then meshes the scene,
/// and every mesh must keep [`check_mesh`]'s invariants.
pub fn mesh_random_floor(data: &[u8]) {
    let floor = decode_polygon(&mut Bytes(data), 256);
    if floor.len() < 3 {
        return;
    }
    write_scratch("fuzz.mtl", FLOOR_AND_LAMP_MTL.as_bytes());
    let path = write_scratch("floor.obj", floor_and_lamp_obj(&floor).as_bytes());
    let Ok(scene) = isorad::scene::load_obj(&path) else {
        return;
    };
    check_scene(&scene);
    if !small_enough(&scene) {
        return;
    }
    for (name, mesher) in MESHERS {
        check_mesh(name, &scene, &mesher(&scene));
    }
}

/// Whether the fuzz meshers should run on `scene` (small enough to be fast).
#[must_use]
pub fn small_enough(scene: &Scene) -> bool {
    estimate_square_elements(scene, &coarse(scene)) <= MAX_FUZZ_ELEMENTS
}

/// What every mesh promises: [`Mesh::validate`] (indices, positive areas,
/// patches, no more than each surface's area), finite vertex positions on
/// their surface's plane, and — nothing standing on these floors — elements
/// covering each surface's whole area.
pub fn check_mesh(name: &str, scene: &Scene, mesh: &Mesh) {
    let areas: Vec<f64> = scene.surfaces.iter().map(|s| s.area()).collect();
    if let Err(e) = mesh.validate(&areas) {
        panic!("{name}: {e}");
    }
    for vertex in &mesh.vertices {
        assert!(vertex.position.is_finite(), "{name}: {vertex:?}");
        assert!(vertex.receiver_position().is_finite(), "{name}: {vertex:?}");
        let surface = scene.surface(vertex.surface);
        let size = surface
            .vertices()
            .iter()
            .map(|v| v.distance(surface.frame().origin))
            .fold(0.0, f64::max);
        let height = surface.frame().height(vertex.position).abs();
        assert!(
            height <= 1e-6 * size,
            "{name}: vertex {height} off its plane (size {size})"
        );
    }
    let mut covered = vec![0.0; scene.surfaces.len()];
    let mut rendered = vec![0.0; scene.surfaces.len()];
    let mut triangles = Vec::new();
    for element in &mesh.elements {
        covered[element.surface.index()] += element.area;
        mesh.element_triangles(element, |_, _| 0.0, &mut triangles);
        for &[a, b, c] in &triangles {
            let [a, b, c] = [a, b, c].map(|v| mesh.vertices[v as usize].position);
            rendered[element.surface.index()] += 0.5 * (b - a).cross(c - a).length();
        }
    }
    for (surface, &area) in areas.iter().enumerate() {
        let (sum, drawn) = (covered[surface], rendered[surface]);
        assert!(
            (sum - area).abs() <= 1e-6 * area,
            "{name}: surface {surface}: elements cover {sum} of {area}"
        );
        assert!(
            (drawn - area).abs() <= 1e-6 * area,
            "{name}: surface {surface}: rendered triangles cover {drawn} of {area}"
        );
    }
}

/// The `photometry` target: `data` as an IES LM-63 file and as an
/// EULUMDAT file ([`parse_ies_bytes`], [`parse_eulumdat_bytes`]).
pub fn parse_photometry(data: &[u8]) {
    parse_ies_bytes(data);
    parse_eulumdat_bytes(data);
}

/// The `photometry_ies` target: `data` as the bytes of an IES LM-63 file,
/// decoded as files are (a byte-order mark dropped, UTF-8 or Latin-1).
/// The parse ends in a distribution whose intensities are finite and
/// non-negative everywhere, with C planes from 0° to 360° and a finite
/// flux, or in an error naming a line of the text.
pub fn parse_ies_bytes(data: &[u8]) {
    check_photometric(data, isorad::photometry::PhotometricFormat::Ies);
}

/// The `photometry_eulumdat` target: [`parse_ies_bytes`] for EULUMDAT.
pub fn parse_eulumdat_bytes(data: &[u8]) {
    check_photometric(data, isorad::photometry::PhotometricFormat::Eulumdat);
}

/// Parses `data` in `format` and checks what comes back (see
/// [`parse_ies_bytes`]).
fn check_photometric(data: &[u8], format: isorad::photometry::PhotometricFormat) {
    let lines = isorad::photometry::decode_text(data).lines().count().max(1);
    match isorad::photometry::parse_photometric_bytes(data, format) {
        Ok(file) => {
            let distribution = file.distribution();
            let c = distribution.c_angles();
            assert_eq!(c.first(), Some(&0.0));
            assert_eq!(c.last(), Some(&360.0));
            assert!(c.windows(2).all(|w| w[0] < w[1]), "{c:?}");
            for k in 0..=24 {
                for j in 0..=12 {
                    let i = distribution.intensity(15.0 * k as f64, 15.0 * j as f64);
                    assert!(i.is_finite() && i >= 0.0, "I = {i}");
                }
            }
            assert!(distribution.flux(1).is_finite());
        }
        Err(problem) => {
            if let Some(line) = problem.line {
                assert!((1..=lines).contains(&line), "line {line} of {lines}");
            }
            assert!(!problem.message.is_empty());
        }
    }
}
