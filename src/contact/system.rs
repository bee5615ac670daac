//! The bodies' stiffness, factorized once: the elastic side of a contact
//! problem.
//!
//! [`ElasticSystem::new`] finds the floating modes of the model (rigid
//! modes only contact holds, [`crate::contact::floating`]), pins them,
//! assembles and factorizes the reduced stiffness K₀ (METIS/AMD, sparse
//! Cholesky) and keeps the factor. Everything a contact solve then needs is
//! a solve with that factor: the response to the external loads, and the
//! response to unit contact forces (the columns of the Delassus matrix
//! W = B K₀⁻¹ Bᵀ). The factor does not depend on gaps, pairings or contact
//! states, so a driver that moves the contact (new gaps, new pairings, a new
//! roll angle expressed in each body's own frame) reuses it: only solves
//! are repeated. The Delassus columns are needed only at the candidate
//! constraints' DOFs and their right-hand sides live there too, so they use
//! substitutions restricted to those DOFs' ancestors in the elimination
//! tree ([`ElasticSystem::solve_reach`], [`ElasticSystem::solve_restricted`]).

use std::time::Instant;

use faer::Par;

use crate::contact::floating::{floating_modes, FloatingModes};
use crate::error::FlankError;
use crate::fem::assembly::{Assembly, SparsePattern};
use crate::fem::constraints::{DofMap, DofTarget};
use crate::fem::loads::load_vector;
use crate::fem::model::Model;
use crate::fem::ordering::OrderingMethod;
use crate::fem::solver::{parallelism, Precision, SolveReach, SparseCholesky};
use crate::fem::static_analysis::{check_rigid_body_modes, validate};
use crate::fem::thermal::has_thermal_strain;

/// Figures of the factorization (for summaries).
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct SystemStats {
    pub dofs: usize,
    pub nnz_factor: usize,
    /// Floating-point operations of the numeric factorization
    /// ([`crate::fem::solver::FactorStats::flops`]).
    pub flops: f64,
    pub ordering: String,
    pub assembly_s: f64,
    pub factorization_s: f64,
    pub floating_modes: usize,
    /// The memory guard's estimated peak of the factorization (MB: the
    /// resident set before it plus the factor and workspace).
    pub estimated_peak_mb: f64,
    /// Estimates of κ₁(K₀) and of κ₁ of the diagonally scaled K₀
    /// ([`ElasticSystem::condition_estimate`]).
    pub condition_estimate: f64,
    pub scaled_condition_estimate: f64,
    /// Wall time of both estimates (s; about 10 solves with the factor).
    pub condition_s: f64,
}

/// The response of the pinned stiffness to the model's external loads
/// (the same for every contact configuration of the same model).
#[derive(Clone, Debug)]
pub struct ExternalResponse {
    /// Reduced right-hand side and full load vector.
    pub rhs: Vec<f64>,
    pub load: Vec<f64>,
    /// Full displacement K₀⁻¹ b (with prescribed values).
    pub displacement: Vec<f64>,
}

/// The factorized stiffness of a model (with its floating modes pinned).
pub struct ElasticSystem {
    /// Computed on first use by [`ElasticSystem::external_response`].
    external: std::sync::OnceLock<ExternalResponse>,
    pub floating: FloatingModes,
    pub dofs: DofMap,
    pattern: SparsePattern,
    values: Vec<f64>,
    chol: SparseCholesky,
    /// −Tᵀ K u₀ (load of prescribed displacements).
    prescribed_load: Vec<f64>,
    par: Par,
    pub stats: SystemStats,
}

