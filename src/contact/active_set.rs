//! The condensed contact problem and its primal active-set solver.
//!
//! On the candidate constraints (n of them) the contact problem is the
//! linear complementarity problem
//!
//! ```text
//!   g = q + (W + C) λ + D α,   λ ≥ 0,  g ≥ 0,  λᵢ gᵢ = 0,   Dᵀλ = r
//! ```
//!
//! with W = B K₀⁻¹ Bᵀ (Delassus matrix, SPD), q the gaps under the external
//! loads, C = diag(1/kᵢ) the penalty compliances (0 for hard contact: then
//! g is the true gap; for a penalty pair g is the gap plus λ/k and the law
//! λ = k·max(0, −gap) is exactly complementarity), D the gaps' sensitivity
//! to the floating modes' amplitudes α and r = −Rᵀf (the floating bodies'
//! equilibrium: the contact forces carry their loads). It is the KKT system
//! of the strictly convex QP
//!
//! ```text
//!   min ½ λᵀ(W + C)λ + qᵀλ   subject to  λ ≥ 0,  Dᵀλ = r,
//! ```
//!
//! α being the multiplier of the equality. The solver is a primal active-set
//! method (Lawson–Hanson type, Nocedal & Wright §16.5): a feasible λ (λ = 0,
//! or with floating modes the non-negative least-squares solution of
//! Dᵀλ = r), then repeatedly the equality-constrained minimizer on the free
//! set F; if it is non-negative the constraints with negative gaps are
//! released into F (all of them at once, or only the most negative after a
//! degenerate step), otherwise the step is cut at the first λᵢ reaching 0
//! and that constraint leaves F. The objective decreases strictly at every
//! non-degenerate step, so the method terminates; an iteration limit guards
//! it anyway. Columns of W are requested lazily, only for constraints that
//! enter F (each is one solve with the factorized stiffness).

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use crate::error::FlankError;

/// Supplies columns of the Delassus matrix W (all n rows).
pub trait Delassus {
    /// Columns `cols` of W, each of length n, in the order given.
    fn columns(&mut self, cols: &[usize]) -> Result<Vec<Vec<f64>>, FlankError>;

    /// Columns that cost about as much together as one alone (a block of
    /// right-hand sides): requests are padded up to a multiple of it with
    /// the candidates most likely to be needed next.
    fn block_size(&self) -> usize {
        1
    }
}

/// A dense W given in full (tests, small problems).
pub struct DenseDelassus(pub DMatrix<f64>);

impl Delassus for DenseDelassus {
    fn columns(&mut self, cols: &[usize]) -> Result<Vec<Vec<f64>>, FlankError> {
        Ok(cols
            .iter()
            .map(|&j| self.0.column(j).iter().copied().collect())
            .collect())
    }
}

/// The data of the condensed problem besides W.
#[derive(Clone, Debug, Default)]
pub struct Condensed {
    /// Gaps without contact forces (and with α = 0).
    pub q: Vec<f64>,
    /// Penalty compliance 1/kᵢ (0 for hard contact).
    pub compliance: Vec<f64>,
    /// Floating-mode columns D (m columns of length n).
    pub d: Vec<Vec<f64>>,
    /// Floating-mode loads r = −Rᵀf (length m).
    pub r: Vec<f64>,
}

/// Violated constraints enter the active set together only if their
/// violation is at least this fraction of the worst one (the worst always
/// enters). 1 would add one violation level at a time, 0 all at once.
pub const ADDITION_FRACTION: f64 = 0.5;

/// Violated constraints that may enter at once when few are active (one
/// block of right-hand sides of the Delassus column solves costs about the
/// same as a single one).
pub const MIN_ADDITIONS: usize = 32;

/// Options of the active-set loop.
#[derive(Clone, Debug)]
pub struct ActiveSetOptions {
    /// Iteration limit (equality-constrained solves).
    pub max_iterations: usize,
    /// A constraint is violated when its gap is below −tolerance (mm).
    pub gap_tolerance: f64,
}

