//! Tests of `clean_polygon` and the plane helpers.

use super::*;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

#[test]
fn plane_of_a_tilted_square() {
    let square = [v(0., 0., 0.), v(2., 0., 0.), v(2., 2., 1.), v(0., 2., 1.)];
    let plane = best_fit_plane(&square).unwrap();
    assert!(plane.max_deviation < 1e-12);
    assert!((plane.area - 2.0 * 5f64.sqrt()).abs() < 1e-12);
    assert!((plane.diameter - 3.0).abs() < 1e-12);
    let n = plane.frame.normal;
    assert!((n - v(0., -1., 2.).normalize()).length() < 1e-12);
}

#[test]
fn projection_lands_on_the_plane() {
    let quad = [v(0., 0., 0.), v(1., 0., 0.1), v(1., 1., 0.), v(0., 1., 0.1)];
    let plane = best_fit_plane(&quad).unwrap();
    assert!((plane.max_deviation - 0.05).abs() < 1e-12);
    for p in project_onto_plane(&quad, &plane.frame) {
        assert!(plane.frame.height(p).abs() < 1e-12);
    }
}

#[test]
fn nearly_planar_face_is_projected_silently() {
    let quad = [
        v(0., 0., 0.),
        v(10., 0., 0.05),
        v(10., 10., 0.),
        v(0., 10., 0.05),
    ];
    let cleaned = clean_polygon("wall", 3, &quad);
    assert_eq!(cleaned.surfaces.len(), 1);
    assert!(cleaned.warning.is_none());
    assert_eq!(cleaned.surfaces[0].material, 3);
    assert!((cleaned.surfaces[0].area() - 100.0).abs() < 0.01);
}

#[test]
fn non_planar_face_is_split_with_warning() {
    let quad = [v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.3), v(0., 1., 0.)];
    let cleaned = clean_polygon("bent", 0, &quad);
    assert_eq!(cleaned.surfaces.len(), 2);
    let warning = cleaned.warning.unwrap();
    assert!(warning.contains("`bent`") && warning.contains("2 triangles"));
    for s in &cleaned.surfaces {
        assert!(s.normal().z > 0.9, "triangles keep the face's front side");
    }
}

#[test]
fn repeated_and_degenerate_faces() {
    let repeated = [
        v(0., 0., 0.),
        v(0., 0., 0.),
        v(1., 0., 0.),
        v(0., 1., 0.),
        v(0., 0., 0.),
    ];
    let cleaned = clean_polygon("r", 0, &repeated);
    assert_eq!(cleaned.surfaces[0].vertices().len(), 3);
    assert!(cleaned.warning.is_none());
    let two = [v(0., 0., 0.), v(1., 0., 0.), v(1., 0., 0.)];
    let cleaned = clean_polygon("two", 0, &two);
    assert!(cleaned.surfaces.is_empty());
    assert!(cleaned.warning.unwrap().contains("`two`"));
    let line = [v(0., 0., 0.), v(1., 0., 0.), v(2., 0., 0.)];
    let cleaned = clean_polygon("line", 0, &line);
    assert!(cleaned.surfaces.is_empty());
    assert!(cleaned.warning.unwrap().contains("area is zero"));
}

fn flat(points: &[(f64, f64)]) -> Vec<DVec3> {
    points.iter().map(|&(x, y)| v(x, y, 0.)).collect()
}

fn total_area(cleaned: &CleanedPolygon) -> f64 {
    cleaned.surfaces.iter().map(Surface::area).sum()
}

#[test]
fn keyhole_is_split_into_triangles_covering_it_once() {
    // A 10 × 10 square with a 4 × 4 hole, joined by a bridge along y = 5.
    let keyhole = flat(&[
        (0., 0.),
        (10., 0.),
        (10., 10.),
        (0., 10.),
        (0., 5.),
        (3., 5.),
        (3., 7.),
        (7., 7.),
        (7., 3.),
        (3., 3.),
        (3., 5.),
        (0., 5.),
    ]);
    let cleaned = clean_polygon("slab", 0, &keyhole);
    assert!((total_area(&cleaned) - 84.0).abs() < 1e-9, "{cleaned:?}");
    let warning = cleaned.warning.unwrap();
    assert!(warning.contains("`slab`") && warning.contains("touches itself"));
    assert!(cleaned.surfaces.iter().all(|s| s.normal().z > 0.99));
}

#[test]
fn two_squares_meeting_at_a_corner_are_kept() {
    let pinched = flat(&[
        (0., 0.),
        (1., 0.),
        (1., 1.),
        (2., 1.),
        (2., 2.),
        (1., 2.),
        (1., 1.),
        (0., 1.),
    ]);
    let cleaned = clean_polygon("pinched", 0, &pinched);
    assert!((total_area(&cleaned) - 2.0).abs() < 1e-12, "{cleaned:?}");
}

#[test]
fn outline_going_twice_round_some_area_is_skipped() {
    // A triangle lobe folded back inside a 10 × 5 rectangle, touching
    // it at (0, 0) and (5, 0) without crossing (found by fuzzing: the
    // meshers covered 40 of its 60 units of shoelace area).
    let folded = flat(&[
        (0., 0.),
        (5., 0.),
        (10., 4.),
        (0., 0.),
        (5., 0.),
        (10., 0.),
        (10., 5.),
        (0., 5.),
        (0., 0.),
        (5.04, 0.),
    ]);
    let cleaned = clean_polygon("folded", 0, &folded);
    assert!(cleaned.surfaces.is_empty(), "{cleaned:?}");
    let warning = cleaned.warning.unwrap();
    assert!(warning.contains("touches itself") && warning.contains("twice"));
}

#[test]
fn simple_outlines_do_not_touch() {
    let l_shape = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)];
    let points: Vec<DVec2> = l_shape.iter().map(|&(x, y)| DVec2::new(x, y)).collect();
    assert_eq!(first_touch(&points), None);
    let cleaned = clean_polygon("l", 0, &flat(&l_shape));
    assert_eq!(cleaned.surfaces.len(), 1);
    assert!(cleaned.warning.is_none());
}