impl ElasticSystem {
    /// Validates, pins the floating modes, assembles and factorizes.
    /// `contact_nodes` are the nodes of the contact surfaces: a floating
    /// body without any of them is an error (nothing could hold it).
    pub fn new(
        model: &Model,
        contact_nodes: &[usize],
        ordering: OrderingMethod,
        threads: usize,
    ) -> Result<Self, FlankError> {
        validate(model)?;
        if has_thermal_strain(model) {
            // the contact solution's external load, work and reactions are
            // the mechanical loads only: a thermal load would be dropped
            return Err(FlankError::Model(
                "thermal strains (temperatures with *EXPANSION) together with contact are not supported; solve without the contact pairs or without the temperatures".into(),
            ));
        }
        if !model.equations.is_empty() {
            // the floating-body detection and the contact condensation are
            // not verified with eliminated equation DOFs
            return Err(FlankError::Model(
                "linear equations (*EQUATION) together with contact are not supported; solve without the contact pairs or without the equations".into(),
            ));
        }
        let dofs0 = DofMap::new(model)?;
        let floating = floating_modes(model, &dofs0);
        if !floating.modes.is_empty() {
            let mut on_contact = vec![false; model.mesh.node_count()];
            for &n in contact_nodes {
                if n < on_contact.len() {
                    on_contact[n] = true;
                }
            }
            for m in &floating.modes {
                if !m.body_nodes.iter().any(|&n| on_contact[n]) {
                    // the body touches no contact surface: the usual message
                    check_rigid_body_modes(model, &dofs0)?;
                    return Err(FlankError::Singular(format!(
                        "body containing node {} has a free rigid-body mode ({}) and no contact surface",
                        m.body_node, m.description
                    )));
                }
            }
        }
        let pinned = floating.pinned_model(model);
        let mut dofs = DofMap::new(&pinned)?;
        check_rigid_body_modes(&pinned, &dofs)?;
        let par = parallelism(threads);
        let t = Instant::now();
        let asm = Assembly::new(&pinned, &mut dofs, ordering)?;
        // the symbolic factorization needs only the pattern: the memory of
        // the matrix values and of the factor is checked before either is
        // allocated (a mesh too fine for the machine is refused in seconds)
        let mut chol = SparseCholesky::analyze(&asm.pattern, ordering, asm.ordering_s, par)?;
        crate::resources::check_memory(
            &format!(
                "the stiffness matrix and its sparse Cholesky factor ({} DOFs, nnz(L) = {:.3e})",
                asm.pattern.n, chol.stats.nnz_factor
            ),
            (8 * asm.pattern.nnz()) as f64 / 1048576.0 + chol.factor_memory_mb(Precision::Double),
            crate::resources::ALTERNATIVES,
        )?;
        let sys = asm.assemble(&pinned, &dofs)?;
        let assembly_s = t.elapsed().as_secs_f64() - chol.stats.symbolic_s;
        let pattern = asm.pattern;
        let names = crate::fem::static_analysis::reduced_dof_names(&pinned, &dofs);
        // Double, not the static solve's mixed default: the Delassus
        // columns are many solves with this one factor, each used as is
        // (no per-column refinement against the f64 matrix).
        chol.factorize(&pattern, &sys.values, Precision::Double, &|r| {
            names.get(r).cloned().unwrap_or_else(|| r.to_string())
        })?;
        let stats = SystemStats {
            dofs: dofs.reduced_count,
            nnz_factor: chol.stats.nnz_factor,
            flops: chol.stats.flops,
            ordering: chol.stats.ordering.clone(),
            assembly_s,
            factorization_s: chol.stats.factorization_s,
            floating_modes: floating.modes.len(),
            estimated_peak_mb: chol.stats.resident_before_mb + chol.stats.factor_estimate_mb,
            condition_estimate: f64::NAN,
            scaled_condition_estimate: f64::NAN,
            condition_s: 0.0,
        };
        let mut system = ElasticSystem {
            external: std::sync::OnceLock::new(),
            floating,
            dofs,
            pattern,
            values: sys.values,
            chol,
            prescribed_load: sys.prescribed_load,
            par,
            stats,
        };
        let t = Instant::now();
        (
            system.stats.condition_estimate,
            system.stats.scaled_condition_estimate,
        ) = system.condition_estimate();
        system.stats.condition_s = t.elapsed().as_secs_f64();
        Ok(system)
    }

    pub fn reduced_count(&self) -> usize {
        self.dofs.reduced_count
    }

    /// Reduced right-hand side of the model's external loads (forces,
    /// pressures, coupling loads, prescribed displacements).
    pub fn external_rhs(&self, model: &Model) -> Result<(Vec<f64>, Vec<f64>), FlankError> {
        let f = load_vector(model)?;
        let mut b = self.dofs.restrict(&f);
        for (c, cp) in model.couplings.iter().enumerate() {
            for k in 0..6 {
                if let Some(r) = self.dofs.coupling_dofs.get(c).and_then(|d| d[k]) {
                    b[r] += cp.load[k];
                }
            }
        }
        for (bi, pi) in b.iter_mut().zip(&self.prescribed_load) {
            *bi += pi;
        }
        Ok((b, f))
    }

    /// The response to the external loads of `model`, solved once and kept:
    /// a driver that solves many contact configurations (roll angles) of
    /// the same model pays for it once. `model` must be the model the
    /// system was built from.
    pub fn external_response(&self, model: &Model) -> Result<&ExternalResponse, FlankError> {
        if let Some(e) = self.external.get() {
            return Ok(e);
        }
        let (rhs, load) = self.external_rhs(model)?;
        let mut q = rhs.clone();
        self.solve(&mut q);
        let displacement = self.expand(&q);
        Ok(self.external.get_or_init(|| ExternalResponse {
            rhs,
            load,
            displacement,
        }))
    }

