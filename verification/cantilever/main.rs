//! # Verification: cantilever with shear deformation (Timoshenko)
//!
//! ## What
//!
//! A prismatic bar of length L = 100 mm and square section b = h = 10 mm,
//! E = 210 000 MPa, ν = 0.3, is clamped on its end face x = 0 (all three
//! displacement components of every node of that face are zero) and loaded on
//! its free end face x = L by a uniform shear traction τ = P/(b h) in −y with
//! resultant P = 1000 N. The traction is turned into consistent nodal loads
//! face by face (`traction_face_load` over `box_faces(mesh, "X1")`).
//!
//! ## Reference
//!
//! Timoshenko beam theory gives the tip deflection
//!
//! ```text
//!     δ = P L³ / (3 E I) + P L / (κ G A),   I = b h³/12,  A = b h,  G = E / (2(1+ν))
//! ```
//!
//! with the shear coefficient κ = 5/6 for a rectangle (the classical value,
//! asserted against) or Cowper's κ = 10(1+ν)/(12+11ν) (G. R. Cowper, "The
//! shear coefficient in Timoshenko's beam theory", J. Appl. Mech. 33 (1966)
//! 335–340), which is also reported. For these proportions (L/h = 10) the shear
//! term is 0.8 % of δ, and the two κ differ by 0.015 % in δ.
//!
//! The 3D elastic solution is not exactly the beam solution: the clamped face
//! also suppresses the Poisson contraction and the warping of the section
//! (a local stress singularity at the clamped edges), and the
//! beam's "tip deflection" must be defined for a 3D field. We take the
//! area-weighted mean of u_y over the tip face, δ = −∫u_y dA / A, computed
//! exactly with the same consistent weights w_a = ∫N_a dA that distribute the
//! traction. With a uniform traction, P·δ is then exactly the external work
//! (twice the strain energy), so for nested conforming meshes with exactly
//! integrated stiffness (Hex20 on a box: 3×3×3 Gauss is exact for its
//! polynomial integrand) δ must *increase monotonically* under refinement —
//! a displacement-based model is too stiff and relaxes towards the limit.
//! That limit lies within a fraction of a percent of the Timoshenko value:
//! the Hex20 sequence extrapolates to 0.68 % *below* it. The cause is the
//! Poisson constraint of the clamp (the root cannot contract anticlastically
//! where the moment is largest, so it is stiffer than a beam): run with ν = 0
//! the same 3D model meets Timoshenko to 10⁻⁵. At ν = 0.3 the clamp effect
//! nearly cancels the shear term (0.77 % of δ), so a 1 % check against
//! Timoshenko cannot tell it from Euler–Bernoulli; the ν = 0 check can (0.1 %
//! tolerance, Euler–Bernoulli misses by 0.6 %).
//!
//! The bending stress at mid-span x = L/2, top fibre y = h, is σ_xx = M c / I
//! with M = P L/2 and c = h/2 (Saint-Venant's flexure solution has this
//! linear σ_xx exactly, far enough from both ends: here 5 depths).
//!
//! ## Checks
//!
//! * Hex20 on (nx, ny, nz) = (10,1,1), (20,2,2), (40,4,4), (80,8,8): δ increases
//!   monotonically, the successive differences shrink, the finest δ is within
//!   1 % of Timoshenko (κ = 5/6).
//! * Hex20R and Wedge15 on (20,2,2) (reported) and (40,4,4): δ within 1 %.
//! * σ_xx at mid-span top fibre within 1 % of M c/I on the two finest Hex20
//!   meshes (and on the Hex20R/Wedge15 meshes at (40,4,4)); the coarser ones
//!   are reported.
//! * ν = 0, Hex20 (40,4,4): δ within 0.1 % of Timoshenko (shear term resolved).
//! * Equilibrium: the reactions on the clamped face sum to +P in y, and the
//!   applied nodal loads sum to −P (round-off).
//!
//! Run: `cargo test --release --test cantilever -- --nocapture`.

#[path = "../common/mod.rs"]
mod common;

use std::sync::Mutex;
use std::time::Instant;

use flank::fem::model::{Model, NodalForce};
use flank::fem::static_analysis::{solve_static, SolveOptions, StaticSolution};
use flank::mesh::structured::{box_mesh, BoxElement};

