//! The Klingelnberg Cyclo-Palloid hypoid pinion: cutter **tilt** and
//! **swivel**, the pinion head's **blade angle** and its **point width**
//! derived from the blank, so that the pinion generated on the gear's
//! crown gear meets its ISO 23509 blank at the mean point.
//!
//! **Why.** A face-hobbed pinion cut on the gear's generating crown gear
//! with the head upright ([`HobbingSetup::pinion_from_gear`]) is generated
//! in a motion that is not a rolling of its pitch cone on the crown gear
//! when the pair has an offset: the instantaneous axis is not the pitch
//! generatrix, so the points of its flanks on its own pitch cone are not
//! generated in the crown plane, and their pressure angles differ from the
//! crown gear's blade angles in opposite senses on the two flanks (seed
//! 000: 20.54° / 19.04° against the blank's 20° / 20°; on a spiral bevel
//! set, offset 0, they agree to 1e-5°).
//! Klingelnberg corrects this on the pinion by tilting the cutter head
//! (cutter tilt on the Cyclo-Palloid machines; Klingelnberg (ed.), *Bevel
//! Gear: Fundamentals and Applications*, Springer 2016, on the Cyclo-Palloid
//! process; Litvin & Fuentes, *Gear Geometry and Applied
//! Theory*, 2nd ed., §20.5 on tilt i and swivel j; Vimercati, Mech. Mach.
//! Theory 42 (2007) §3, tilt on the face-hobbed pinion). To first order a
//! head turned by the small rotation ω about a line of the crown plane
//! turns each flank normal n = ±cos α e_p + sin α e_z (e_p ⟂ the trace t
//! in the plane) by ω × n: the component of ω along t changes the two
//! flanks' pressure angles by ∓ω_t (their difference), the component
//! along e_p their spiral angles by ±ω_p tan α (again the difference, which
//! the blank does not fix: face hobbing's two flanks differ anyway), and
//! neither moves the mean of the two pressure angles or of the two spiral
//! angles to first order. So the head is tilted about t (the swivel puts
//! the tilt axis along t), the mean pressure-angle error is met by the
//! pinion head's blade angle (one angle on both blades: a standard
//! Cyclo-Palloid head's blades are symmetric) and the tooth thickness by the
//! point width. (A Newton on tilt and swivel alone for the two pressure
//! angles, or with the mean spiral angle as a third target, is singular to
//! first order: tried, it wandered to a 2.8° tilt on a spiral bevel set
//! that needs none.)
//!
//! **Construction** (frames of [`crate::geometry::bevel::cradle_machine`]):
//! the variables are the signed tilt i about the mean trace's tangent t at
//! P (swivel j with (cos j, sin j, 0) = t, [`HobbingSetup::mean_trace_swivel`];
//! the tilt rotation Rot_z(j) Rot_x(i) Rot_z(−j) of the machine), the
//! change Δα of both blade angles and the change Δw of the blades' spacing
//! at the pitch height (each blade moved by Δw/2 in its plane, away from
//! the other). The head turns about the **mean point** P at the pitch
//! height (the middle of the pinion's tooth, [`HobbingSetup::mean_point`]),
//! so the tooth is not cut deeper or shifted: the head centre C₀ moves to
//! C₁ = P + T (C₀ − P); its in-plane part gives the radial distance and the
//! cradle angle, its height C₁,z is taken up by the sliding base
//! (ΔX_B − C₁,z: moving the work along the cradle axis is the same relative
//! motion as moving the cutter, since the cradle turns about that axis).
//! Changing a blade angle keeps the blade's in-plane coordinate at the
//! pitch height. The tilted tip plane no longer sweeps the root cone; the
//! flank's root line is put where the tip reaches
//! ([`HobbingSetup::generated_root`], the blank's root slope kept).
//!
//! **Newton** ([`cyclo_palloid_pinion`]): the residual
//! (α_concave − α*_concave, α_convex − α*_convex, (s_mn − s*_mn)/R_m1)
//! measured on the generated flanks at their mean points (u = 0, v = R_m1;
//! pressure angles on the pinion's pitch cone as
//! [`FlankMeasure::on_pitch_cone`](crate::geometry::bevel::generated_surface::FlankMeasure::on_pitch_cone); s_mn = ρ_m Δφ cos β_m1 as
//! `machine_settings::check_mean_point`), its Jacobian by forward
//! differences, at most `max_iterations` steps, each bounded and halved
//! until the residual decreases (≤ 20 halvings); the error names the
//! residual reached.
//!
//! **What it does to the pair** (seed 000, `papers/seed000-hypoid`): the
//! upright pinion is the near-conjugate mate of the gear (TE 0.02″); the
//! tilted one meets the blank's pressure angles, so it departs from that
//! mate by the same ±0.5°–1° at the mean point: a deliberate profile
//! mismatch that localises the contact (README there has the TCA).