impl Default for ActiveSetOptions {
    fn default() -> Self {
        ActiveSetOptions {
            max_iterations: 500,
            gap_tolerance: 1e-12,
        }
    }
}

/// Answer of the condensed problem with its residuals.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct ActiveSetSolution {
    /// Contact forces λ (N), one per candidate.
    #[serde(skip)]
    pub lambda: Vec<f64>,
    /// Floating-mode amplitudes α.
    pub alpha: Vec<f64>,
    /// g = q + Wλ + Dα: the gap (mm) of every candidate (without the
    /// penalty term).
    #[serde(skip)]
    pub gap: Vec<f64>,
    pub iterations: usize,
    /// Constraints released into / dropped from the free set, in total.
    pub releases: usize,
    pub drops: usize,
    pub active: usize,
    /// Columns of W computed (= solves with the stiffness).
    pub columns: usize,
    /// max over candidates of max(0, −(gᵢ + cᵢλᵢ)): violation of the
    /// contact law (mm; the penetration of hard contacts).
    pub max_violation: f64,
    /// max |λᵢ (gᵢ + cᵢλᵢ)| (N·mm): complementarity.
    pub complementarity: f64,
    /// ‖Dᵀλ − r‖ / ‖r‖ (floating bodies' equilibrium), 0 without them.
    pub equilibrium: f64,
    /// Objective ½λᵀ(W + C)λ + qᵀλ (N·mm).
    pub objective: f64,
}

/// Non-negative least squares min ‖Aλ − r‖, λ ≥ 0 (Lawson–Hanson) for a
/// short wide A (rows = floating modes); ties in the entering variable go to
/// the smallest `prefer` value. Returns λ, the residual norm and whether the
/// iteration limit stopped it.
fn nnls(a: &DMatrix<f64>, r: &DVector<f64>, prefer: &[f64], limit: usize) -> (Vec<f64>, f64, bool) {
    let n = a.ncols();
    let mut x = vec![0.0; n];
    let mut passive: Vec<usize> = Vec::new();
    let scale = r.norm().max(f64::MIN_POSITIVE);
    let residual = |x: &[f64]| {
        let mut res = -r.clone();
        for (j, &v) in x.iter().enumerate() {
            if v != 0.0 {
                res += a.column(j) * v;
            }
        }
        res
    };
    let solve_ls = |set: &[usize]| -> Vec<f64> {
        let ap = DMatrix::from_fn(a.nrows(), set.len(), |i, k| a[(i, set[k])]);
        let svd = ap.svd(true, true);
        match svd.solve(r, 1e-12) {
            Ok(z) => z.iter().copied().collect(),
            Err(_) => vec![0.0; set.len()],
        }
    };
    let mut finished = false;
    for _ in 0..limit {
        let res = residual(&x);
        if res.norm() <= 1e-13 * scale {
            finished = true;
            break;
        }
        let w = a.transpose() * (-res);
        let mut best: Option<(usize, f64)> = None;
        for j in 0..n {
            if passive.contains(&j) {
                continue;
            }
            let wj = w[j];
            if !(wj > 1e-14 * scale) {
                continue;
            }
            let better = match best {
                None => true,
                Some((b, wb)) => {
                    if (wj - wb).abs() <= 1e-12 * wb.abs() {
                        prefer[j] < prefer[b]
                    } else {
                        wj > wb
                    }
                }
            };
            if better {
                best = Some((j, wj));
            }
        }
        let Some((j, _)) = best else {
            finished = true;
            break;
        };
        passive.push(j);
        for _ in 0..limit {
            let z = solve_ls(&passive);
            if z.iter().all(|&v| v > 0.0) {
                for (k, &p) in passive.iter().enumerate() {
                    x[p] = z[k];
                }
                break;
            }
            let mut alpha = 1.0f64;
            for (k, &p) in passive.iter().enumerate() {
                if z[k] <= 0.0 {
                    let t = x[p] / (x[p] - z[k]);
                    alpha = alpha.min(t);
                }
            }
            for (k, &p) in passive.iter().enumerate() {
                x[p] += alpha * (z[k] - x[p]);
            }
            passive.retain(|&p| x[p] > 1e-15 * scale);
            for (j, v) in x.iter_mut().enumerate() {
                if !passive.contains(&j) {
                    *v = 0.0;
                }
            }
            if passive.is_empty() {
                break;
            }
        }
    }
    let res = residual(&x).norm();
    (x, res, !finished)
}

