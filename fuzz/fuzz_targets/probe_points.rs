//! The probe points CSV: `parse_probe_points` must return finite points
//! (unit normals, in-range line numbers) or an error naming a line.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let lines = text.lines().count();
    match isorad::scene::parse_probe_points(&text, std::path::Path::new("points.csv")) {
        Ok(points) => {
            for point in points {
                assert!(point.position.is_finite());
                assert!((1..=lines).contains(&point.line));
                if let Some(n) = point.normal {
                    assert!((n.length() - 1.0).abs() < 1e-9, "{n}");
                }
            }
        }
        Err(e) => assert!(e.to_string().starts_with("points.csv:"), "{e}"),
    }
});
