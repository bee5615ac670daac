//! The load-increment driver: the torque schedule, one solve per
//! increment from the previous totals, the states and residuals of each.

use super::problem::{
    FrictionOptions, FrictionSolution, FrictionSolver, Increment, Increments, Prepared, Residuals,
    MAX_INCREMENTS,
};
use super::residual::{gaps, residuals, slips, states, Previous};
use crate::error::FlankError;

/// The totals T₁ < T₂ < … < T_N = T of the schedule (empty for T = 0).
pub(crate) fn schedule(torque: f64, increments: Increments) -> Result<Vec<f64>, FlankError> {
    let n = match increments {
        Increments::Count(n) => {
            if n == 0 || n > MAX_INCREMENTS {
                return Err(FlankError::Model(format!(
                    "friction LTCA: {n} increments (expected 1 … {MAX_INCREMENTS})"
                )));
            }
            n
        }
        Increments::Size(dt) => {
            if !(dt > 0.0 && dt.is_finite()) {
                return Err(FlankError::Model(format!(
                    "friction LTCA: increment size {dt} N·mm must be finite and > 0"
                )));
            }
            let n = (torque / dt).ceil();
            if n > MAX_INCREMENTS as f64 {
                return Err(FlankError::Model(format!(
                    "friction LTCA: increment {dt} N·mm gives {n} increments for {torque} N·mm (more than {MAX_INCREMENTS})"
                )));
            }
            // a remainder below 1e-9 ΔT is round-off of T/ΔT, not an increment
            let whole = (torque / dt).floor();
            if torque - whole * dt <= 1e-9 * dt {
                whole as usize
            } else {
                n as usize
            }
        }
    };
    if torque == 0.0 {
        return Ok(Vec::new());
    }
    Ok(match increments {
        Increments::Count(_) => (1..=n).map(|k| torque * k as f64 / n as f64).collect(),
        Increments::Size(dt) => (1..=n)
            .map(|k| if k == n { torque } else { dt * k as f64 })
            .collect(),
    })
}

fn check_options(o: &FrictionOptions) -> Result<(), FlankError> {
    if o.max_fixed_point == 0 || o.max_qp_iterations == 0 || o.max_polish == 0 || o.max_pivots == 0
    {
        return Err(FlankError::Model(
            "friction LTCA: iteration limits must be ≥ 1".into(),
        ));
    }
    if !(o.tolerance >= 0.0) || !(o.fixed_point_tolerance >= 0.0) {
        return Err(FlankError::Model(
            "friction LTCA: tolerances must be ≥ 0".into(),
        ));
    }
    Ok(())
}

/// Runs the increments with `options.solver` (module doc of [`super`]).
pub(crate) fn run(
    prob: &Prepared,
    options: &FrictionOptions,
) -> Result<FrictionSolution, FlankError> {
    check_options(options)?;
    let torques = schedule(prob.torque, options.increments)?;
    let start_rotation = prob.start_rotation();
    let mut pn = vec![0.0; prob.m];
    let mut pt = vec![0.0; prob.m];
    let mut theta = start_rotation;
    let mut previous_torque = 0.0;
    let mut increments = Vec::with_capacity(torques.len());
    let mut max_residual = Residuals::default();
    let mut limit_hit = false;
    for &tk in &torques {
        let prev = Previous {
            pn: &pn,
            pt: &pt,
            theta,
        };
        let ans = match options.solver {
            FrictionSolver::Clarabel => {
                super::clarabel::step(prob, &prev, tk - previous_torque, tk, options)?
            }
            FrictionSolver::Lemke => super::lemke::step(prob, &prev, tk, options)?,
        };
        let gap = gaps(prob, &ans.pn, &ans.pt, ans.theta);
        let slip = slips(prob, &prev, &ans.pn, &ans.pt, ans.theta);
        let state = states(prob, &ans.pn, &ans.pt, &gap, &slip);
        let residual = residuals(prob, tk, &ans.pn, &ans.pt, &gap, &slip);
        max_residual = if increments.is_empty() {
            residual
        } else {
            max_residual.worst(&residual)
        };
        limit_hit |= ans.limit_hit && !ans.polished;
        pn.clone_from(&ans.pn);
        pt.clone_from(&ans.pt);
        theta = ans.theta;
        previous_torque = tk;
        increments.push(Increment {
            torque: tk,
            normal: ans.pn,
            tangential: ans.pt,
            rotation: ans.theta,
            gap,
            slip,
            state,
            residual,
            iterations: ans.iterations,
            inner_iterations: ans.inner_iterations,
            polish_iterations: ans.polish_iterations,
            polished: ans.polished,
            newton_iterations: ans.newton_iterations,
            newton: ans.newton,
            limit_hit: ans.limit_hit,
        });
    }
    Ok(FrictionSolution {
        solver: options.solver,
        start_rotation,
        within_tolerance: !limit_hit && max_residual.max <= options.tolerance,
        increments,
        max_residual,
    })
}
