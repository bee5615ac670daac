//! The settings of the LTCA solve at one position ([`LtcaSettings`]: local
//! model, FE cells, QP, condition number) and of friction in the
//! spur/helical and hypoid LTCA ([`LtcaFriction`]): the Coulomb coefficient
//! (one μ, or one per tooth pair for the wet–dry loop), the load
//! increments, the friction model, and the map from μ per tooth pair to μ
//! per candidate point of [`crate::ltca::friction::FrictionProblem`]. The
//! solve itself is [`crate::ltca::model`].

use crate::error::FlankError;
use crate::ltca::friction::FrictionOptions;
use crate::ltca::qp::QpOptions;
use crate::settings::{FrictionModel, LocalModel};

/// Settings of the LTCA solve at one position.
#[derive(Clone, Debug, serde::Serialize)]
pub struct LtcaSettings {
    pub local: LocalModel,
    /// κ: FE cell half-width across the line in flank element sizes.
    pub fe_cell_factor: f64,
    /// Gauss points per direction over a cell (tensor interpolation).
    pub cell_samples: usize,
    /// Limit on the fixed-point iterations on the Hertz half-widths (≥ 1);
    /// the loop stops earlier when they change by less than
    /// [`crate::ltca::model::HALF_WIDTH_TOLERANCE`]. Default 10: seed 002 converges in 1–3
    /// rounds, seed 004 (helical, K = 40) in 6–7 and seed 001 (hypoid) in
    /// up to 8, where the former default 4 stopped 27 of 50 and 12 of 30
    /// positions unconverged.
    pub local_iterations: usize,
    pub qp: QpOptions,
    /// Report κ(F) (one symmetric eigen-decomposition per position).
    pub condition: bool,
    /// Coulomb friction (seeds 001/003); `None`: frictionless.
    pub friction: Option<LtcaFriction>,
    /// μ per tooth pair (entry k − 1 for pinion tooth k), replacing
    /// `friction.mu` (the wet–dry loop, [`crate::ltca::lubricated`]).
    pub pair_mu: Option<Vec<f64>>,
}

impl Default for LtcaSettings {
    fn default() -> Self {
        LtcaSettings {
            local: LocalModel::default(),
            fe_cell_factor: 1.0,
            cell_samples: 3,
            local_iterations: 10,
            qp: QpOptions::default(),
            condition: false,
            friction: None,
            pair_mu: None,
        }
    }
}

/// Coulomb friction in the LTCA: the problem of [`crate::ltca::friction`]
/// on the candidates (C_nn with the near field as without friction; C_nt,
/// C_tn, C_tt from the tensors along each point's tangent, the sliding
/// direction), in load increments.
#[derive(Clone, Debug, serde::Serialize)]
pub struct LtcaFriction {
    pub mu: f64,
    pub options: FrictionOptions,
    /// Pinion speed ω₁ (rad/s) of the TCA velocities: the sliding
    /// coefficient of a point is s = v_s / (ω₁ r_n) (sliding distance per
    /// unit normal approach of the pinion's rotation, seeds 001/003).
    pub pinion_speed_rad_s: f64,
    /// Also solve every position by Lemke's method and report the
    /// largest difference ([`crate::ltca::friction::cross_check`]).
    pub cross_check: bool,
    /// Which slip the friction resists.
    pub model: FrictionModel,
}

impl LtcaFriction {
    /// The number of equal load increments (`None` for increments of a
    /// size).
    pub fn increment_count(&self) -> Option<usize> {
        match self.options.increments {
            crate::ltca::friction::Increments::Count(n) => Some(n),
            crate::ltca::friction::Increments::Size(_) => None,
        }
    }

