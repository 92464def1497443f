//! Exporting a solution: the glb parses back with the gltf crate, the PLY
//! reads back with a plain reader, both with the solution's vertices and
//! colours; bad values and unknown formats are refused.

use std::path::Path;

use isorad::{
    Ambient, Length, Settings, Solver, ToneMap,
    export::{export_glb, export_ply},
    export_solution, load_scene,
    phase::silent,
};

/// The Cornell box, coarsely meshed (elements of 3/40 of its diagonal) and
/// solved to 5 %.
fn solved_cornell() -> Solver {
    let scene = load_scene("cornell").unwrap().scene;
    let mut settings = Settings::default();
    settings.mesh.max_edge = Length::OfDiagonal(3.0 / 40.0);
    settings.solver.tolerance = 0.05;
    let mut solver = Solver::new(scene, settings).unwrap();
    solver.run();
    solver
}

/// An exposure that clips the light but not the walls: both branches of
/// the colour mapping are exercised.
fn tone_map() -> ToneMap {
    ToneMap::new(-2.0)
}

/// The display colour the exporters promise: clamp(L · 2^exposure, 0, 1).
fn display_colour(radiosity: isorad::Rgb, tone_map: &ToneMap) -> [f32; 3] {
    let l = radiosity / std::f64::consts::PI * tone_map.exposure.exp2();
    l.to_array().map(|c| c.clamp(0.0, 1.0) as f32)
}

#[test]
fn glb_parses_back_with_the_solutions_vertices_and_colours() {
    let solver = solved_cornell();
    let solution = solver.solution(Ambient::Everywhere, &silent);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cornell.glb");
    export_glb(&solution, &tone_map(), &path).unwrap();

    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(&bytes[..4], b"glTF");
    assert_eq!(bytes.len() % 4, 0);
    let gltf = gltf::Gltf::from_slice(&bytes).expect("a valid glTF 2.0 binary");
    assert!(gltf.extensions_used().any(|e| e == "KHR_materials_unlit"));
    let blob = gltf.blob.clone().expect("a BIN chunk");
    let mesh = gltf.meshes().next().expect("one mesh");
    let primitive = mesh.primitives().next().expect("one primitive");
    assert_eq!(primitive.mode(), gltf::mesh::Mode::Triangles);
    let material = primitive.material();
    assert!(material.unlit());
    assert_eq!(
        material.pbr_metallic_roughness().base_color_factor(),
        [1.0; 4]
    );
    let reader = primitive.reader(|_| Some(&blob));

    // As many vertices as the solution, at the same places.
    let positions: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
    assert_eq!(positions.len(), solver.mesh().vertices.len());
    for (p, v) in positions.iter().zip(&solver.mesh().vertices) {
        assert!((v.position.as_vec3() - glam::Vec3::from(*p)).length() < 1e-3);
    }
    // POSITION's bounds enclose every vertex (the spec requires them).
    let accessor = primitive.get(&gltf::Semantic::Positions).unwrap();
    let (min, max) = (accessor.min().unwrap(), accessor.max().unwrap());
    for k in 0..3 {
        let low = positions.iter().map(|p| p[k]).fold(f32::INFINITY, f32::min);
        let high = positions
            .iter()
            .map(|p| p[k])
            .fold(f32::NEG_INFINITY, f32::max);
        assert_eq!(min[k].as_f64().unwrap() as f32, low);
        assert_eq!(max[k].as_f64().unwrap() as f32, high);
    }

    // The same colours: COLOR_0 is the linear, exposed and clamped radiance.
    let colours: Vec<[f32; 3]> = reader.read_colors(0).unwrap().into_rgb_f32().collect();
    assert_eq!(colours.len(), solution.radiosity().len());
    let mut clipped = 0;
    for (colour, b) in colours.iter().zip(&solution.radiosity()) {
        let expected = display_colour(*b, &tone_map());
        for k in 0..3 {
            assert!(
                (colour[k] - expected[k]).abs() < 1e-6,
                "{colour:?} vs {expected:?}"
            );
        }
        clipped += usize::from(colour.contains(&1.0));
    }
    assert!(clipped > 0 && clipped < colours.len(), "{clipped} clipped");

    // The renderer's triangles, and flat unit normals.
    let indices: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
    let rendered = solution.triangles();
    assert_eq!(indices.len(), 3 * rendered.len());
    for (triangle, shaded) in indices.chunks(3).zip(&rendered) {
        for (&v, &p) in triangle.iter().zip(&shaded.positions) {
            assert_eq!(solver.mesh().vertices[v as usize].position, p);
        }
    }
    let normals: Vec<[f32; 3]> = reader.read_normals().unwrap().collect();
    assert!(
        normals
            .iter()
            .all(|n| (glam::Vec3::from(*n).length() - 1.0).abs() < 1e-5)
    );

    // The HDR radiance in the application-specific attribute.
    let radiance = primitive
        .attributes()
        .find(|(semantic, _)| semantic.to_string() == "_RADIANCE")
        .expect("a _RADIANCE attribute")
        .1;
    assert_eq!(radiance.count(), solver.mesh().vertices.len());
    assert_eq!(radiance.dimensions(), gltf::accessor::Dimensions::Vec3);
}

