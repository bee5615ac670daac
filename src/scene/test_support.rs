//! Scene texts and assertions shared by the section tests.

use std::path::Path;

use super::{parse_scene, Scene};
use crate::error::FlankError;

pub(super) const SPUR: &str = r#"
[pair]
kind = "spur"
centre_distance_mm = 90.0

[pinion]
teeth = 13
normal_module_mm = 3.8
normal_pressure_angle_deg = 20.0
helix_angle_deg = 0.0
face_width_mm = 13.3
profile_shift = 0.3
rack = { addendum = 1.25, dedendum = 1.0, tip_radius = 0.38 }
tip_diameter_mm = 58.7
bore_diameter_mm = 20.0
material = "steel"

[pinion.micro]
tip_relief_um = 10.0
tip_relief_length_mm = 1.0
tip_relief_shape = "parabolic"
lead_crowning_um = 5.0
helix_slope_deviation_um = -3.0
end_relief_um = 20.0
end_relief_length_mm = 2.0

[gear]
teeth = 35
normal_module_mm = 3.8
normal_pressure_angle_deg = 20.0
face_width_mm = 13.3
profile_shift = -0.59931744
tip_diameter_mm = 135.5
bore_diameter_mm = 80.0
material = "steel"

[materials.steel]
young_modulus_mpa = 206000.0
poisson_ratio = 0.3

[load]
torque_nm = 312.0
speed_rpm = 11758.0

[analyses]
mesh = {}

[mesh]
teeth_in_sector = 3
element = "wedge15"
flank_size_mm = 0.1
base_size_mm = 1.0
"#;

pub(super) const HELICAL: &str = r#"
[pair]
kind = "helical"
centre_distance_mm = 462.917331

[pinion]
teeth = 21
normal_module_mm = 15
normal_pressure_angle_deg = 20.0
helix_angle_deg = 20.0
hand = "right"
face_width_mm = 180.0
bore_diameter_mm = 200.0
material = "a"

[gear]
teeth = 37
normal_module_mm = 15.0
normal_pressure_angle_deg = 20.0
helix_angle_deg = 20.0
hand = "left"
face_width_mm = 180.0
bore_diameter_mm = 400.0
material = "b"

[materials.a]
young_modulus_mpa = 207000.0
poisson_ratio = 0.3

[materials.b]
young_modulus_mpa = 210000.0
poisson_ratio = 0.29

[load]
torque_nm = 5000.0
speed_rpm = 3000.0
"#;

pub(super) fn parse(text: &str) -> Result<Scene, FlankError> {
    parse_scene(text, Path::new("/nonexistent/scene.toml"))
}

/// Replaces `from` (which must occur exactly once) by `to`.
pub(super) fn edit(text: &str, from: &str, to: &str) -> String {
    assert_eq!(text.matches(from).count(), 1, "edit anchor {from:?}");
    text.replacen(from, to, 1)
}

/// 1-based line of the first occurrence of `needle`.
pub(super) fn line_of(text: &str, needle: &str) -> usize {
    let i = text.find(needle).expect("needle");
    1 + text[..i].matches('\n').count()
}

/// Asserts a Parse error at `line` whose message contains every one of `words`.
pub(super) fn expect_err(text: &str, line: usize, words: &[&str]) {
    assert_parse_error(parse(text).map(|_| ()), line, words)
}

fn assert_parse_error(result: Result<(), FlankError>, line: usize, words: &[&str]) {
    match result {
        Ok(_) => panic!("expected an error mentioning {words:?}"),
        Err(FlankError::Parse {
            file,
            line: l,
            message,
        }) => {
            assert_eq!(file, Path::new("/nonexistent/scene.toml"));
            for w in words {
                assert!(message.contains(w), "message {message:?} lacks {w:?}");
            }
            assert_eq!(l, line, "line of {message:?}");
        }
        Err(e) => panic!("expected a parse error, got {e}"),
    }
}
