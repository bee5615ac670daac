//! Hertz line contact in closed form (Johnson, *Contact Mechanics*, 1985,
//! §4.2, eqs. 4.43–4.45): the half-width and peak pressure of two
//! cylinders under a load per length, and the contact modulus E* of two
//! bodies. Used by the LTCA's local contact model ([`crate::ltca::local`])
//! and by the FE contact bands that resolve the Hertz width
//! ([`crate::mesh_cycle::contact_band`]).

use std::f64::consts::PI;

/// Hertz line contact: half-width a (mm) and peak pressure (MPa) for load
/// per length `p_line` (N/mm), equivalent radius `radius` (mm), contact
/// modulus `e_star` (MPa).
pub fn hertz_line(p_line: f64, radius: f64, e_star: f64) -> (f64, f64) {
    if !(p_line > 0.0 && radius > 0.0) {
        return (0.0, 0.0);
    }
    (
        (4.0 * p_line * radius / (PI * e_star)).sqrt(),
        (p_line * e_star / (PI * radius)).sqrt(),
    )
}

/// Contact modulus E* of two bodies (MPa).
pub fn contact_modulus(e: [f64; 2], nu: [f64; 2]) -> f64 {
    1.0 / ((1.0 - nu[0] * nu[0]) / e[0] + (1.0 - nu[1] * nu[1]) / e[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hertz_line_values() {
        // P′ = 1000 N/mm, R = 10 mm, E* = 113 187 MPa (steel/steel, ν 0.3)
        let e = contact_modulus([206e3, 206e3], [0.3, 0.3]);
        let (a, p) = hertz_line(1000.0, 10.0, e);
        assert!((a - (4.0 * 1e4 / (PI * e)).sqrt()).abs() < 1e-15);
        assert!(
            (p * a * PI / 2.0 - 1000.0).abs() < 1e-9,
            "P′ = π a p_max / 2"
        );
    }
}