/// A PLY file read back: header lines, vertex records and faces.
struct Ply {
    header: Vec<String>,
    positions: Vec<[f32; 3]>,
    radiance: Vec<[f32; 3]>,
    colours: Vec<[u8; 3]>,
    faces: Vec<[u32; 3]>,
}

/// Reads the binary PLY layout isorad writes (and checks it is that one).
fn read_ply(bytes: &[u8]) -> Ply {
    let end = b"end_header\n";
    let header_end = bytes.windows(end.len()).position(|w| w == end).unwrap() + end.len();
    let header: Vec<String> = std::str::from_utf8(&bytes[..header_end])
        .unwrap()
        .lines()
        .map(str::to_owned)
        .collect();
    let count = |element: &str| -> usize {
        let prefix = format!("element {element} ");
        header
            .iter()
            .find_map(|l| l.strip_prefix(&prefix))
            .unwrap()
            .parse()
            .unwrap()
    };
    let (vertices, faces) = (count("vertex"), count("face"));
    let mut at = header_end;
    let f32_at = |bytes: &[u8], at: &mut usize| {
        let value = f32::from_le_bytes(bytes[*at..*at + 4].try_into().unwrap());
        *at += 4;
        value
    };
    let mut ply = Ply {
        header: header.clone(),
        positions: Vec::new(),
        radiance: Vec::new(),
        colours: Vec::new(),
        faces: Vec::new(),
    };
    for _ in 0..vertices {
        let floats: Vec<f32> = (0..9).map(|_| f32_at(bytes, &mut at)).collect();
        ply.positions.push([floats[0], floats[1], floats[2]]);
        ply.radiance.push([floats[6], floats[7], floats[8]]);
        ply.colours.push([bytes[at], bytes[at + 1], bytes[at + 2]]);
        at += 3;
    }
    for _ in 0..faces {
        assert_eq!(bytes[at], 3);
        at += 1;
        let index =
            |k: usize| u32::from_le_bytes(bytes[at + 4 * k..at + 4 * k + 4].try_into().unwrap());
        ply.faces.push([index(0), index(1), index(2)]);
        at += 12;
    }
    assert_eq!(at, bytes.len(), "no trailing bytes");
    ply
}

#[test]
fn ply_round_trips_positions_radiance_colours_and_faces() {
    let solver = solved_cornell();
    let solution = solver.solution(Ambient::Everywhere, &silent);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cornell.ply");
    let tone_map = tone_map();
    export_ply(&solution, &tone_map, &path).unwrap();
    let ply = read_ply(&std::fs::read(&path).unwrap());
    assert_eq!(ply.header[1], "format binary_little_endian 1.0");
    for property in ["radiance_r", "radiance_g", "radiance_b", "red", "nx"] {
        assert!(
            ply.header
                .iter()
                .any(|l| l.ends_with(&format!(" {property}"))),
            "{property}"
        );
    }
    assert_eq!(ply.positions.len(), solver.mesh().vertices.len());
    for (k, vertex) in solver.mesh().vertices.iter().enumerate() {
        assert_eq!(
            glam::Vec3::from(ply.positions[k]),
            vertex.position.as_vec3()
        );
        let radiance = solution.radiosity_at(k) / std::f64::consts::PI;
        let expected = glam::Vec3::from_array(radiance.to_f32_array());
        assert!(
            (glam::Vec3::from(ply.radiance[k]) - expected).length() <= 1e-6 * expected.length()
        );
        // The PNG's pixel value for that radiance.
        assert_eq!(
            ply.colours[k],
            radiance.to_array().map(|c| tone_map.map_channel(c))
        );
    }
    let rendered = solution.triangles();
    assert_eq!(ply.faces.len(), rendered.len());
    for (face, shaded) in ply.faces.iter().zip(&rendered) {
        let corners = face.map(|v| solver.mesh().vertices[v as usize].position);
        assert_eq!(corners, shaded.positions);
    }
}

#[test]
fn unknown_extension_is_refused() {
    let solver = solved_cornell();
    let solution = solver.solution(Ambient::Everywhere, &silent);
    let error = export_solution(&solution, &tone_map(), Path::new("out.obj")).unwrap_err();
    assert!(error.to_string().contains(".ply or .glb"), "{error}");
}

#[test]
fn render_exports_several_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_isorad"))
        .current_dir(dir.path())
        .args([
            "render",
            "--width",
            "32",
            "--height",
            "32",
            "--tolerance",
            "0.1",
            "-q",
            "--export",
            "box.glb",
            "--export",
            "box.ply",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let glb = std::fs::read(dir.path().join("box.glb")).unwrap();
    assert!(gltf::Gltf::from_slice(&glb).is_ok());
    assert!(
        std::fs::read(dir.path().join("box.ply"))
            .unwrap()
            .starts_with(b"ply\n")
    );
    // A bad extension fails before solving, and writes nothing.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_isorad"))
        .current_dir(dir.path())
        .args(["render", "-q", "--export", "box.stl", "--png", "x.png"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("box.stl"));
    assert!(!dir.path().join("x.png").exists());
}
