//! The daylight of a scene in words: its sky, its sun, and where isorad
//! found the light can come in (`render` and `info` print it).

use isorad::Scene;
use isorad::lighting::{PortalKind, Portals};

use crate::table::significant;

/// Lines describing the scene's daylight and its portals; none without a
/// `[sky]`. `portals` are the scene's ([`Portals::of_scene`]).
pub fn daylight_lines(scene: &Scene, portals: &Portals) -> Vec<String> {
    let Some(daylight) = &scene.daylight else {
        return Vec::new();
    };
    let mut lines = vec![format!(
        "daylight: {}, {} lx on the open horizontal plane (zenith {} cd/m²), ground reflectance {}",
        daylight.sky.model.name(),
        significant(daylight.sky_horizontal_illuminance()),
        significant(daylight.sky.zenith_luminance),
        daylight.ground_reflectance
    )];
    if let Some(sun) = daylight.sun {
        lines.push(format!(
            "sun: altitude {:.2}°, azimuth {:.2}° from north, {} lx direct normal{}",
            sun.position.altitude.to_degrees(),
            sun.position.azimuth.to_degrees(),
            significant(sun.normal_illuminance),
            if daylight.sun_direction().is_none() {
                " (no beam)"
            } else {
                ""
            }
        ));
    }
    let openings: Vec<String> = portals
        .portals
        .iter()
        .filter(|p| p.kind == PortalKind::Opening)
        .map(|p| {
            let corners: Vec<_> = p.triangles.iter().flatten().collect();
            let centre = corners.iter().copied().sum::<glam::DVec3>() / corners.len() as f64;
            let area: f64 = p
                .triangles
                .iter()
                .map(|t| (t[1] - t[0]).cross(t[2] - t[0]).length() / 2.0)
                .sum();
            format!(
                "({} {} {}) {} m²",
                significant(centre.x),
                significant(centre.y),
                significant(centre.z),
                significant(area)
            )
        })
        .collect();
    let panes = portals.portals.len() - openings.len();
    lines.push(format!(
        "daylight enters through {} opening(s){}{} and {panes} glazing surface(s)",
        openings.len(),
        if openings.is_empty() { "" } else { ": " },
        openings
            .iter()
            .take(8)
            .cloned()
            .collect::<Vec<_>>()
            .join(", ")
    ));
    if openings.len() > 8 {
        lines.push(format!("  … and {} more openings", openings.len() - 8));
    }
    lines
}
