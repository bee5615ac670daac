//! Unit tests of `generation`, in their own file so that the module reads on its own.

use super::*;

/// A plane crown-gear tooth (rack-like plane through the work's axis
/// offset) rolling on a cylinder: the classical involute as the
/// envelope, checked in closed form. Tool: the plane x = s sin α·…;
/// here the simplest: a straight rack flank in the plane, generating a
/// spur involute of base radius r_b = r cos α. q = (s along the rack
/// flank, θ = axial coordinate, ψ = roll angle of the work).
#[derive(Debug)]
struct RackRoll {
    r: f64,
    alpha: f64,
}

impl RackRoll {
    fn pos<D: DualNum<Primitive = f64> + Copy>(&self, q: [D; 3]) -> [D; 3] {
        let (s, th, psi) = (q[0], q[1], q[2]);
        let (sa, ca) = self.alpha.sin_cos();
        // rack flank in the rack frame (pitch line y = r, rack moves
        // along x by r ψ): point = (s sin α + r ψ, r − s cos α, θ)
        let xr = s * sa + psi * self.r;
        let yr = -(s * ca) + self.r;
        // into the work frame, rotated by −ψ
        let (sp, cp) = (psi.sin(), psi.cos());
        [xr * cp + yr * sp, -(xr * sp) + yr * cp, th]
    }
}

impl EnvelopeMap for RackRoll {
    fn jet(&self, q: [f64; 3]) -> Jet {
        jet_of(q, |x| self.pos(x))
    }
    fn normal_orientation(&self) -> f64 {
        1.0
    }
}

#[test]
fn jet_matches_finite_differences() {
    let m = RackRoll {
        r: 50.0,
        alpha: 0.35,
    };
    let q = [1.3, 2.0, 0.07];
    let j = m.jet(q);
    let h = 1e-5;
    for k in 0..3 {
        let mut qp = q;
        let mut qm = q;
        qp[k] += h;
        qm[k] -= h;
        let jp = m.jet(qp);
        let jm = m.jet(qm);
        for c in 0..3 {
            let fd = (jp.r[c] - jm.r[c]) / (2.0 * h);
            assert!((fd - j.d1[k][c]).abs() < 1e-7, "d1 {k} {c}");
            for l in 0..3 {
                let fd2 = (jp.d1[l][c] - jm.d1[l][c]) / (2.0 * h);
                assert!((fd2 - j.d2[k][l][c]).abs() < 1e-6, "d2 {k} {l} {c}");
            }
        }
    }
    let (f, g) = meshing(&j);
    let jp = m.jet([q[0], q[1], q[2] + h]);
    let jm = m.jet([q[0], q[1], q[2] - h]);
    let fd = (meshing(&jp).0 - meshing(&jm).0) / (2.0 * h);
    assert!(
        (fd - g[2]).abs() < 1e-6 * (1.0 + g[2].abs()),
        "{fd} {:?}",
        g
    );
    assert!(f.is_finite());
}

/// The rack-generated envelope is the involute of r_b = r cos α: every
/// solved point lies at involute polar angle inv(α_y) relative to the
/// base-circle start, and the meshing residual vanishes.
#[test]
fn rack_envelope_is_involute() {
    let m = RackRoll {
        r: 50.0,
        alpha: 20f64.to_radians(),
    };
    let rb = 50.0 * m.alpha.cos();
    let opt = SolveOptions::default();
    // axial section here: z = θ, ρ = radius
    let mut q = [0.0, 0.0, 0.0];
    let mut angles = vec![];
    for i in 0..9 {
        let rho = 48.0 + 0.5 * i as f64;
        let p = solve_axial(&m, 3.0, rho, q, &opt).unwrap();
        q = p.q;
        assert!(p.meshing_residual().abs() < 1e-12);
        let (z, r) = axial_radius(p.jet.r);
        assert!((z - 3.0).abs() < 1e-12 && (r - rho).abs() < 1e-12);
        let ay = (rb / rho).acos();
        let inv = ay.tan() - ay;
        angles.push(p.jet.r[1].atan2(p.jet.r[0]) + inv);
        // the normal is perpendicular to the radial-section tangent
        let (t, _) = p.section_tangent(0.0, 1.0).unwrap();
        assert!(dot(t, p.normal).abs() < 1e-12 * norm(t));
    }
    // the polar angle + inv(α_y) is constant on an involute
    for a in &angles {
        assert!((a - angles[0]).abs() < 1e-12, "{angles:?}");
    }
}

/// The rack roll with the length-scaled meshing row (f/L, L = 1 since
/// |r_s × r_θ| = 1) and a capped roll step: the same involute, the row
/// n·r_ψ ≤ 1e-12 mm. (The instantaneous axis itself, where r_ψ = 0, is
/// exercised by the conjugate pinion of the E = 0 pair F2 in
/// `verification/bevel_conjugate`: its whole pitch line.)
#[test]
fn length_scaled_meshing_row() {
    #[derive(Debug)]
    struct Scaled(RackRoll);
    impl EnvelopeMap for Scaled {
        fn jet(&self, q: [f64; 3]) -> Jet {
            self.0.jet(q)
        }
        fn normal_orientation(&self) -> f64 {
            1.0
        }
        fn meshing_length(&self) -> Option<f64> {
            Some(1.0)
        }
        fn max_roll_step(&self) -> f64 {
            0.2
        }
    }
    let m = Scaled(RackRoll {
        r: 50.0,
        alpha: 20f64.to_radians(),
    });
    let rb = 50.0 * m.0.alpha.cos();
    let opt = SolveOptions::default();
    let start = solve_axial(&m, 3.0, 50.0, [0.0, 3.0, 0.0], &opt).unwrap();
    let mut angles = vec![];
    for i in 0..9 {
        let rho = 48.0 + 0.5 * i as f64;
        let p = solve_axial(&m, 3.0, rho, start.q, &opt).unwrap();
        let n_v = dot(p.normal, p.jet.d1[2]);
        assert!(n_v.abs() <= 1e-12, "n·r_ψ = {n_v:e} mm at ρ = {rho}");
        let (z, r) = axial_radius(p.jet.r);
        assert!((z - 3.0).abs() < 1e-12 && (r - rho).abs() < 1e-12);
        let ay = (rb / rho).acos();
        angles.push(p.jet.r[1].atan2(p.jet.r[0]) + ay.tan() - ay);
    }
    for a in &angles {
        assert!((a - angles[0]).abs() < 1e-12, "{angles:?}");
    }
    // a wild start: the roll step is capped, Newton still converges
    let p = solve_axial(&m, 3.0, 49.0, [0.0, 3.0, 1.0], &opt).unwrap();
    assert!((axial_radius(p.jet.r).1 - 49.0).abs() < 1e-12);
}

#[test]
fn singular_and_nonconvergent_are_errors() {
    let m = RackRoll {
        r: 50.0,
        alpha: 20f64.to_radians(),
    };
    let opt = SolveOptions {
        max_iterations: 1,
        ..SolveOptions::default()
    };
    let e = solve_axial(&m, 3.0, 49.0, [5.0, 0.0, 0.3], &opt).unwrap_err();
    assert!(matches!(e, EnvelopeError::NotConverged { .. }), "{e}");
    // inside the base circle there is no envelope point
    let e = solve_axial(&m, 3.0, 30.0, [0.0, 0.0, 0.0], &SolveOptions::default());
    assert!(e.is_err());
}
