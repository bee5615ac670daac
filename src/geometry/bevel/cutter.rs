//! The face-milling cutter head (Gleason spread-blade / duplex type): one
//! blade per side, each a profile in the cutter's axial plane swept around
//! the cutter axis.
//!
//! Cutter frame: z_c along the cutter axis, from the blade tips (the tip
//! plane z_c = 0) into the blades; a blade point at profile parameter s and
//! cutter angle θ is r_c(s, θ) = (ρ(s) cos θ, ρ(s) sin θ, h(s)) (Litvin &
//! Fuentes, *Gear Geometry and Applied Theory*, 2nd ed., §20.2: the
//! generating cones of the head cutter; §20.3 for the edge radius
//! generating the fillet).
//!
//! Profile of one blade in the axial plane (ρ, h), σ = +1 for the
//! **outside** blade (its edge faces away from the cutter axis; it cuts the
//! **concave** flank), σ = −1 for the **inside** blade (convex flank):
//!
//! * main straight edge through the blade point (ρ, h) = (r_p, 0) at the
//!   blade (pressure) angle α to the cutter axis: (r_p + σ t sin α,
//!   t cos α);
//! * optional **Toprem**: below the height h_t the edge has the larger
//!   angle α + Δα (removes material at the work's root);
//! * optional **Flankrem / blade curvature**: the main edge is a circular
//!   arc of radius ρ_w, tangent to the straight edge where it starts and
//!   bending toward the work (it removes material toward the work's tip);
//! * the **edge radius** ρ_f: a circular arc tangent to the tip plane and
//!   to the lowest straight edge; it generates the fillet.
//!
//! s is the arc length from the tangent point of the edge radius with the
//! lowest straight edge (s < 0 on the edge radius, down to
//! s_min = −ρ_f (π/2 − α₁) where the arc meets the tip plane).

use num_dual::DualNum;

use crate::error::{FlankError, Result};

/// Which blade of the head.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BladeSide {
    /// Edge facing the cutter axis: cuts the convex flank.
    Inside,
    /// Edge facing away from the axis: cuts the concave flank.
    Outside,
}

impl BladeSide {
    /// σ = −1 (inside), +1 (outside).
    pub fn sigma(self) -> f64 {
        match self {
            BladeSide::Inside => -1.0,
            BladeSide::Outside => 1.0,
        }
    }
}

/// Toprem: a second, larger blade angle near the tip.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Toprem {
    /// Δα added to the blade angle below the start height (rad, > 0).
    pub angle: f64,
    /// Height above the tip plane where the Toprem edge meets the main
    /// edge (mm).
    pub height: f64,
}

/// One blade (module docs for the profile).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blade {
    pub side: BladeSide,
    /// Blade point radius r_p: radius of the main edge's intersection with
    /// the tip plane (mm).
    pub point_radius: f64,
    /// Blade (pressure) angle α of the main edge to the cutter axis (rad).
    pub pressure_angle: f64,
    /// Edge (tip) radius ρ_f (mm, ≥ 0).
    pub edge_radius: f64,
    pub toprem: Option<Toprem>,
    /// Flankrem / blade curvature: radius of the circular main edge (mm;
    /// None = straight).
    pub curvature_radius: Option<f64>,
    /// Blade height above the tip plane (mm): the profile's end.
    pub height: f64,
}

/// Derived constants of the profile (f64, computed once).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BladeProfile {
    sigma: f64,
    /// Angle of the lowest straight edge α₁ and of the main edge α.
    alpha1: f64,
    alpha: f64,
    rho_f: f64,
    /// Edge-radius centre (ρ, h).
    centre: (f64, f64),
    /// Tangent point T of the edge radius with the lowest edge.
    tangent_point: (f64, f64),
    /// s where the main edge starts (0 without Toprem) and its start point.
    s_main: f64,
    main_start: (f64, f64),
    curvature_radius: Option<f64>,
    /// s at the tip-plane end of the edge radius and at the blade top.
    pub s_min: f64,
    pub s_max: f64,
}