/// Solves the condensed contact problem.
pub fn solve_active_set(
    w: &mut dyn Delassus,
    prob: &Condensed,
    options: &ActiveSetOptions,
) -> Result<ActiveSetSolution, FlankError> {
    let n = prob.q.len();
    let m = prob.d.len();
    if prob.compliance.len() != n || prob.d.iter().any(|c| c.len() != n) || prob.r.len() != m {
        return Err(FlankError::Solver(
            "contact problem: inconsistent dimensions".into(),
        ));
    }
    if prob
        .q
        .iter()
        .chain(&prob.compliance)
        .chain(prob.d.iter().flatten())
        .chain(&prob.r)
        .any(|v| !v.is_finite())
    {
        return Err(FlankError::Solver(
            "contact problem: non-finite gap, compliance or load".into(),
        ));
    }
    let tol = options.gap_tolerance;
    let mut cols: Vec<Option<Vec<f64>>> = vec![None; n];
    let mut computed = 0usize;
    let block = w.block_size().max(1);
    // candidates by their last computed gap, smallest first: the padding of
    // column requests (the next ones to close are the nearest to closing)
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| prob.q[a].total_cmp(&prob.q[b]));
    let mut fetch = |set: &[usize],
                     cols: &mut Vec<Option<Vec<f64>>>,
                     order: &[usize]|
     -> Result<(), FlankError> {
        let mut need: Vec<usize> = set.iter().copied().filter(|&j| cols[j].is_none()).collect();
        if need.is_empty() {
            return Ok(());
        }
        if !need.len().is_multiple_of(block) {
            let mut taken = vec![false; n];
            for &j in &need {
                taken[j] = true;
            }
            for &j in order {
                if need.len().is_multiple_of(block) {
                    break;
                }
                if cols[j].is_none() && !taken[j] {
                    taken[j] = true;
                    need.push(j);
                }
            }
        }
        let got = w.columns(&need)?;
        for (j, c) in need.into_iter().zip(got) {
            if c.len() != n || c.iter().any(|v| !v.is_finite()) {
                return Err(FlankError::Solver(format!(
                    "contact problem: column {j} of the Delassus matrix is invalid"
                )));
            }
            cols[j] = Some(c);
            computed += 1;
        }
        Ok(())
    };

    // phase 1: a feasible start
    let mut lambda = vec![0.0; n];
    let rnorm = prob.r.iter().map(|v| v * v).sum::<f64>().sqrt();
    if m > 0 && rnorm > 0.0 {
        let a = DMatrix::from_fn(m, n, |i, j| prob.d[i][j]);
        let r = DVector::from_column_slice(&prob.r);
        let limit = 10 * (n + m) + 10;
        let (x, res, hit_limit) = nnls(&a, &r, &prob.q, limit);
        if hit_limit && !(res <= 1e-9 * rnorm) {
            return Err(FlankError::Solver(format!(
                "finding contact forces that balance the floating bodies' loads stopped at its iteration limit ({limit}) with residual {res:.3e} of {rnorm:.3e}"
            )));
        }
        if !(res <= 1e-9 * rnorm) {
            return Err(FlankError::Solver(format!(
                "the loads on the floating bodies cannot be balanced by compressive contact forces at the {n} candidate slave nodes (residual {:.3e} of {:.3e}): the bodies do not touch within the search distance, or the load pulls them apart (wrong sign)",
                res, rnorm
            )));
        }
        lambda = x;
    }
    let mut free: Vec<usize> = (0..n).filter(|&i| lambda[i] > 0.0).collect();
    let mut alpha = vec![0.0; m];
    let mut sol = ActiveSetSolution::default();
    let mut degenerate = false;
    let mut converged = false;
    let mut rank_deficient = false;
    while sol.iterations < options.max_iterations {
        sol.iterations += 1;
        fetch(&free, &mut cols, &order)?;
        // equality-constrained minimizer on F
        let k = free.len();
        let mut mff = DMatrix::<f64>::zeros(k, k);
        for (b, &j) in free.iter().enumerate() {
            let cj = cols[j].as_ref().expect("fetched");
            for (a, &i) in free.iter().enumerate() {
                let ci = cols[i].as_ref().expect("fetched");
                mff[(a, b)] = 0.5 * (cj[i] + ci[j]);
            }
            mff[(b, b)] += prob.compliance[j];
        }
        let qf = DVector::from_iterator(k, free.iter().map(|&i| prob.q[i]));
        let (lstar, astar) = if k == 0 {
            rank_deficient = m > 0;
            (DVector::zeros(0), vec![0.0; m])
        } else {
            let chol = mff.clone().cholesky().ok_or_else(|| {
                FlankError::Solver(format!(
                    "contact problem: the Delassus matrix of the {k} active constraints is not positive definite (two slave nodes paired identically?)"
                ))
            })?;
            let z = chol.solve(&qf);
            if m == 0 {
                (-z, Vec::new())
            } else {
                let df = DMatrix::from_fn(k, m, |a, c| prob.d[c][free[a]]);
                let y = chol.solve(&df);
                let s = df.transpose() * &y;
                let rhs = -DVector::from_column_slice(&prob.r) - df.transpose() * &z;
                let eig = SymmetricEigen::new(s.clone());
                let smax = eig.eigenvalues.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                let mut al = DVector::<f64>::zeros(m);
                rank_deficient = false;
                for c in 0..m {
                    let ev = eig.eigenvalues[c];
                    let v = eig.eigenvectors.column(c);
                    if ev > 1e-10 * smax && smax > 0.0 {
                        al += v * (v.dot(&rhs) / ev);
                    } else {
                        rank_deficient = true;
                    }
                }
                let l = -z - y * &al;
                (l, al.iter().copied().collect())
            }
        };
        let negative = (0..k).any(|a| lstar[a] < 0.0);
        if !negative {
            for (a, &i) in free.iter().enumerate() {
                lambda[i] = lstar[a];
            }
            alpha = astar;
            // gaps of the constraints outside F
            let g = gaps(prob, &cols, &free, &lambda, &alpha);
            order.sort_by(|&a, &b| g[a].total_cmp(&g[b]));
            let mut in_free = vec![false; n];
            for &i in &free {
                in_free[i] = true;
            }
            let mut viol: Vec<(f64, usize)> = (0..n)
                .filter(|&i| lambda[i] == 0.0 && !in_free[i] && g[i] < -tol)
                .map(|i| (g[i], i))
                .collect();
            if viol.is_empty() {
                converged = true;
                break;
            }
            viol.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(std::cmp::Ordering::Equal));
            if degenerate {
                viol.truncate(1);
            } else {
                // only the clearly violated enter: each entering constraint
                // costs a solve for its Delassus column, and the barely
                // violated ones are mostly pushed open by the others
                let worst = viol[0].0;
                viol.retain(|v| v.0 <= ADDITION_FRACTION * worst);
                // and at most as many as are active already (the set at
                // most doubles): a start far from the answer (one node
                // holding a floating body) violates nearly every candidate
                viol.truncate(free.len().max(MIN_ADDITIONS));
            }
            sol.releases += viol.len();
            free.extend(viol.iter().map(|v| v.1));
            free.sort_unstable();
            degenerate = false;
        } else {
            // step towards λ* until the first λᵢ reaches 0
            let mut beta = 1.0f64;
            for (a, &i) in free.iter().enumerate() {
                if lstar[a] < 0.0 {
                    let t = lambda[i] / (lambda[i] - lstar[a]);
                    beta = beta.min(t);
                }
            }
            let beta = beta.clamp(0.0, 1.0);
            for (a, &i) in free.iter().enumerate() {
                lambda[i] += beta * (lstar[a] - lambda[i]);
            }
            // leave F: the blocking constraint(s)
            let floor = 1e-14 * free.iter().fold(0.0f64, |x, &i| x.max(lambda[i].abs()));
            let before = free.len();
            let mut out: Vec<usize> = Vec::new();
            for (a, &i) in free.iter().enumerate() {
                if lstar[a] < 0.0 && lambda[i] <= floor {
                    out.push(i);
                }
            }
            if out.is_empty() {
                // round-off: drop the one closest to its bound
                if let Some((_, i)) = free
                    .iter()
                    .enumerate()
                    .filter(|(a, _)| lstar[*a] < 0.0)
                    .map(|(_, &i)| (lambda[i], i))
                    .min_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(std::cmp::Ordering::Equal))
                {
                    out.push(i);
                }
            }
            for &i in &out {
                lambda[i] = 0.0;
            }
            free.retain(|i| !out.contains(i));
            sol.drops += before - free.len();
            degenerate = beta <= 1e-12;
        }
    }
    if !converged {
        let g = gaps(prob, &cols, &free, &lambda, &alpha);
        let worst = (0..n)
            .map(|i| -(g[i] + prob.compliance[i] * lambda[i]))
            .fold(0.0f64, f64::max);
        return Err(FlankError::Solver(format!(
            "contact active set did not converge within {} iterations ({} active of {n} candidates, largest law violation {:.3e} mm); raise the iteration limit or check the model",
            options.max_iterations,
            free.len(),
            worst
        )));
    }
    if rank_deficient {
        return Err(FlankError::Solver(format!(
            "a floating body's rigid motion is not held by the {} active contact constraints (frictionless contact cannot hold it, or the body is unloaded and its position is undetermined); hold that motion with a *BOUNDARY",
            free.len()
        )));
    }
    let g = gaps(prob, &cols, &free, &lambda, &alpha);
    sol.max_violation = (0..n)
        .map(|i| -(g[i] + prob.compliance[i] * lambda[i]))
        .fold(0.0f64, f64::max);
    sol.complementarity = (0..n)
        .map(|i| (lambda[i] * (g[i] + prob.compliance[i] * lambda[i])).abs())
        .fold(0.0f64, f64::max);
    if m > 0 {
        let mut e = 0.0;
        for c in 0..m {
            let s: f64 = (0..n).map(|i| prob.d[c][i] * lambda[i]).sum::<f64>() - prob.r[c];
            e += s * s;
        }
        sol.equilibrium = if rnorm > 0.0 {
            e.sqrt() / rnorm
        } else {
            e.sqrt()
        };
    }
    let mut obj = 0.0;
    for &j in &free {
        let cj = cols[j].as_ref().expect("fetched");
        for &i in &free {
            obj += 0.5 * lambda[i] * cj[i] * lambda[j];
        }
        obj += 0.5 * prob.compliance[j] * lambda[j] * lambda[j] + prob.q[j] * lambda[j];
    }
    sol.objective = obj;
    sol.active = free.iter().filter(|&&i| lambda[i] > 0.0).count();
    sol.columns = computed;
    sol.lambda = lambda;
    sol.alpha = alpha;
    sol.gap = g;
    Ok(sol)
}