/// Length, height (load direction y) and width (z), mm.
const L: f64 = 100.0;
const H: f64 = 10.0;
const B: f64 = 10.0;
/// Material (MPa) and load (N).
const E: f64 = 210_000.0;
const NU: f64 = 0.3;
const P: f64 = 1000.0;

/// The tests run in parallel threads by default; the solver already uses both
/// cores, and the printed run times should be those of one solve at a time.
static SERIAL: Mutex<()> = Mutex::new(());

/// The beam of Poisson's ratio ν.
fn beam(nu: f64) -> common::TipLoadedBeam {
    common::TipLoadedBeam {
        length: L,
        height: H,
        width: B,
        young: E,
        poisson: nu,
        load: P,
    }
}

/// Timoshenko tip deflection for a shear coefficient κ (ν = 0.3).
fn timoshenko(kappa: f64) -> f64 {
    beam(NU).timoshenko(kappa)
}

/// Timoshenko tip deflection for a shear coefficient κ and Poisson's ratio ν.
fn timoshenko_nu(kappa: f64, nu: f64) -> f64 {
    beam(nu).timoshenko(kappa)
}

/// Bending-only (Euler–Bernoulli) tip deflection P L³ / (3 E I), for comparison.
fn euler_bernoulli() -> f64 {
    beam(NU).euler_bernoulli()
}

/// Cowper's shear coefficient of a rectangular section.
fn kappa_cowper() -> f64 {
    beam(NU).cowper_kappa()
}

/// One solved cantilever and the figures taken from it.
struct Result {
    /// Area-weighted mean tip deflection −∫u_y dA / A (mm, positive downwards).
    delta: f64,
    /// Mean σ_xx over the nodes of the top fibre at mid-span (MPa).
    sigma_mid: f64,
    /// Largest relative deviation of those nodes from M c / I.
    sigma_spread: f64,
    dofs: usize,
    seconds: f64,
}

/// Builds, solves and post-processes the cantilever on `cells` elements of `kind`.
fn cantilever(cells: [usize; 3], kind: BoxElement) -> Result {
    cantilever_nu(cells, kind, NU)
}

/// Same, for Poisson's ratio `nu`.
fn cantilever_nu(cells: [usize; 3], kind: BoxElement, nu: f64) -> Result {
    let mesh = box_mesh([L, H, B], cells, kind);
    let mut model = common::model_from_mesh(mesh, E, nu);

    // Clamp: every component of every node on x = 0.
    common::fix_set(&mut model, "X0", &[0, 1, 2], 0.0);

    // Tip load: w_a = ∫ N_a dA over the tip face, assembled face by face; the
    // nodal force is −τ w_a in y. The same weights give the exact area mean of u_y.
    let tau = P / (B * H);
    let weight = common::face_weights(&model, "X1");
    let area: f64 = weight.iter().sum();
    assert!((area - B * H).abs() < 1e-10 * B * H, "tip face area {area}");
    for (n, &w) in weight.iter().enumerate() {
        if w != 0.0 {
            model.forces.push(NodalForce {
                node: n,
                component: 1,
                value: -tau * w,
            });
        }
    }
    let applied: f64 = model.forces.iter().map(|f| f.value).sum();
    assert!((applied + P).abs() < 1e-9 * P, "applied load {applied}");

    let t = Instant::now();
    let sol = solve_static(&model, &SolveOptions::default()).expect("cantilever solves");
    let seconds = t.elapsed().as_secs_f64();

    check_equilibrium(&model, &sol);

    let u = &sol.displacement;
    let delta = -weight
        .iter()
        .enumerate()
        .map(|(n, w)| w * u[3 * n + 1])
        .sum::<f64>()
        / area;

    // Bending stress at mid-span, top fibre: all nodes on the line x = L/2, y = h.
    let stress = &sol.recovery.as_ref().expect("stresses recovered").stress;
    let reference = sigma_reference();
    let line: Vec<f64> = (0..model.mesh.node_count())
        .filter(|&n| {
            let x = model.mesh.coords[n];
            (x[0] - 0.5 * L).abs() < 1e-9 && (x[1] - H).abs() < 1e-9
        })
        .map(|n| stress[n][0])
        .collect();
    assert!(
        !line.is_empty(),
        "no nodes at mid-span top fibre for {cells:?}"
    );
    let sigma_mid = line.iter().sum::<f64>() / line.len() as f64;
    let sigma_spread = line
        .iter()
        .map(|s| ((s - reference) / reference).abs())
        .fold(0.0, f64::max);

    Result {
        delta,
        sigma_mid,
        sigma_spread,
        dofs: sol.stats.dofs,
        seconds,
    }
}