impl Blade {
    /// Checks the blade and derives its profile; errors name the field.
    pub fn profile(&self) -> Result<BladeProfile> {
        let bad = |m: String| {
            Err(FlankError::Model(format!(
                "cutter blade ({:?}): {m}",
                self.side
            )))
        };
        let a = self.pressure_angle;
        if !(a.is_finite() && a > -1.2 && a < 1.2) {
            return bad(format!("pressure_angle {a} rad outside (−1.2, 1.2)"));
        }
        if !(self.point_radius.is_finite() && self.point_radius > 0.0) {
            return bad(format!("point_radius {} must be > 0", self.point_radius));
        }
        if !(self.edge_radius.is_finite() && self.edge_radius >= 0.0) {
            return bad(format!("edge_radius {} must be ≥ 0", self.edge_radius));
        }
        if !(self.height.is_finite() && self.height > 0.0) {
            return bad(format!("height {} must be > 0", self.height));
        }
        if let Some(r) = self.curvature_radius {
            if !(r.is_finite() && r.abs() > self.height) {
                return bad(format!(
                    "curvature_radius {r} must exceed the blade height {}",
                    self.height
                ));
            }
        }
        let sigma = self.side.sigma();
        let (sa, ca) = a.sin_cos();
        let (alpha1, l0) = match self.toprem {
            Some(t) => {
                if !(t.angle.is_finite() && t.angle > 0.0 && a + t.angle < 1.4) {
                    return bad(format!("toprem angle {} must be in (0, 1.4 − α)", t.angle));
                }
                if !(t.height.is_finite() && t.height > 0.0 && t.height < self.height) {
                    return bad(format!("toprem height {} must be in (0, height)", t.height));
                }
                let a1 = a + t.angle;
                let k = (self.point_radius + sigma * t.height * sa / ca, t.height);
                let w = t.height / a1.cos();
                (a1, (k.0 - sigma * w * a1.sin(), k.1 - w * a1.cos()))
            }
            None => (a, (self.point_radius, 0.0)),
        };
        let (s1, c1) = alpha1.sin_cos();
        let rf = self.edge_radius;
        let st = rf * (1.0 - s1) / c1;
        let tp = (l0.0 + st * sigma * s1, l0.1 + st * c1);
        // centre = T − ρ_f n_b, n_b = (σ cos α₁, −sin α₁)
        let centre = (tp.0 - rf * sigma * c1, tp.1 + rf * s1);
        let (s_main, main_start) = match self.toprem {
            Some(t) => {
                let len = (t.height - tp.1) / c1;
                if len <= 0.0 {
                    return bad(format!(
                        "toprem height {} lies inside the edge radius (tangent at {:.4})",
                        t.height, tp.1
                    ));
                }
                (len, (tp.0 + sigma * len * s1, t.height))
            }
            None => (0.0, tp),
        };
        if self.height <= main_start.1 {
            return bad(format!(
                "height {} below the edge radius / toprem",
                self.height
            ));
        }
        let s_max = s_main + (self.height - main_start.1) / ca;
        let s_min = -rf * (std::f64::consts::FRAC_PI_2 - alpha1);
        let p = BladeProfile {
            sigma,
            alpha1,
            alpha: a,
            rho_f: rf,
            centre,
            tangent_point: tp,
            s_main,
            main_start,
            curvature_radius: self.curvature_radius,
            s_min,
            s_max,
        };
        // the edge must stay on its side of the cutter axis
        let inner = [s_min, 0.0, s_main, s_max]
            .iter()
            .map(|&s| p.rho_h(s).0)
            .fold(f64::INFINITY, f64::min);
        if inner <= 0.0 {
            return bad(format!(
                "the profile crosses the cutter axis (radius {inner:.4} mm): point_radius too small"
            ));
        }
        Ok(p)
    }
}

