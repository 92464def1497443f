//! Integration tests of the comparison pictures: log–log plots (SVG, PNG)
//! and meshes side by side, read back and checked pixel by pixel against the
//! documented layout and the sRGB curve.

use std::path::Path;

use glam::DVec2;
use isorad::{
    Error,
    render::srgb_encode,
    study::{MeshPanel, Series, write_loglog_plot, write_mesh_panels},
};

/// Header band above each mesh panel and gap between panels, pixels (as
/// documented on `write_mesh_panels`).
const HEADER: u32 = 48;
const GAP: u32 = 4;
const BACKGROUND: [u8; 3] = [40, 40, 40];
const WIREFRAME: [u8; 3] = [255, 140, 0];
const OUTLINE: [u8; 3] = [90, 180, 255];

fn two_series() -> Vec<Series> {
    vec![
        Series {
            name: "square mesh".into(),
            points: vec![
                (121.0, 0.09),
                (441.0, 0.04),
                (961.0, 0.021),
                (3721.0, 0.008),
            ],
        },
        Series {
            name: "contour mesh".into(),
            points: vec![(401.0, 0.012), (101.0, 0.035), (1601.0, 0.004)],
        },
    ]
}

/// The files in `dir`, to check that no temporary file is left behind.
fn entries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .expect("readable directory")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect()
}

#[test]
fn png_and_svg_plots_are_written_and_read_back() {
    let dir = tempfile::tempdir().expect("temporary directory");

    let png = dir.path().join("error.png");
    write_loglog_plot(&png, "Cornell box", "vertices", "RMS error", &two_series())
        .expect("PNG plot written");
    let image = image::open(&png).expect("a PNG").to_rgb8();
    assert_eq!(image.dimensions(), (900, 600));
    let first = *image.get_pixel(0, 0);
    assert!(image.pixels().any(|p| *p != first), "all one colour");
    // Both series colours appear (Tableau blue and orange).
    let has = |rgb: [u8; 3]| image.pixels().any(|p| p.0 == rgb);
    assert!(has([31, 119, 180]) && has([255, 127, 14]));

    let svg_path = dir.path().join("error.svg");
    write_loglog_plot(
        &svg_path,
        "Cornell box",
        "vertices",
        "RMS error",
        &two_series(),
    )
    .expect("SVG plot written");
    let svg = std::fs::read_to_string(&svg_path).expect("readable SVG");
    assert!(svg.contains("<svg"));
    assert!(svg.contains("square mesh") && svg.contains("contour mesh"));
    assert!(svg.contains("RMS error") && svg.contains("Cornell box"));

    let mut names = entries(dir.path());
    names.sort();
    assert_eq!(names, ["error.png", "error.svg"]);
}

#[test]
fn unplottable_points_are_skipped_and_empty_plots_still_written() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let mixed = vec![
        Series {
            name: "mixed".into(),
            points: vec![
                (0.0, 1.0),
                (-1.0, 2.0),
                (f64::NAN, 3.0),
                (1.0, f64::INFINITY),
                (10.0, 0.5),
                (100.0, 0.1),
                (1000.0, -0.1),
            ],
        },
        Series {
            name: "nothing left".into(),
            points: vec![(f64::NAN, f64::NAN), (0.0, 0.0)],
        },
    ];
    for name in ["mixed.png", "mixed.svg"] {
        let path = dir.path().join(name);
        write_loglog_plot(&path, "mixed", "x", "y", &mixed).expect("plot written");
        assert!(std::fs::metadata(&path).expect("file").len() > 0);
    }

    // Nothing at all: a valid file that says so.
    let empty_png = dir.path().join("empty.png");
    write_loglog_plot(&empty_png, "empty", "x", "y", &[]).expect("empty PNG plot");
    assert_eq!(
        image::open(&empty_png)
            .expect("a PNG")
            .to_rgb8()
            .dimensions(),
        (900, 600)
    );
    let empty_svg = dir.path().join("empty.svg");
    write_loglog_plot(&empty_svg, "empty", "x", "y", &mixed[1..]).expect("empty SVG plot");
    let svg = std::fs::read_to_string(&empty_svg).expect("readable SVG");
    assert!(svg.contains("<svg") && svg.contains("no positive, finite data"));
}

