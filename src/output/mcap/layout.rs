//! The Foxglove layout written beside a run's MCAP: the shipped layout
//! (docs/foxglove/wetbounce_layout.json: the 3D panel, the heights, the contacts on the
//! timeline and in a log) with its camera and grid fitted to this scene. Foxglove cannot fit a
//! camera to what a file holds, and one fixed camera either shows a 0.5 m column or a 3 mm drop,
//! never both.

use glam::DVec3;
use serde_json::{Value, json};

/// The shipped layout, the template of every run's.
pub const TEMPLATE: &str = include_str!("../../../docs/foxglove/wetbounce_layout.json");

/// The layout's file name beside `<stem>.mcap`.
pub fn file_name(stem: &str) -> String {
    format!("{stem}_foxglove_layout.json")
}

/// The smallest 1, 2 or 5 × 10^k that is at least `x` (> 0): a grid size a reader can count.
fn round_up_125(x: f64) -> f64 {
    let decade = 10f64.powf(x.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * decade)
        .find(|s| *s >= x * (1.0 - 1e-12))
        .unwrap_or(10.0 * decade)
}

/// The shipped layout with the 3D panel's camera on `center`, far enough to see a sphere of
/// radius `half` whole (45° of view: `half / sin 22.5°` is 2.6 `half`, rounded up to 3), and the
/// grid of 20 divisions under it, as wide as the scene rounded up to 1, 2 or 5 × 10^k metres.
pub fn fitted(center: DVec3, half: f64) -> String {
    let mut layout: Value = serde_json::from_str(TEMPLATE).expect("the shipped layout is JSON");
    let panel = &mut layout["configById"]["3D!wetbounce"];
    let camera = &mut panel["cameraState"];
    camera["targetOffset"] = json!([center.x, center.y, center.z]);
    camera["distance"] = json!(3.0 * half);
    camera["near"] = json!(1e-3 * half);
    camera["far"] = json!(1e3 * half);
    let size = round_up_125(2.0 * half);
    let grid = &mut panel["layers"]["grid"];
    grid["size"] = json!(size);
    grid["label"] = json!(format!("Grid ({} per division)", metres(size / 20.0)));
    grid["position"] = json!([center.x, center.y, center.z - half]);
    serde_json::to_string_pretty(&layout).expect("a JSON value prints")
}

/// `x` metres in the unit that reads best: `1 cm`, `0.5 mm`, `2 m`.
fn metres(x: f64) -> String {
    let (value, unit) = if x >= 1.0 {
        (x, "m")
    } else if x >= 1e-2 {
        (x * 1e2, "cm")
    } else {
        (x * 1e3, "mm")
    };
    format!("{} {unit}", (value * 1e6).round() / 1e6)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_sizes_are_one_two_or_five_times_a_power_of_ten() {
        for (x, want) in [(0.03, 0.05), (0.5, 0.5), (0.51, 1.0), (1.9e-3, 2e-3), (7.0, 10.0)] {
            assert!((round_up_125(x) - want).abs() < 1e-12 * want, "{x}: {}", round_up_125(x));
        }
    }

    #[test]
    fn the_camera_looks_at_the_scene_from_three_half_widths() {
        let layout: Value = serde_json::from_str(&fitted(DVec3::new(0.0, 0.0, 0.25), 0.25)).unwrap();
        let panel = &layout["configById"]["3D!wetbounce"];
        assert_eq!(panel["cameraState"]["targetOffset"], json!([0.0, 0.0, 0.25]));
        assert_eq!(panel["cameraState"]["distance"], json!(0.75));
        assert_eq!(panel["layers"]["grid"]["size"], json!(0.5));
        assert_eq!(panel["layers"]["grid"]["label"], json!("Grid (2.5 cm per division)"));
        // The other panels are the shipped layout's.
        let shipped: Value = serde_json::from_str(TEMPLATE).unwrap();
        assert_eq!(layout["layout"], shipped["layout"]);
        assert_eq!(layout["configById"]["RosOut!events"], shipped["configById"]["RosOut!events"]);
    }
}