impl BladeProfile {
    /// σ: +1 outside blade, −1 inside blade.
    pub fn sigma(&self) -> f64 {
        self.sigma
    }

    /// s at the end of the edge radius (start of the straight edge): 0.
    pub fn form_parameter(&self) -> f64 {
        0.0
    }

    /// s at height `h` above the tip plane on the straight edges (for a
    /// start guess; exact without curvature).
    pub fn s_at_height(&self, h: f64) -> f64 {
        if h <= self.main_start.1 {
            (h - self.tangent_point.1) / self.alpha1.cos()
        } else {
            self.s_main + (h - self.main_start.1) / self.alpha.cos()
        }
    }

    /// (ρ(s), h(s)) in the cutter's axial plane, generic over dual numbers
    /// (the piece is chosen by the real part of s).
    pub fn profile<D: DualNum<Primitive = f64> + Copy>(&self, s: D) -> (D, D) {
        let sig = self.sigma;
        let sr = s.re();
        if sr < 0.0 && self.rho_f > 0.0 {
            // edge radius: c + ρ_f (σ cos(α₁ − φ), −sin(α₁ − φ)), φ = s/ρ_f
            let ang = -(s / self.rho_f) + self.alpha1;
            (
                ang.cos() * (sig * self.rho_f) + self.centre.0,
                -(ang.sin() * self.rho_f) + self.centre.1,
            )
        } else if sr < self.s_main {
            let (s1, c1) = self.alpha1.sin_cos();
            (
                s * (sig * s1) + self.tangent_point.0,
                s * c1 + self.tangent_point.1,
            )
        } else {
            let t = s - self.s_main;
            let (sa, ca) = self.alpha.sin_cos();
            let (m0, m1) = self.main_start;
            match self.curvature_radius {
                None => (t * (sig * sa) + m0, t * ca + m1),
                Some(rw) => {
                    // arc tangent to the edge at its start, bending toward
                    // the work (+n_b = (σ cos α, −sin α))
                    let e = t / rw;
                    let (se, ome) = (e.sin() * rw, (-(e.cos()) + 1.0) * rw);
                    (
                        se * (sig * sa) + ome * (sig * ca) + m0,
                        se * ca - ome * sa + m1,
                    )
                }
            }
        }
    }

    /// (ρ, h) for a plain f64 s.
    pub fn rho_h(&self, s: f64) -> (f64, f64) {
        self.profile(s)
    }
}

/// A face-milling cutter head: the two blades.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CutterHead {
    pub inside: Blade,
    pub outside: Blade,
}

impl CutterHead {
    /// A head of mean (nominal) radius r_c and point width W: blade point
    /// radii r_c ∓ W/2, the given blade angles (inside, outside), edge
    /// radius and blade height, no Toprem or curvature.
    pub fn new(
        mean_radius: f64,
        point_width: f64,
        pressure_angles: (f64, f64),
        edge_radius: f64,
        height: f64,
    ) -> Result<Self> {
        if !(point_width.is_finite() && point_width > 0.0 && point_width < mean_radius) {
            return Err(FlankError::Model(format!(
                "cutter: point_width {point_width} must be in (0, mean radius {mean_radius})"
            )));
        }
        let blade = |side, r, a| Blade {
            side,
            point_radius: r,
            pressure_angle: a,
            edge_radius,
            toprem: None,
            curvature_radius: None,
            height,
        };
        let head = CutterHead {
            inside: blade(
                BladeSide::Inside,
                mean_radius - 0.5 * point_width,
                pressure_angles.0,
            ),
            outside: blade(
                BladeSide::Outside,
                mean_radius + 0.5 * point_width,
                pressure_angles.1,
            ),
        };
        // the edge radii must fit the point width
        let (pi, po) = (head.inside.profile()?, head.outside.profile()?);
        let gap = po.rho_h(po.s_min).0 - pi.rho_h(pi.s_min).0;
        if gap < -1e-12 {
            return Err(FlankError::Model(format!(
                "cutter: edge_radius {edge_radius} too large for point_width {point_width}"
            )));
        }
        Ok(head)
    }