#[test]
fn a_plot_needs_a_known_extension() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join("error.pdf");
    let result = write_loglog_plot(&path, "t", "x", "y", &two_series());
    assert!(matches!(result, Err(Error::Output { .. })), "{result:?}");
    assert!(entries(dir.path()).is_empty());
}

/// The unit square split along its diagonal into two triangles, with the
/// field v = x (0, 1, 1, 0 at the corners).
fn unit_square(title: &str) -> MeshPanel {
    let corners = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(1.0, 1.0),
        DVec2::new(0.0, 1.0),
    ];
    MeshPanel {
        title: title.into(),
        points: corners.clone(),
        values: vec![0.0, 1.0, 1.0, 0.0],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        outline: corners,
    }
}

/// `panels` written side by side in squares of `size` pixels, read back.
fn drawn(panels: &[MeshPanel], size: u32) -> image::RgbImage {
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join("panels.png");
    write_mesh_panels(&path, panels, size).expect("panels written");
    image::open(&path).expect("a PNG").to_rgb8()
}

#[test]
fn mesh_panels_shade_the_field_and_draw_the_wireframe() {
    const SIZE: u32 = 160;
    let image = drawn(&[unit_square("square 1×1"), unit_square("again")], SIZE);
    assert_eq!(image.dimensions(), (2 * SIZE + GAP, HEADER + SIZE));
    let pixel = |x: u32, y: u32| image.get_pixel(x, y).0;

    // The unit square fills the panel less a margin of SIZE/16 = 10 pixels:
    // x = 0 at column left + 10, x = 1 at left + 150; y = 1 at row 58,
    // y = 0 at row 198.
    let margin = f64::from(SIZE / 16);
    let span = f64::from(SIZE) - 2.0 * margin;
    for left in [0, SIZE + GAP] {
        // The field at pixel centres away from every edge: v = x, grey = srgb(v)
        // (the largest value is 1).
        for (x, y) in [(0.5, 0.25), (0.25, 0.75), (0.75, 0.4)] {
            let column = left + (margin + x * span) as u32;
            let row = HEADER + (margin + (1.0 - y) * span) as u32;
            let v = (f64::from(column - left) + 0.5 - margin) / span;
            let expected = 255.0 * srgb_encode(v);
            let [r, g, b] = pixel(column, row);
            assert!(r == g && g == b, "grey expected, got {:?}", [r, g, b]);
            assert!(
                (f64::from(r) - expected).abs() <= 1.0,
                "at ({x}, {y}): {r} vs {expected:.1}"
            );
        }

        // The diagonal (t, t) is a triangle edge: orange within a pixel.
        for k in 1..10 {
            let t = f64::from(k) / 10.0;
            let column = left + (margin + t * span) as u32;
            let row = HEADER + (margin + (1.0 - t) * span) as u32;
            let near = (row - 1..=row + 1).map(|r| pixel(column, r));
            assert!(
                near.clone().any(|p| p == WIREFRAME),
                "no wireframe near ({t}, {t}): {:?}",
                near.collect::<Vec<_>>()
            );
        }

        // The outline along y = 0, and background outside the square.
        let bottom = HEADER + (margin + span) as u32;
        assert_eq!(pixel(left + SIZE / 2, bottom), OUTLINE);
        assert_eq!(pixel(left + 3, HEADER + 3), BACKGROUND);
        assert_eq!(pixel(left + SIZE - 3, HEADER + SIZE - 3), BACKGROUND);
    }
    // The gap between panels is background too, and the header holds text.
    assert_eq!(pixel(SIZE + GAP / 2, HEADER + SIZE / 2), BACKGROUND);
    let header_lit = (0..SIZE)
        .flat_map(|x| (0..HEADER).map(move |y| (x, y)))
        .filter(|&(x, y)| pixel(x, y)[0] > 150)
        .count();
    assert!(header_lit > 50, "{header_lit} bright header pixels");
}