/// g = q + W[:, F] λ_F + Dα for all constraints.
fn gaps(
    prob: &Condensed,
    cols: &[Option<Vec<f64>>],
    free: &[usize],
    lambda: &[f64],
    alpha: &[f64],
) -> Vec<f64> {
    let mut g = prob.q.clone();
    for &j in free {
        if lambda[j] == 0.0 {
            continue;
        }
        if let Some(c) = &cols[j] {
            for (gi, ci) in g.iter_mut().zip(c) {
                *gi += ci * lambda[j];
            }
        }
    }
    for (c, a) in prob.d.iter().zip(alpha) {
        for (gi, di) in g.iter_mut().zip(c) {
            *gi += di * a;
        }
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A random SPD "Delassus" matrix (positive entries, like contact).
    fn spd(n: usize, seed: u64) -> DMatrix<f64> {
        let mut s = seed;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64) / ((1u64 << 53) as f64)
        };
        let a = DMatrix::from_fn(n, n, |_, _| next());
        &a * a.transpose() + DMatrix::identity(n, n) * (n as f64 * 0.1)
    }

    /// Checks the KKT conditions of a solution.
    fn check_kkt(w: &DMatrix<f64>, p: &Condensed, s: &ActiveSetSolution) {
        let n = p.q.len();
        for i in 0..n {
            let gi = p.q[i]
                + (0..n).map(|j| w[(i, j)] * s.lambda[j]).sum::<f64>()
                + p.d.iter().zip(&s.alpha).map(|(d, a)| d[i] * a).sum::<f64>()
                + p.compliance[i] * s.lambda[i];
            assert!(s.lambda[i] >= 0.0);
            assert!(gi >= -1e-10, "gap {i}: {gi}");
            assert!((s.lambda[i] * gi).abs() < 1e-9, "complementarity {i}");
        }
        assert!(s.equilibrium < 1e-10);
    }

    #[test]
    fn random_lcps_satisfy_kkt() {
        for seed in 0..20u64 {
            let n = 5 + (seed as usize % 25);
            let w = spd(n, seed);
            let q: Vec<f64> = (0..n)
                .map(|i| ((i as f64 * 1.7 + seed as f64).sin()) * 3.0)
                .collect();
            let compliance = (0..n)
                .map(|i| {
                    if (i + seed as usize).is_multiple_of(3) {
                        0.5
                    } else {
                        0.0
                    }
                })
                .collect();
            let p = Condensed {
                q,
                compliance,
                ..Default::default()
            };
            let s = solve_active_set(
                &mut DenseDelassus(w.clone()),
                &p,
                &ActiveSetOptions::default(),
            )
            .unwrap();
            check_kkt(&w, &p, &s);
        }
    }

    #[test]
    fn floating_mode_balances_the_load() {
        // a "body" pressed by r = 10 onto 8 springs with positive gaps: the
        // rigid approach α closes the nearest gaps
        let n = 8;
        let w = spd(n, 7) * 0.01;
        let q: Vec<f64> = (0..n).map(|i| 0.1 * (i as f64 - 3.5).powi(2)).collect();
        let p = Condensed {
            q,
            compliance: vec![0.0; n],
            d: vec![vec![1.0; n]],
            r: vec![10.0],
        };
        let s = solve_active_set(
            &mut DenseDelassus(w.clone()),
            &p,
            &ActiveSetOptions::default(),
        )
        .unwrap();
        check_kkt(&w, &p, &s);
        let total: f64 = s.lambda.iter().sum();
        assert!((total - 10.0).abs() < 1e-10);
        // the load pulling away cannot be balanced: a clear error
        let p2 = Condensed {
            r: vec![-10.0],
            ..p.clone()
        };
        let err = solve_active_set(&mut DenseDelassus(w), &p2, &ActiveSetOptions::default())
            .unwrap_err()
            .to_string();
        assert!(err.contains("cannot be balanced"), "{err}");
    }

    #[test]
    fn iteration_limit_is_reported() {
        let n = 12;
        let w = spd(n, 3);
        let p = Condensed {
            q: vec![-1.0; n],
            compliance: vec![0.0; n],
            ..Default::default()
        };
        let err = solve_active_set(
            &mut DenseDelassus(w),
            &p,
            &ActiveSetOptions {
                max_iterations: 1,
                ..Default::default()
            },
        )
        .unwrap_err()
        .to_string();
        assert!(
            err.contains("did not converge within 1 iterations"),
            "{err}"
        );
    }
}