    /// The blade of one side.
    pub fn blade(&self, side: BladeSide) -> &Blade {
        match side {
            BladeSide::Inside => &self.inside,
            BladeSide::Outside => &self.outside,
        }
    }

    /// Point width W = r_p,outside − r_p,inside (mm).
    pub fn point_width(&self) -> f64 {
        self.outside.point_radius - self.inside.point_radius
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn blade(side: BladeSide) -> Blade {
        Blade {
            side,
            point_radius: 75.0,
            pressure_angle: 20f64.to_radians(),
            edge_radius: 1.0,
            toprem: None,
            curvature_radius: None,
            height: 12.0,
        }
    }

    /// The edge radius is tangent to the tip plane at s_min and to the
    /// edge at s = 0; the straight edge passes through the blade point.
    #[test]
    fn profile_is_continuous_and_tangent() {
        for side in [BladeSide::Inside, BladeSide::Outside] {
            let b = blade(side);
            let p = b.profile().unwrap();
            let (rho, h) = p.rho_h(p.s_min);
            assert!(h.abs() < 1e-12, "{h}");
            let _ = rho;
            // through (r_p, 0) extrapolated: ρ − σ h tan α = r_p on the edge
            let (r5, h5) = p.rho_h(5.0);
            let a = b.pressure_angle;
            assert!((r5 - p.sigma() * h5 * a.tan() - 75.0).abs() < 1e-12);
            // C¹ at s = 0
            let e = 1e-7;
            let (ra, ha) = p.rho_h(-e);
            let (rb, hb) = p.rho_h(e);
            assert!(((rb - ra) / (2.0 * e) - p.sigma() * a.sin()).abs() < 1e-6);
            assert!(((hb - ha) / (2.0 * e) - a.cos()).abs() < 1e-6);
            // unit speed on the arc
            let (r1, h1) = p.rho_h(-0.3 - e);
            let (r2, h2) = p.rho_h(-0.3 + e);
            assert!(
                (((r2 - r1).powi(2) + (h2 - h1).powi(2)).sqrt() / (2.0 * e) - 1.0).abs() < 1e-6
            );
        }
    }

    #[test]
    fn toprem_and_curvature() {
        let mut b = blade(BladeSide::Outside);
        b.toprem = Some(Toprem {
            angle: 4f64.to_radians(),
            height: 2.5,
        });
        b.curvature_radius = Some(400.0);
        let p = b.profile().unwrap();
        let (_, h) = p.rho_h(p.s_min);
        assert!(h.abs() < 1e-12);
        // the main edge starts at the toprem height on the main line
        let (rk, hk) = p.rho_h(p.s_main);
        assert!((hk - 2.5).abs() < 1e-12);
        assert!((rk - 75.0 - 2.5 * b.pressure_angle.tan()).abs() < 1e-12);
        // curvature: the edge leaves the straight line toward the work
        let s = p.s_main + 8.0;
        let (r, h) = p.rho_h(s);
        let straight = 75.0 + h * b.pressure_angle.tan();
        let dev = (r - straight) * b.pressure_angle.cos();
        // sagitta ≈ L²/(2 ρ_w)
        assert!((dev - 64.0 / 800.0).abs() < 2e-3, "{dev}");
        // bad input names the field
        b.toprem = Some(Toprem {
            angle: -0.1,
            height: 2.5,
        });
        let e = b.profile().unwrap_err().to_string();
        assert!(e.contains("toprem angle"), "{e}");
        assert!(CutterHead::new(75.0, 0.5, (0.35, 0.35), 2.0, 10.0).is_err());
    }
}
