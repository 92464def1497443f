//! Probe points: where a user wants the solution read, from a CSV file.

use glam::DVec3;
use std::path::Path;

use crate::error::{Error, Result};

/// A point at which to read the solution, as a lighting designer's sensor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbePoint {
    /// Position, on a surface of the scene.
    pub position: DVec3,
    /// Optional unit normal: picks among surfaces meeting at the point (a
    /// corner) and must agree with the chosen surface's front.
    pub normal: Option<DVec3>,
    /// 1-based line of the file it came from (0 when built in code).
    pub line: usize,
}

/// Parses probe points: one per line, `x,y,z` or `x,y,z,nx,ny,nz`. Blank
/// lines and lines starting with `#` are skipped, and so is a first line
/// that is a header (`x,y,z…`). `path` only names the file in errors.
pub fn parse_probe_points(text: &str, path: &Path) -> Result<Vec<ProbePoint>> {
    let error = |line: usize, message: String| Error::ProbePoint {
        path: path.to_path_buf(),
        line,
        message,
    };
    let mut points = Vec::new();
    for (index, raw) in text.lines().enumerate() {
        let line = index + 1;
        let content = raw.trim();
        if content.is_empty() || content.starts_with('#') {
            continue;
        }
        if points.is_empty() && content.to_ascii_lowercase().starts_with('x') {
            continue;
        }
        let fields: Vec<&str> = content.split(',').map(str::trim).collect();
        if fields.len() != 3 && fields.len() != 6 {
            return Err(error(
                line,
                format!(
                    "expected 3 or 6 comma-separated numbers, found {}",
                    fields.len()
                ),
            ));
        }
        let mut numbers = [0.0; 6];
        for (k, field) in fields.iter().enumerate() {
            numbers[k] = field
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| error(line, format!("`{field}` is not a finite number")))?;
        }
        let normal = if fields.len() == 6 {
            let n = DVec3::new(numbers[3], numbers[4], numbers[5]);
            let length = n.length();
            if !(length.is_finite() && length > 0.0) {
                return Err(error(line, "the normal has zero length".into()));
            }
            Some(n / length)
        } else {
            None
        };
        points.push(ProbePoint {
            position: DVec3::new(numbers[0], numbers[1], numbers[2]),
            normal,
            line,
        });
    }
    Ok(points)
}

/// Reads and parses a probe-points file.
pub fn load_probe_points(path: &Path) -> Result<Vec<ProbePoint>> {
    parse_probe_points(&super::source::read_text(path)?, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_with_and_without_normals() {
        let text = "x,y,z,nx,ny,nz\n# a comment\n1,2,3\n\n4, 5, 6, 0, 0, 2\n";
        let points = parse_probe_points(text, Path::new("p.csv")).unwrap();
        assert_eq!(points.len(), 2);
        assert_eq!(points[0].position, DVec3::new(1.0, 2.0, 3.0));
        assert_eq!(points[0].line, 3);
        assert_eq!(points[1].normal, Some(DVec3::Z));
    }

    #[test]
    fn errors_name_the_line() {
        for (text, line) in [
            ("1,2\n", 1),
            ("1,2,3\n1,nan,3\n", 2),
            ("1,2,3,0,0,0\n", 1),
            ("1,2,3\nx,y,z\n", 2),
        ] {
            let message = parse_probe_points(text, Path::new("p.csv"))
                .unwrap_err()
                .to_string();
            assert!(message.starts_with(&format!("p.csv:{line}:")), "{message}");
        }
    }
}