/// M c / I at mid-span, top fibre (tension for a load in −y).
fn sigma_reference() -> f64 {
    let i = B * H.powi(3) / 12.0;
    P * (L / 2.0) * (H / 2.0) / i
}

/// Reactions on the clamped face balance the load: Σ R_y = +P, Σ R_x = Σ R_z = 0.
fn check_equilibrium(model: &Model, sol: &StaticSolution) {
    let r = sol.reaction.as_ref().expect("reactions recovered");
    let mut sum = [0.0; 3];
    for &n in &model.mesh.node_sets["X0"] {
        for k in 0..3 {
            sum[k] += r[3 * n + k];
        }
    }
    assert!(
        (sum[1] - P).abs() < 1e-6 * P,
        "reaction R_y = {} (expected {P})",
        sum[1]
    );
    assert!(
        sum[0].abs() < 1e-6 * P && sum[2].abs() < 1e-6 * P,
        "reaction {sum:?}"
    );
}

fn print_header() {
    println!(
        "Timoshenko δ: κ = 5/6 → {:.6} mm, Cowper κ = {:.4} → {:.6} mm (Euler–Bernoulli {:.6} mm); M c / I = {:.3} MPa",
        timoshenko(5.0 / 6.0),
        kappa_cowper(),
        timoshenko(kappa_cowper()),
        euler_bernoulli(),
        sigma_reference()
    );
}

fn report(label: &str, cells: [usize; 3], r: &Result) {
    let d56 = timoshenko(5.0 / 6.0);
    let dc = timoshenko(kappa_cowper());
    let eb = euler_bernoulli();
    println!(
        "{label:<8} {:>12} {:>7} DOFs  δ = {:.6} mm  err(κ=5/6) {:+.3e}  err(Cowper) {:+.3e}  err(EB) {:+.3e}  σ_xx(L/2, h) = {:.3} MPa (err {:+.3e}, max node dev {:.2e})  {:.2} s",
        format!("{cells:?}"),
        r.dofs,
        r.delta,
        (r.delta - d56) / d56,
        (r.delta - dc) / dc,
        (r.delta - eb) / eb,
        r.sigma_mid,
        (r.sigma_mid - sigma_reference()) / sigma_reference(),
        r.sigma_spread,
        r.seconds
    );
}

/// Hex20 mesh sequence: monotone, Cauchy-convergent, finest within 1 %.
#[test]
fn hex20_convergence() {
    let _guard = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    print_header();
    let meshes = [[10, 1, 1], [20, 2, 2], [40, 4, 4], [80, 8, 8]];
    let results: Vec<Result> = meshes
        .iter()
        .map(|&c| {
            let r = cantilever(c, BoxElement::Hex20);
            report("Hex20", c, &r);
            r
        })
        .collect();

    // Nested meshes, exact integration: the compliance P·δ can only grow.
    for k in 1..results.len() {
        assert!(
            results[k].delta > results[k - 1].delta,
            "δ not increasing: {:?} → {:?}",
            results[k - 1].delta,
            results[k].delta
        );
    }
    // Successive differences shrink (Cauchy sequence); print the observed ratio.
    let diffs: Vec<f64> = results
        .windows(2)
        .map(|w| w[1].delta - w[0].delta)
        .collect();
    for k in 1..diffs.len() {
        println!(
            "Cauchy: |δ{} − δ{}| = {:.3e}, ratio to previous difference {:.3}",
            k + 1,
            k,
            diffs[k],
            diffs[k] / diffs[k - 1]
        );
        assert!(
            diffs[k] < diffs[k - 1],
            "differences not shrinking: {diffs:?}"
        );
    }
    // Aitken/Richardson limit from the last three values (reported, not asserted).
    let n = results.len();
    let (d1, d2, d3) = (
        results[n - 3].delta,
        results[n - 2].delta,
        results[n - 1].delta,
    );
    let limit = d3 - (d3 - d2).powi(2) / ((d3 - d2) - (d2 - d1));
    println!(
        "Aitken limit of the Hex20 sequence: {limit:.6} mm ({:+.3e} vs κ = 5/6, {:+.3e} vs Cowper)",
        (limit - timoshenko(5.0 / 6.0)) / timoshenko(5.0 / 6.0),
        (limit - timoshenko(kappa_cowper())) / timoshenko(kappa_cowper())
    );

    let fin = &results[n - 1];
    common::check(
        "cantilever",
        "Hex20 80x8x8 tip deflection (κ=5/6)",
        fin.delta,
        timoshenko(5.0 / 6.0),
        0.01,
        fin.seconds,
    );
    for (c, r) in meshes.iter().zip(&results).skip(2) {
        common::check(
            "cantilever",
            &format!("Hex20 {}x{}x{} σ_xx mid-span top", c[0], c[1], c[2]),
            r.sigma_mid,
            sigma_reference(),
            0.01,
            r.seconds,
        );
    }
}