use nalgebra::{Matrix3, Vector3};

use crate::error::{FlankError, Result};
use crate::geometry::bevel::face_hobbing::tilt_matrix;
use crate::geometry::bevel::hobbing_settings::{
    measure_mean_point, HobbedMeanPoint, HobbingBlank, HobbingSetup,
};
use crate::geometry::vec3::V3;

/// The variables of the pinion setup (module docs): the head's tilt i
/// about the mean tooth trace's tangent at P (rad, signed), the
/// blade-angle change Δα (rad) and the spacing change Δw of the blades at
/// the pitch height (mm).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PinionTiltVariables {
    pub tilt: f64,
    pub blade_angle_change: f64,
    pub width_change: f64,
}

impl PinionTiltVariables {
    fn from_vec(x: &Vector3<f64>) -> Self {
        PinionTiltVariables {
            tilt: x[0],
            blade_angle_change: x[1],
            width_change: x[2],
        }
    }
}

impl HobbingSetup {
    /// The swivel j that puts the tilt axis (cos j, sin j, 0) along the
    /// tangent of the mean point's tooth trace in the crown plane: the
    /// trace's normal at P passes through the rolling circles' contact
    /// point I = C ρ_b/M on the line from the crown centre to the cutter
    /// centre C (ISO 23509 clause 6.3; `hobbing_settings` module docs).
    pub fn mean_trace_swivel(&self) -> f64 {
        let m = &self.settings.machine;
        let k = self.base_radius / m.radial_distance;
        let (sq, cq) = m.cradle_angle.sin_cos();
        let pi = [
            self.mean_point[0] - k * m.radial_distance * cq,
            self.mean_point[1] - k * m.radial_distance * sq,
        ];
        pi[0].atan2(-pi[1])
    }

    /// This setup (a pinion on the gear's crown gear, head upright) with
    /// the head turned about the mean point, the blade angles and the
    /// blades' spacing changed by `x` (module docs). Errors name the
    /// setting or blade.
    pub fn with_pinion_tilt(&self, x: &PinionTiltVariables) -> Result<Self> {
        let m0 = self.settings.machine;
        if m0.tilt != 0.0 || m0.swivel != 0.0 {
            return Err(FlankError::Model(
                "Cyclo-Palloid pinion tilt: the setup is already tilted (start from pinion_from_gear)"
                    .into(),
            ));
        }
        let swivel = self.mean_trace_swivel();
        let tilt = x.tilt;
        let t = tilt_matrix(tilt, swivel);
        let k = self.mean_point;
        let (sq, cq) = m0.cradle_angle.sin_cos();
        let d = [
            m0.radial_distance * cq - k[0],
            m0.radial_distance * sq - k[1],
            -k[2],
        ];
        let c1: V3 = std::array::from_fn(|r| k[r] + (0..3).map(|c| t[r][c] * d[c]).sum::<f64>());
        let mut machine = m0;
        machine.radial_distance = c1[0].hypot(c1[1]);
        machine.cradle_angle = c1[1].atan2(c1[0]);
        machine.sliding_base = m0.sliding_base - c1[2];
        machine.tilt = tilt;
        machine.swivel = swivel;
        let mut out =
            self.with_blade_changes(x.width_change, (x.blade_angle_change, x.blade_angle_change))?;
        out.settings.machine = machine;
        out.settings.validate()?;
        out.mean_point = [k[0], k[1], k[2] - c1[2]];
        Ok(out)
    }
}

/// The derived Cyclo-Palloid pinion setup's record: the variables, the
/// swivel (the mean trace's direction), the mean-point figures before
/// (head upright) and after, the Newton steps taken and the final residual
/// (the largest of the two pressure-angle errors in rad and the thickness
/// error / R_m1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PinionTilt {
    pub variables: PinionTiltVariables,
    pub swivel: f64,
    pub upright: HobbedMeanPoint,
    pub tilted: HobbedMeanPoint,
    pub iterations: usize,
    pub residual: f64,
}

/// Largest step of each variable in one Newton step (rad, rad, mm), and
/// the bound on the tilt (rad) beyond which the derivation is refused.
const STEP_BOUND: [f64; 3] = [0.02, 0.02, 0.5];
const TILT_BOUND: f64 = 0.35;
/// Forward-difference steps of the Jacobian (rad, rad, mm).
const FD_STEP: [f64; 3] = [1e-6, 1e-6, 1e-5];