    /// The checked settings of μ (`None` for μ = 0), `increments` equal
    /// load steps and `model`, for a pinion at `speed_rpm` (friction needs
    /// the sliding direction, i.e. a speed > 0; `source` names the scene).
    pub fn checked(
        mu: f64,
        increments: usize,
        model: FrictionModel,
        cross_check: bool,
        speed_rpm: f64,
        source: &std::path::Path,
    ) -> Result<Option<Self>, FlankError> {
        if !(mu.is_finite() && (0.0..=1.0).contains(&mu)) {
            return Err(FlankError::Model(format!(
                "--friction-mu {mu}: a coefficient in [0, 1] is needed"
            )));
        }
        if mu == 0.0 {
            return Ok(None);
        }
        if !(1..=10_000).contains(&increments) {
            return Err(FlankError::Model(format!(
                "--increments {increments}: between 1 and 10000 load increments are needed"
            )));
        }
        if !(speed_rpm > 0.0) {
            return Err(FlankError::Model(format!(
                "{}: friction needs the sliding direction, from [load] speed_rpm > 0 (got {speed_rpm})",
                source.display()
            )));
        }
        Ok(Some(LtcaFriction {
            mu,
            options: FrictionOptions {
                increments: crate::ltca::friction::Increments::Count(increments),
                ..Default::default()
            },
            pinion_speed_rad_s: speed_rpm * std::f64::consts::PI / 30.0,
            cross_check,
            model,
        }))
    }
}

impl LtcaSettings {
    /// μ per candidate point from [`LtcaSettings::pair_mu`], given each
    /// point's pinion tooth (1-based); `None` without a per-pair μ (then
    /// `friction.mu` holds everywhere). Errors: a tooth without an entry,
    /// a μ outside [0, 1], or a per-pair μ without friction.
    pub fn point_mu(
        &self,
        teeth: impl Iterator<Item = usize>,
    ) -> Result<Option<Vec<f64>>, FlankError> {
        let Some(mu) = &self.pair_mu else {
            return Ok(None);
        };
        if self.friction.is_none() {
            return Err(FlankError::Model(
                "LTCA: a friction coefficient per tooth pair needs the frictional LTCA (friction μ > 0)".into(),
            ));
        }
        if let Some(p) = mu
            .iter()
            .position(|m| !(m.is_finite() && (0.0..=1.0).contains(m)))
        {
            return Err(FlankError::Model(format!(
                "LTCA: friction coefficient {} of tooth pair {} must be in [0, 1]",
                mu[p],
                p + 1
            )));
        }
        teeth
            .map(|k| {
                k.checked_sub(1)
                    .and_then(|p| mu.get(p).copied())
                    .ok_or_else(|| {
                        FlankError::Model(format!(
                            "LTCA: no friction coefficient for pinion tooth {k} ({} tooth pairs given)",
                            mu.len()
                        ))
                    })
            })
            .collect::<Result<Vec<f64>, _>>()
            .map(Some)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pair_mu_maps_to_points() {
        let mut s = LtcaSettings::default();
        assert_eq!(s.point_mu([1, 2].into_iter()).unwrap(), None);
        s.pair_mu = Some(vec![0.01, 0.02, 0.03]);
        let e = s.point_mu([1].into_iter()).unwrap_err();
        assert!(e.to_string().contains("needs the frictional LTCA"), "{e}");
        s.friction = LtcaFriction::checked(
            0.05,
            3,
            FrictionModel::Sliding,
            false,
            1000.0,
            std::path::Path::new("x.toml"),
        )
        .unwrap();
        let v = s.point_mu([3, 1, 1, 2].into_iter()).unwrap().unwrap();
        assert_eq!(v, vec![0.03, 0.01, 0.01, 0.02]);
        let e = s.point_mu([4].into_iter()).unwrap_err();
        assert!(e.to_string().contains("pinion tooth 4"), "{e}");
        s.pair_mu = Some(vec![0.01, f64::NAN]);
        let e = s.point_mu([1].into_iter()).unwrap_err();
        assert!(e.to_string().contains("tooth pair 2"), "{e}");
    }
}