/// Hex20R (reduced integration) and Wedge15: (20,2,2) reported, (40,4,4)
/// asserted (1 % on δ and on σ_xx). The (20,2,2) mesh is not a converged mesh
/// for any of the three elements (Hex20 itself is 1.05 % off there).
#[test]
fn other_elements() {
    let _guard = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    print_header();
    for (kind, label) in [
        (BoxElement::Hex20R, "Hex20R"),
        (BoxElement::Wedge15, "Wedge15"),
    ] {
        for c in [[20, 2, 2], [40, 4, 4]] {
            let r = cantilever(c, kind);
            report(label, c, &r);
            if c[0] == 40 {
                common::check(
                    "cantilever",
                    &format!("{label} {}x{}x{} tip deflection (κ=5/6)", c[0], c[1], c[2]),
                    r.delta,
                    timoshenko(5.0 / 6.0),
                    0.01,
                    r.seconds,
                );
                common::check(
                    "cantilever",
                    &format!("{label} {}x{}x{} σ_xx mid-span top", c[0], c[1], c[2]),
                    r.sigma_mid,
                    sigma_reference(),
                    0.01,
                    r.seconds,
                );
            }
        }
    }
}

/// Why the 3D limit lies 0.7 % below Timoshenko at ν = 0.3: the clamped face
/// also suppresses the Poisson (anticlastic) contraction where the bending
/// moment is largest, which stiffens the root. With ν = 0 that effect is
/// absent, the shear term is 0.60 % of δ, and the 3D answer must reproduce
/// Timoshenko much more closely: the residual end effects (warping restraint
/// at the clamp, load introduction at the tip) act over about one depth h,
/// i.e. a share of order h/L = 0.1 of the shear term, 0.06 % of δ. Tolerance
/// 0.1 % of δ, well below the 0.6 % by which Euler–Bernoulli misses, so this
/// check does discriminate the shear term.
#[test]
fn shear_term_without_poisson_clamp() {
    let _guard = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let reference = timoshenko_nu(5.0 / 6.0, 0.0);
    println!(
        "ν = 0: Timoshenko δ = {reference:.6} mm (κ = 5/6 = Cowper's value at ν = 0), Euler–Bernoulli {:.6} mm",
        euler_bernoulli()
    );
    for c in [[20, 2, 2], [40, 4, 4]] {
        let r = cantilever_nu(c, BoxElement::Hex20, 0.0);
        println!(
            "Hex20 ν=0 {:>12} δ = {:.6} mm  err(Timoshenko) {:+.3e}  err(EB) {:+.3e}  {:.2} s",
            format!("{c:?}"),
            r.delta,
            (r.delta - reference) / reference,
            (r.delta - euler_bernoulli()) / euler_bernoulli(),
            r.seconds
        );
        if c[0] == 40 {
            common::check(
                "cantilever",
                "Hex20 40x4x4 ν=0 tip deflection",
                r.delta,
                reference,
                1e-3,
                r.seconds,
            );
        }
    }
}
