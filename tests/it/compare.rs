//! `isorad compare`'s study on a shadowed receiver: the floor under
//! `scenes/table`'s table and small tilted lamp, measured against the exact
//! direct field with occlusion.

use isorad::{
    Settings, SurfaceId,
    lighting::{area_lights, dominant_field},
    load_scene,
    scene::Visibility,
    study::{CompareSettings, MeshSpec, ReceiverComparison, compare_receiver},
};

/// The id of the surface named `name`.
fn surface_named(scene: &isorad::Scene, name: &str) -> SurfaceId {
    SurfaceId::new(scene.surfaces.iter().position(|s| s.name == name).unwrap())
}

/// The table floor compared with square 30 × 30 and the seed's 10 × 3
/// layout, without and with the shadow boundaries.
fn table_floor() -> ReceiverComparison {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let loaded = load_scene(root.join("scenes/table/table.toml").to_str().unwrap()).unwrap();
    let scene = &loaded.scene;
    let visibility = Visibility::new(scene);
    let lamps = area_lights(scene);
    let floor = surface_named(scene, "floor");
    let field = dominant_field(scene, floor, &lamps, 0).unwrap();
    let mut settings = CompareSettings::default();
    settings.square_sizes = vec![30, 40];
    settings.contour_sizes = vec![(10, 3)];
    settings.contour_errors_per_mille = Vec::new();
    settings.grid = 200;
    settings.mesh = Settings::from_scene_options(&loaded.options).unwrap().mesh;
    compare_receiver(scene, &visibility, floor, &[field], &settings)
}

#[test]
fn shadow_aware_contour_meshes_need_five_times_fewer_vertices_than_square_30_under_a_table() {
    let comparison = table_floor();
    let record = |spec| comparison.record(spec).unwrap();
    let square = record(MeshSpec::Square { n: 30 });
    let finer_square = record(MeshSpec::Square { n: 40 });
    let seed = record(MeshSpec::Contour {
        directions: 10,
        levels: 3,
    });
    let shadow_aware = record(MeshSpec::ShadowContour {
        directions: 10,
        levels: 3,
    });
    // The seed's layout alone smears the table's shadow: worse than square
    // 30 × 30 (0.156 against 0.096 when measured).
    assert!(seed.rms_rel_error > square.rms_rel_error);
    // With the shadow boundaries as edges it beats even square 40 × 40
    // (0.074 against 0.079), with at least five times fewer vertices than
    // square 30 × 30 (189 against 961).
    assert!(
        shadow_aware.rms_rel_error < finer_square.rms_rel_error,
        "{} against {}",
        shadow_aware.rms_rel_error,
        finer_square.rms_rel_error
    );
    let fewer = square.vertex_count() as f64 / shadow_aware.vertex_count() as f64;
    assert!(fewer >= 5.0, "{fewer:.2}× fewer vertices");
    // Its boundaries have vertices at their ends and where they cross the
    // rings, not at the element spacing: 98 more than the seed's layout's
    // 91 (at the spacing, 228 more).
    assert!(shadow_aware.vertex_count() > seed.vertex_count());
    assert!(shadow_aware.vertex_count() < 3 * seed.vertex_count());
}

/// A quad as an OBJ object, wound so that its normal is `normal`.
fn obj_quad(
    obj: &mut String,
    name: &str,
    material: &str,
    corners: [[f64; 3]; 4],
    normal: [f64; 3],
) {
    use glam::DVec3;
    let c = corners.map(DVec3::from);
    let facing = (c[1] - c[0]).cross(c[2] - c[0]).dot(DVec3::from(normal));
    let order = if facing > 0.0 {
        [0, 1, 2, 3]
    } else {
        [3, 2, 1, 0]
    };
    obj.push_str(&format!("o {name}\nusemtl {material}\n"));
    for k in order {
        obj.push_str(&format!("v {} {} {}\n", c[k].x, c[k].y, c[k].z));
    }
    obj.push_str("f -4 -3 -2 -1\n");
}

/// A box from `lo` to `hi` (no bottom where it stands on the floor).
fn obj_box(obj: &mut String, name: &str, lo: [f64; 3], hi: [f64; 3]) {
    let ([x0, y0, z0], [x1, y1, z1]) = (lo, hi);
    let faces = [
        (
            [[x0, y1, z0], [x0, y1, z1], [x1, y1, z1], [x1, y1, z0]],
            [0.0, 1.0, 0.0],
        ),
        (
            [[x0, y0, z0], [x0, y0, z1], [x1, y0, z1], [x1, y0, z0]],
            [0.0, -1.0, 0.0],
        ),
        (
            [[x0, y0, z0], [x0, y1, z0], [x0, y1, z1], [x0, y0, z1]],
            [-1.0, 0.0, 0.0],
        ),
        (
            [[x1, y0, z0], [x1, y1, z0], [x1, y1, z1], [x1, y0, z1]],
            [1.0, 0.0, 0.0],
        ),
        (
            [[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0]],
            [0.0, 0.0, -1.0],
        ),
        (
            [[x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]],
            [0.0, 0.0, 1.0],
        ),
    ];
    for (corners, normal) in faces {
        if normal[1] < 0.0 && y0 == 0.0 {
            continue;
        }
        obj_quad(obj, name, "wood", corners, normal);
    }
}