    /// Solves K₀ x = b in place.
    pub fn solve(&self, b: &mut [f64]) {
        self.chol.solve_in_place(b);
    }

    /// Solves K₀ X = B for the columns of `b` (n × k, column major).
    pub fn solve_columns(&self, b: faer::MatMut<'_, f64>) {
        self.chol.solve_columns_with(b, self.par);
    }

    /// The reach of reduced DOFs `dofs` in the factor's elimination tree,
    /// for [`solve_restricted`](Self::solve_restricted); `None` if the
    /// factor is simplicial (small systems): solve in full then.
    pub fn solve_reach(&self, dofs: &[usize]) -> Option<SolveReach> {
        self.chol.reach(dofs)
    }

    /// K₀⁻¹ B on the rows of `reach` for sparse columns of B (`(dof,
    /// value)` lists, every DOF in the reach): restricted forward and
    /// backward substitutions ([`SparseCholesky::solve_restricted`]), the
    /// same numbers as [`solve_columns`](Self::solve_columns) on those rows.
    pub fn solve_restricted(
        &self,
        reach: &SolveReach,
        columns: &[&[(usize, f64)]],
    ) -> faer::Mat<f64> {
        self.chol.solve_restricted(reach, columns, self.par)
    }

    /// Reduced vector Tᵀc of a linear form Σ cᵀu_node (sparse, merged).
    pub fn reduced_form(&self, terms: &[(usize, [f64; 3])]) -> Vec<(usize, f64)> {
        let mut out: Vec<(usize, f64)> = Vec::with_capacity(3 * terms.len());
        for &(node, c) in terms {
            for k in 0..3 {
                if c[k] != 0.0 {
                    self.dofs
                        .for_each_term(3 * node + k, |r, coef| out.push((r, coef * c[k])));
                }
            }
        }
        out.sort_unstable_by_key(|e| e.0);
        let mut merged: Vec<(usize, f64)> = Vec::with_capacity(out.len());
        for (r, v) in out {
            match merged.last_mut() {
                Some(last) if last.0 == r => last.1 += v,
                _ => merged.push((r, v)),
            }
        }
        merged
    }

    /// Full displacement of a reduced solution including prescribed values.
    pub fn expand(&self, q: &[f64]) -> Vec<f64> {
        self.dofs.expand(q)
    }

    /// Full displacement of a reduced solution without prescribed values
    /// (the response to a load alone).
    pub fn expand_linear(&self, q: &[f64]) -> Vec<f64> {
        (0..self.dofs.targets.len())
            .map(|d| match self.dofs.targets[d] {
                DofTarget::Free(r) => q[r],
                DofTarget::Coupled { start, len, .. } => self.dofs.terms[start..start + len]
                    .iter()
                    .map(|&(r, c)| c * q[r])
                    .sum(),
                DofTarget::Fixed(_) | DofTarget::Unused => 0.0,
            })
            .collect()
    }

    /// Relative residual ‖K₀q − b‖/‖b‖ and backward error of a solution
    /// ([`crate::fem::residual::backward_error`]).
    pub fn residual(&self, q: &[f64], b: &[f64]) -> (f64, f64) {
        crate::fem::residual::backward_error(&self.pattern, &self.values, q, b)
    }

    /// Estimates of the 1-norm condition number κ₁(K₀) of the pinned
    /// stiffness and of its diagonally scaled form
    /// ([`crate::fem::residual::condition_estimate`],
    /// [`crate::fem::residual::scaled_condition_estimate`]: a few solves
    /// with the factor each).
    pub fn condition_estimate(&self) -> (f64, f64) {
        let solve = |x: &mut [f64]| self.chol.solve_in_place(x);
        (
            crate::fem::residual::condition_estimate(&self.pattern, &self.values, solve),
            crate::fem::residual::scaled_condition_estimate(&self.pattern, &self.values, solve),
        )
    }

    /// Motion of each coupling's reference DOFs in a reduced solution.
    pub fn coupling_motion(&self, q: &[f64]) -> Vec<[f64; 6]> {
        self.dofs
            .coupling_dofs
            .iter()
            .map(|cd| {
                let mut m = [0.0; 6];
                for k in 0..6 {
                    if let Some(r) = cd[k] {
                        m[k] = q[r];
                    }
                }
                m
            })
            .collect()
    }
}