/// The Cyclo-Palloid pinion (module docs): cut on the crown gear of `gear`
/// ([`HobbingSetup::pinion_from_gear`]), its head tilted about the mean
/// trace's tangent through P, its blade angle and point width set, by a
/// Newton on the three variables until the residual is ≤ `tol` (at most
/// `max_iterations` steps). Errs with the residual reached, or when the
/// tilt would exceed 0.35 rad, or when a trial setup does not generate the
/// mean point.
pub fn cyclo_palloid_pinion(
    gear: &HobbingSetup,
    pinion: HobbingBlank,
    generated: bool,
    tol: f64,
    max_iterations: usize,
) -> Result<(HobbingSetup, PinionTilt)> {
    if !generated {
        return Err(FlankError::Model(
            "Cyclo-Palloid pinion tilt: derived for a generated pinion only (a formate pinion has no generating roll)".into(),
        ));
    }
    let upright = HobbingSetup::pinion_from_gear(gear, pinion, true)?;
    let b = upright.blank;
    let target = Vector3::new(
        b.pressure_angle_concave,
        b.pressure_angle_convex,
        b.normal_thickness / b.mean_cone_distance,
    );
    let residual_of = |x: &Vector3<f64>| -> Result<(HobbingSetup, HobbedMeanPoint, Vector3<f64>)> {
        let s = upright.with_pinion_tilt(&PinionTiltVariables::from_vec(x))?;
        let m = measure_mean_point(&s)?;
        let f = Vector3::new(
            m.pressure_angle.0,
            m.pressure_angle.1,
            m.thickness / b.mean_cone_distance,
        ) - target;
        Ok((s, m, f))
    };
    let size = |f: &Vector3<f64>| f.amax();
    let mut x = Vector3::zeros();
    let (mut setup, first, mut f) = residual_of(&x)?;
    let mut measured = first;
    for it in 0..=max_iterations {
        let r = size(&f);
        if r <= tol {
            return Ok((
                setup,
                PinionTilt {
                    variables: PinionTiltVariables::from_vec(&x),
                    swivel: upright.mean_trace_swivel(),
                    upright: first,
                    tilted: measured,
                    iterations: it,
                    residual: r,
                },
            ));
        }
        if it == max_iterations {
            break;
        }
        let mut jac = Matrix3::zeros();
        for k in 0..3 {
            let mut xk = x;
            xk[k] += FD_STEP[k];
            let (_, _, fk) = residual_of(&xk)?;
            jac.set_column(k, &((fk - f) / FD_STEP[k]));
        }
        let step = jac.lu().solve(&(-f)).ok_or_else(|| {
            FlankError::Model(format!(
                "Cyclo-Palloid pinion tilt: singular Jacobian at step {it} (residual {r:.3e})"
            ))
        })?;
        let scale = (0..3)
            .map(|k| (STEP_BOUND[k] / step[k].abs()).min(1.0))
            .fold(1.0f64, f64::min);
        // halve until the residual decreases (at most 20 halvings)
        let mut lambda = scale;
        let mut accepted = None;
        for _ in 0..20 {
            let xn = x + step * lambda;
            if xn[0].abs() > TILT_BOUND {
                return Err(FlankError::Model(format!(
                    "Cyclo-Palloid pinion tilt: the tilt would exceed {TILT_BOUND} rad at step {it} (residual {r:.3e}): the blank's pressure angles are not reached by tilting this pinion's head"
                )));
            }
            if let Ok((s, m, fnew)) = residual_of(&xn) {
                if size(&fnew) < r {
                    accepted = Some((xn, s, m, fnew));
                    break;
                }
            }
            lambda *= 0.5;
        }
        let Some((xn, s, m, fnew)) = accepted else {
            return Err(FlankError::Model(format!(
                "Cyclo-Palloid pinion tilt: no decreasing step at step {it} (residual {r:.3e})"
            )));
        };
        x = xn;
        setup = s;
        measured = m;
        f = fnew;
    }
    Err(FlankError::Model(format!(
        "Cyclo-Palloid pinion tilt: the residual did not reach {tol:e} in {max_iterations} Newton steps (last {:.3e}: pressure angles {:.3e} / {:.3e} rad, thickness {:.3e} mm)",
        size(&f),
        f[0],
        f[1],
        f[2] * b.mean_cone_distance
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::bevel::body::{angle_from_y, wrap_angle};
    use crate::geometry::bevel::cutter::BladeSide;
    use crate::geometry::bevel::cutting::CutterSpec;
    use crate::geometry::bevel::hobbing_settings::{HobbingCutter, Member};
    use crate::geometry::bevel::{blank_design, BlankInputs};
    use crate::geometry::surface::ToothSurface;
    use crate::geometry::vec3::{dot, norm};

    /// Seed 000's blank (papers/seed000-hypoid/scene.toml), offset `a` mm.
    fn seed000(a: f64) -> (HobbingSetup, HobbingBlank) {
        let json = format!(
            r#"{{"method": 3, "Sigma_deg": 90.0, "a_mm": {a}, "z1": 12, "z2": 41,
 "de2_mm": 213.2, "b2_mm": 32.0, "beta_m2_deg": 32.0, "rc0_mm": 100.0, "z0": 5,
 "data_type": "I", "alpha_dD_deg": 20.0, "alpha_dC_deg": 20.0, "f_alim": 0.0,
 "k_hap": 1.0, "k_hfp": 1.25, "x_hm1": 0.53, "x_smn": 0.0}}"#
        );
        let d = blank_design(&BlankInputs::from_json(&json).unwrap()).unwrap();
        let spec = CutterSpec::of_blank(&d);
        let cutter = HobbingCutter {
            radius: spec.radius,
            blade_groups: spec.blade_groups.unwrap(),
            edge_radius: spec.edge_radius,
        };
        // right-hand gear (κ = −1), left-hand pinion (κ = +1), as the scene
        let gb = HobbingBlank {
            hand: -1.0,
            ..HobbingBlank::from_design(&d, Member::Gear).unwrap()
        };
        let pb = HobbingBlank {
            hand: 1.0,
            ..HobbingBlank::from_design(&d, Member::Pinion).unwrap()
        };
        (HobbingSetup::new(gb, cutter, true).unwrap(), pb)
    }

    /// Seed 000 (hypoid, a = 30 mm): the upright pinion misses the blank's
    /// 20°/20° by more than 0.5° on each flank; the derived setup meets the
    /// blank's pressure angles, the mean spiral angle β_m1 and s_mn1 to
    /// 1e-9 (measured again on the full flanks, not the Newton's own
    /// mean-point solve); its surfaces satisfy the equation of meshing to
    /// 1e-10 with normals ⟂ r_u, r_v on a 21 × 11 grid of both flanks.
    #[test]
    fn seed000_tilted_pinion_meets_the_blank() {
        let (gear, pb) = seed000(30.0);
        let t0 = std::time::Instant::now();
        let (s, fit) = cyclo_palloid_pinion(&gear, pb, true, 1e-10, 30).unwrap();
        let took = t0.elapsed().as_secs_f64();
        let deg = f64::to_degrees;
        println!(
            "seed 000 pinion: tilt {:.6}°, swivel {:.4}°, blade angle change {:+.6}°, point width change {:+.6} mm, {} Newton steps, residual {:.2e}, {took:.3} s",
            deg(fit.variables.tilt),
            deg(fit.swivel),
            deg(fit.variables.blade_angle_change),
            fit.variables.width_change,
            fit.iterations,
            fit.residual
        );
        println!(
            "  upright: α {:.6}° / {:.6}°, β {:.6}° / {:.6}°, s_mn {:.6} mm",
            deg(fit.upright.pressure_angle.0),
            deg(fit.upright.pressure_angle.1),
            deg(fit.upright.spiral_angle.0),
            deg(fit.upright.spiral_angle.1),
            fit.upright.thickness
        );
        for a in [fit.upright.pressure_angle.0, fit.upright.pressure_angle.1] {
            assert!((a - pb.pressure_angle_concave).abs() > 0.5f64.to_radians());
        }
        assert!(fit.residual <= 1e-10 && fit.variables.tilt != 0.0);
        // the tilt axis is the mean trace's tangent, which makes β_m1 with
        // the pinion's generatrix (+x_m) on this left-hand pinion
        assert!(
            (fit.swivel - pb.spiral_angle).abs() < 1e-9,
            "{}",
            fit.swivel
        );
        let rm = pb.mean_cone_distance;
        let (cc, cv) = (
            s.flank(BladeSide::Outside).unwrap(),
            s.flank(BladeSide::Inside).unwrap(),
        );
        let (mc, mv) = (cc.measure(0.0, rm).unwrap(), cv.measure(0.0, rm).unwrap());
        let err = [
            mc.pressure_angle - pb.pressure_angle_concave,
            mv.pressure_angle - pb.pressure_angle_convex,
        ];
        // the mean spiral angle is not a target: a tilt along the trace
        // changes it to second order only
        let beta = 0.5 * (mc.spiral_angle + mv.spiral_angle) - pb.spiral_angle;
        let (pa, pv) = (cc.point(0.0, rm), cv.point(0.0, rm));
        let d = wrap_angle(angle_from_y(pa) - angle_from_y(pv)).abs();
        let s_mn = rm * pb.pitch_angle.sin() * d * pb.spiral_angle.cos();
        println!(
            "  tilted, on the flanks: α {:.10}° / {:.10}° (errors {:.2e} / {:.2e} rad), β {:.6}° / {:.6}° (mean − β_m1 {:.2e} rad), s_mn {:.9} mm (blank {:.9})",
            deg(mc.pressure_angle),
            deg(mv.pressure_angle),
            err[0],
            err[1],
            deg(mc.spiral_angle),
            deg(mv.spiral_angle),
            beta,
            s_mn,
            pb.normal_thickness
        );
        for e in err {
            assert!(e.abs() <= 1e-9, "{err:?}");
        }
        assert!((s_mn - pb.normal_thickness).abs() <= 1e-9 * rm);
        assert!(beta.abs() < 1e-3, "{beta}");
        assert!((mc.cone_distance - rm).abs() < 1e-9 && (mv.cone_distance - rm).abs() < 1e-9);
        // the head turned about P: the blade at P is still at the pitch
        // height (the tilted mean point is where the upright one was,
        // relative to the work)
        let (mut mesh, mut orth) = (0.0f64, 0.0f64);
        for f in [&cc, &cv] {
            let (r0, r1) = f.v_range();
            for j in 0..11 {
                let v = r0 + (r1 - r0) * j as f64 / 10.0;
                let (ur, ut) = (f.u_root(v), f.u_tip(v));
                for i in 0..21 {
                    let u = ur + (ut - ur) * i as f64 / 20.0;
                    mesh = mesh.max(f.meshing_residual(u, v).unwrap().abs());
                    let (_, n, ru, rv) = f.try_evaluate(u, v).unwrap();
                    orth = orth
                        .max(dot(n, ru).abs() / norm(ru))
                        .max(dot(n, rv).abs() / norm(rv));
                }
            }
        }
        println!("  meshing residual ≤ {mesh:.2e}, |n·r_u|/|r_u|, |n·r_v|/|r_v| ≤ {orth:.2e}");
        assert!(mesh <= 1e-10 && orth <= 1e-10, "{mesh} {orth}");
    }

    /// Offset 0 (the seed-000 blank as a spiral bevel set): the pinion on
    /// the gear's crown gear rolls on it, so the upright head already meets
    /// the blank's pressure angles and the derived tilt is nil (≤ 1e-7 rad).
    #[test]
    fn spiral_bevel_needs_no_tilt() {
        let (gear, pb) = seed000(0.0);
        let (_, fit) = cyclo_palloid_pinion(&gear, pb, true, 1e-10, 30).unwrap();
        println!(
            "spiral bevel: upright α {:.10}° / {:.10}°; derived tilt {:.2e} rad, blade angle change {:.2e} rad, width change {:.2e} mm",
            fit.upright.pressure_angle.0.to_degrees(),
            fit.upright.pressure_angle.1.to_degrees(),
            fit.variables.tilt,
            fit.variables.blade_angle_change,
            fit.variables.width_change
        );
        assert!(fit.variables.tilt.abs() <= 1e-6 && fit.variables.blade_angle_change.abs() <= 1e-6);
    }

    /// Bad input: a formate pinion, a pressure angle no tilt within the
    /// bound reaches, and too few steps, each refused with the reason and
    /// the residual.
    #[test]
    fn unreachable_targets_are_refused_with_the_residual() {
        let (gear, pb) = seed000(30.0);
        let e = cyclo_palloid_pinion(&gear, pb, false, 1e-10, 30)
            .unwrap_err()
            .to_string();
        assert!(e.contains("generated"), "{e}");
        let far = HobbingBlank {
            pressure_angle_concave: pb.pressure_angle_concave + 0.8,
            ..pb
        };
        let e = cyclo_palloid_pinion(&gear, far, true, 1e-10, 30)
            .unwrap_err()
            .to_string();
        assert!(e.contains("residual"), "{e}");
        let e = cyclo_palloid_pinion(&gear, pb, true, 1e-10, 1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("did not reach") && e.contains("last"), "{e}");
        // a tilted setup is not tilted again
        let (s, _) = cyclo_palloid_pinion(&gear, pb, true, 1e-9, 30).unwrap();
        let e = s
            .with_pinion_tilt(&PinionTiltVariables::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("already tilted"), "{e}");
    }
}
