//! The `[load]` section: the operating point (pinion torque and speed).

use serde::Deserialize;
use toml::Spanned;

use super::location::{Cx, Res};

/// Operating point, internal units.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Load {
    /// Torque on the pinion (N·mm); ≥ 0.
    pub torque_nmm: f64,
    /// Pinion speed (rev/min); ≥ 0.
    pub speed_rpm: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawLoad {
    torque_nm: Spanned<f64>,
    speed_rpm: Spanned<f64>,
}

/// The operating point in internal units (N·m → N·mm).
pub(super) fn load(cx: &Cx, raw: &RawLoad) -> Res<Load> {
    let torque_nm = cx.non_negative(&raw.torque_nm, "load.torque_nm")?;
    let speed_rpm = cx.non_negative(&raw.speed_rpm, "load.speed_rpm")?;
    Ok(Load {
        torque_nmm: torque_nm * 1000.0,
        speed_rpm,
    })
}

/// Line of `load.torque_nm` (checks made after the scene is read point at it).
pub(super) fn torque_line(cx: &Cx, raw: &RawLoad) -> usize {
    cx.line(raw.torque_nm.span().start)
}

#[cfg(test)]
mod tests {
    use crate::scene::test_support::*;

    #[test]
    fn negative_torque() {
        let t = edit(SPUR, "torque_nm = 312.0", "torque_nm = -312.0");
        expect_err(
            &t,
            line_of(&t, "torque_nm"),
            &["load.torque_nm", "negative"],
        );
    }
}