/// A 6 × 5 m office floor under six 0.6 m ceiling panels 2.8 m up, with
/// two desks (each a top on a pedestal) and two chairs' seats as boxes.
fn six_light_floor() -> ReceiverComparison {
    let dir = tempfile::tempdir().unwrap();
    let mut obj = String::from("mtllib office.mtl\n");
    obj_quad(
        &mut obj,
        "floor",
        "floor",
        [
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 5.0],
            [6.0, 0.0, 5.0],
            [6.0, 0.0, 0.0],
        ],
        [0.0, 1.0, 0.0],
    );
    for (i, x) in [1.5, 3.0, 4.5].into_iter().enumerate() {
        for (j, z) in [1.5, 3.5].into_iter().enumerate() {
            let corners = [
                [x - 0.3, 2.8, z - 0.3],
                [x - 0.3, 2.8, z + 0.3],
                [x + 0.3, 2.8, z + 0.3],
                [x + 0.3, 2.8, z - 0.3],
            ];
            obj_quad(
                &mut obj,
                &format!("lamp_{i}{j}"),
                "lamp",
                corners,
                [0.0, -1.0, 0.0],
            );
        }
    }
    for (k, (x, z)) in [(1.2, 1.0), (3.2, 3.0)].into_iter().enumerate() {
        obj_box(
            &mut obj,
            &format!("desk_{k}"),
            [x, 0.72, z],
            [x + 1.6, 0.75, z + 0.8],
        );
        let pedestal = ([x + 1.15, 0.0, z + 0.1], [x + 1.55, 0.72, z + 0.7]);
        obj_box(&mut obj, &format!("pedestal_{k}"), pedestal.0, pedestal.1);
        let chair = ([x + 0.5, 0.0, z + 0.9], [x + 1.0, 0.45, z + 1.35]);
        obj_box(&mut obj, &format!("chair_{k}"), chair.0, chair.1);
    }
    let mtl = "newmtl floor\nKd 0.5 0.5 0.5\n\nnewmtl wood\nKd 0.6 0.45 0.3\n\n\
               newmtl lamp\nKd 0 0 0\nKe 10 10 10\n";
    std::fs::write(dir.path().join("office.obj"), obj).unwrap();
    std::fs::write(dir.path().join("office.mtl"), mtl).unwrap();
    let loaded = load_scene(dir.path().join("office.obj").to_str().unwrap()).unwrap();
    let scene = &loaded.scene;
    let visibility = Visibility::new(scene);
    let lamps = area_lights(scene);
    assert_eq!(lamps.len(), 6);
    let floor = surface_named(scene, "floor");
    let fields: Vec<_> = (0..lamps.len())
        .filter_map(|k| dominant_field(scene, floor, &lamps, k))
        .collect();
    assert_eq!(fields.len(), 6);
    let mut settings = CompareSettings::default();
    settings.square_sizes = vec![20, 30, 40];
    settings.contour_errors_per_mille = Vec::new();
    settings.grid = 200;
    compare_receiver(scene, &visibility, floor, &fields, &settings)
}

#[test]
fn greedy_insertion_needs_three_times_fewer_vertices_than_square_30_under_six_lights() {
    let comparison = six_light_floor();
    let square = comparison.record(MeshSpec::Square { n: 30 }).unwrap();
    let greedy = |spec: &MeshSpec| matches!(spec, MeshSpec::Greedy { .. });
    // 119 vertices when measured, 8.0× fewer than square 30 × 30's 961
    // (5.9× by the mean relative error).
    let vertices = comparison
        .vertices_for_error(greedy, square.rms_rel_error)
        .unwrap();
    let fewer = square.vertex_count() as f64 / vertices;
    assert!(fewer >= 3.0, "{fewer:.2}× fewer vertices");
    // And by the mean relative error where B is above 1 % of its maximum.
    let by_mean = comparison
        .vertices_for_measure(greedy, |r| r.mean_rel_error, square.mean_rel_error)
        .unwrap();
    let fewer = square.vertex_count() as f64 / by_mean;
    assert!(
        fewer >= 3.0,
        "{fewer:.2}× fewer vertices by the mean relative error"
    );
    // Every budget holds, and each larger one errs less.
    let mut budgets: Vec<_> = comparison
        .records
        .iter()
        .filter(|r| greedy(&r.spec))
        .collect();
    budgets.sort_by_key(|r| r.vertex_count());
    assert_eq!(budgets.len(), 6);
    for pair in budgets.windows(2) {
        let MeshSpec::Greedy { vertices } = pair[1].spec else {
            unreachable!()
        };
        assert!(pair[1].vertex_count() <= vertices);
        assert!(pair[1].rms_rel_error < pair[0].rms_rel_error);
    }
}