#[test]
fn values_are_normalised_over_all_panels() {
    const SIZE: u32 = 160;
    // The second panel's field is twice the first: the first shows v/2.
    let mut brighter = unit_square("brighter");
    brighter.values = vec![0.0, 2.0, 2.0, 0.0];
    let image = drawn(&[unit_square("dim"), brighter], SIZE);
    let (column, row) = (80, HEADER + 115);
    let v = (f64::from(column) + 0.5 - 10.0) / 140.0;
    let dim = f64::from(image.get_pixel(column, row).0[0]);
    let bright = f64::from(image.get_pixel(column + SIZE + GAP, row).0[0]);
    assert!((dim - 255.0 * srgb_encode(0.5 * v)).abs() <= 1.0, "{dim}");
    assert!((bright - 255.0 * srgb_encode(v)).abs() <= 1.0, "{bright}");
}

#[test]
fn clockwise_triangles_are_shaded_and_far_lines_stay_in_their_square() {
    const SIZE: u32 = 160;
    // Clockwise triangles, and a sliver along y = 0.5 reaching far out.
    let mut odd = unit_square("clockwise");
    odd.triangles = vec![[0, 2, 1], [0, 3, 2]];
    odd.points.extend([
        DVec2::new(-1e6, 0.5),
        DVec2::new(1e6, 0.5),
        DVec2::new(1e300, 0.5),
    ]);
    odd.triangles.extend([[4, 5, 6]]);
    let start = std::time::Instant::now();
    let image = drawn(&[odd, unit_square("plain")], SIZE);
    assert!(start.elapsed().as_secs() < 10, "far lines took too long");
    let pixel = |x: u32, y: u32| image.get_pixel(x, y).0;

    // Both panels show the same field away from the edges.
    for (column, row) in [(80, HEADER + 115), (40, HEADER + 50)] {
        assert_eq!(pixel(column, row), pixel(column + SIZE + GAP, row));
        assert_ne!(pixel(column, row), BACKGROUND);
    }
    // The sliver's edge y = 0.5 (row 48 + 10 + 70) crosses the first square
    // from side to side and stops there: the gap and the second panel keep
    // their own pixels.
    let row = HEADER + 80;
    for column in [0, 5, 80, 155, SIZE - 1] {
        assert_eq!(pixel(column, row), WIREFRAME, "column {column}");
    }
    for column in SIZE..SIZE + GAP {
        assert_eq!(pixel(column, row), BACKGROUND);
    }
    assert_eq!(pixel(SIZE + GAP + 3, row), BACKGROUND);
}

#[test]
fn degenerate_panels_are_drawn_without_panic() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join("degenerate.png");
    let mut odd = unit_square("odd");
    odd.points.push(DVec2::new(f64::NAN, 0.5));
    odd.points.push(DVec2::new(0.5, 0.5));
    odd.values = vec![f64::NAN, 1.0, f64::INFINITY, -3.0];
    odd.triangles
        .extend([[0, 1, 9], [0, 0, 2], [0, 1, 4], [0, 2, 5], [5, 5, 5]]);
    let panels = [
        MeshPanel::default(),
        odd,
        MeshPanel {
            title: "a single point".into(),
            points: vec![DVec2::new(3.0, 4.0)],
            ..MeshPanel::default()
        },
    ];
    write_mesh_panels(&path, &panels, 64).expect("panels written");
    let image = image::open(&path).expect("a PNG").to_rgb8();
    assert_eq!(image.dimensions(), (3 * 64 + 2 * GAP, HEADER + 64));
    // The empty panel is all background.
    assert_eq!(image.get_pixel(32, HEADER + 32).0, BACKGROUND);

    let none = write_mesh_panels(&dir.path().join("none.png"), &[], 64);
    assert!(matches!(none, Err(Error::Output { .. })), "{none:?}");
    let tiny = write_mesh_panels(&dir.path().join("tiny.png"), &panels, 0);
    assert!(matches!(tiny, Err(Error::Output { .. })), "{tiny:?}");
    assert_eq!(entries(dir.path()), ["degenerate.png"]);
}

#[test]
fn writing_into_a_missing_directory_fails_cleanly() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let missing = dir.path().join("missing");
    for name in ["plot.png", "plot.svg"] {
        let result = write_loglog_plot(&missing.join(name), "t", "x", "y", &two_series());
        assert!(matches!(result, Err(Error::Io { .. })), "{result:?}");
    }
    let result = write_mesh_panels(&missing.join("panels.png"), &[unit_square("s")], 64);
    assert!(matches!(result, Err(Error::Io { .. })), "{result:?}");
    assert!(!missing.exists());
    assert!(entries(dir.path()).is_empty());
}
