//! EHL film thickness and traction formulas of `flank::lubrication`
//! against values computed by hand from the formulas as published
//! (README.md shows the arithmetic), their regime flags, the seed's
//! transcription discrepancies, and bad lubricant data.
//!
//! Film: three operating points A (circular), B (R_y/R_x = 4), C (line,
//! R_y = ∞) in SI; Chittenden et al. 1985, Hamrock–Dowson 1977 and
//! Dowson–Higginson (line; central by Dowson–Toyoda) to 1e-5 relative
//! (the hand values are printed to 6 digits). Chittenden and Hamrock–Dowson
//! central films within 5 % of each other at all three points (two fits to
//! the same numerical solutions; a wrong exponent or group breaks this).
//!
//! Traction: four points T1…T4 with a MIL-PRF-23699 oil at 100 °C; Evans &
//! Johnson's thermal Eyring μ (β restored) to 1e-5; flags as computed by
//! hand (T2, T3 isothermal below thermal; T4 thermal μ ≤ 0 → isothermal
//! fallback, not Eyring).

use flank::error::FlankError;
use flank::lubrication::{
    film_thickness, reduced_modulus, traction, FilmFlag, FilmInput, FilmModel, Lubricant,
    LubricantSi, TractionFlag, TractionInput,
};

/// Relative tolerance against the 6-digit hand values.
const TOL: f64 = 1e-5;

fn oil() -> LubricantSi {
    LubricantSi {
        name: "MIL-PRF-23699 at 100 °C".into(),
        bulk_temperature_c: Some(100.0),
        viscosity_pa_s: 0.00468,
        pressure_viscosity_per_gpa: 10.0,
        temperature_viscosity_per_k: 0.0275,
        eyring_stress_mpa: 4.0,
        conductivity_w_per_m_k: 0.14,
        solid_density_kg_per_m3: 7800.0,
        solid_specific_heat_j_per_kg_k: 460.0,
        solid_conductivity_w_per_m_k: 45.0,
    }
}

/// E′ of two steels E = 206 GPa, ν = 0.3 (MPa).
fn e_prime() -> f64 {
    reduced_modulus([206_000.0; 2], [0.3; 2])
}

/// Operating point in SI → flank's internal units (mm, N, s, MPa).
fn film_input(
    eta_pa_s: f64,
    alpha_per_gpa: f64,
    rx_m: f64,
    ry_m: f64,
    w: f64,
    u: f64,
) -> FilmInput {
    FilmInput {
        viscosity: eta_pa_s * 1e-6,
        pressure_viscosity: alpha_per_gpa * 1e-3,
        reduced_modulus: e_prime(),
        radius_x: rx_m * 1e3,
        radius_y: ry_m * 1e3,
        load: w,
        length: 13.3,
        entraining_speed: u * 1e3,
    }
}

fn close(what: &str, got: f64, want: f64, tol: f64) {
    let e = got / want - 1.0;
    println!("{what:<34} {got:>12.6} {want:>12.6}  {e:+.2e}");
    assert!(e.abs() <= tol, "{what}: {got} vs {want} ({e:+.2e})");
}

#[test]
fn reduced_modulus_of_two_steels() {
    // E′ = E/(1 − ν²) = 206 GPa / 0.91
    close("E′ (GPa)", e_prime() * 1e-3, 226.374, TOL);
}

#[test]
fn film_thickness_against_hand_values() {
    // (name, input, [Chittenden hc, hmin], [HD hc, hmin], [DH hc, hmin]) in µm
    let points = [
        (
            "A circular",
            film_input(0.00468, 10.0, 5e-3, 5e-3, 1000.0, 10.0),
            [0.109724, 0.0646397],
            [0.113360, 0.0659339],
            [0.207257, 0.161596],
        ),
        (
            "B R_y/R_x = 4",
            film_input(0.02, 20.0, 10e-3, 40e-3, 5000.0, 20.0),
            [1.09853, 0.800681],
            [1.07864, 0.791504],
            [1.51902, 1.15301],
        ),
        (
            "C line",
            film_input(0.00468, 10.0, 3e-3, f64::INFINITY, 10000.0, 5.0),
            [0.0644715, 0.0550476],
            [0.0675474, 0.0542997],
            [0.0827638, 0.0591991],
        ),
    ];
    println!(
        "{:<34} {:>12} {:>12}  rel. error",
        "quantity (µm)", "flank", "hand"
    );
    for (name, input, ch, hd, dh) in &points {
        let c = film_thickness(FilmModel::Chittenden, input).unwrap();
        let h = film_thickness(FilmModel::HamrockDowson, input).unwrap();
        let d = film_thickness(FilmModel::DowsonHigginson, input).unwrap();
        close(
            &format!("{name}: Chittenden h_c"),
            c.central * 1e3,
            ch[0],
            TOL,
        );
        close(
            &format!("{name}: Chittenden h_min"),
            c.minimum * 1e3,
            ch[1],
            TOL,
        );
        close(
            &format!("{name}: Hamrock–Dowson h_c"),
            h.central * 1e3,
            hd[0],
            TOL,
        );
        close(
            &format!("{name}: Hamrock–Dowson h_min"),
            h.minimum * 1e3,
            hd[1],
            TOL,
        );
        close(
            &format!("{name}: Dowson–Higginson h_c"),
            d.central * 1e3,
            dh[0],
            TOL,
        );
        close(
            &format!("{name}: Dowson–Higginson h_min"),
            d.minimum * 1e3,
            dh[1],
            TOL,
        );
        // two fits of the same numerical EHL solutions agree
        let agree = c.central / h.central - 1.0;
        println!("{name}: Chittenden / Hamrock–Dowson − 1 = {agree:+.4}");
        assert!(agree.abs() < 0.05, "{name}: {agree}");
        // flags: point fits beyond R_y/R_x = 25, the line fit below it
        let line = !input.radius_y.is_finite();
        assert_eq!(
            c.flags.contains(&FilmFlag::OutsideEllipticityRange),
            line,
            "{name}"
        );
        assert_eq!(
            d.flags.contains(&FilmFlag::PointContactInLineFit),
            !line,
            "{name}"
        );
    }
}

#[test]
fn seed_transcription_of_the_chittenden_groups() {
    // seed eq. 3's π-groups with E_r = E′/2 against the Hamrock–Dowson groups
    close(
        "h_c(seed groups)/h_c",
        flank::lubrication::film::seed_groups_ratio(),
        0.713619,
        TOL,
    );
}

#[test]
fn traction_against_hand_values() {
    let lub = Lubricant::from_si(&oil()).unwrap();
    // (name, h_c m, R_x m, P̄ Pa, u m/s, v_s m/s, ζ, μ_thermal, μ used, flags)
    let points = [
        (
            "T1",
            0.15e-6,
            5e-3,
            1.0e9,
            10.0,
            5.0,
            0.138991,
            0.0260816,
            0.0260816,
            vec![],
        ),
        (
            "T2",
            0.3e-6,
            10e-3,
            0.7e9,
            20.0,
            2.0,
            0.0581441,
            0.0174628,
            0.0174628,
            vec![TractionFlag::IsothermalBelowThermal],
        ),
        (
            "T3 (pitch point)",
            0.1e-6,
            3e-3,
            1.5e9,
            5.0,
            0.0,
            0.279714,
            0.0298098,
            0.0298098,
            vec![TractionFlag::IsothermalBelowThermal],
        ),
        (
            "T4 (low pressure)",
            0.5e-6,
            10e-3,
            0.15e9,
            20.0,
            10.0,
            0.0161493,
            -0.0628635,
            0.4187e6 / 0.15e9,
            vec![
                TractionFlag::ThermalFormulaNotPositive,
                TractionFlag::NotEyring,
            ],
        ),
    ];
    for (name, h, rx, p, u, vs, zeta, mu_t, mu, flags) in points {
        let t = traction(
            &lub,
            &TractionInput {
                central_film: h * 1e3,
                radius_x: rx * 1e3,
                reduced_modulus: e_prime(),
                mean_pressure: p * 1e-6,
                entraining_speed: u * 1e3,
                sliding_speed: vs * 1e3,
            },
        )
        .unwrap();
        close(&format!("{name}: ζ"), t.zeta, zeta, TOL);
        close(&format!("{name}: μ thermal"), t.mu_thermal, mu_t, TOL);
        // T4's fallback: τ_iso printed to 4 digits by hand
        let tol = if name.starts_with("T4") { 1e-3 } else { TOL };
        close(&format!("{name}: μ used"), t.mu, mu, tol);
        assert_eq!(t.flags, flags, "{name}");
    }
}

#[test]
fn bad_lubricant_data_gives_clear_errors() {
    let bad = |edit: fn(&mut LubricantSi), words: &[&str]| {
        let mut s = oil();
        edit(&mut s);
        let e = Lubricant::from_si(&s).unwrap_err().to_string();
        println!("{e}");
        for w in words {
            assert!(e.contains(w), "`{e}` lacks `{w}`");
        }
    };
    bad(
        |s| s.viscosity_pa_s = -0.005,
        &["viscosity_pa_s", "-0.005", "0.0001"],
    );
    // α in 1/Pa by mistake
    bad(
        |s| s.pressure_viscosity_per_gpa = 1.0e-8,
        &["pressure_viscosity_per_gpa", "1/GPa"],
    );
    bad(
        |s| s.pressure_viscosity_per_gpa = 200.0,
        &["pressure_viscosity_per_gpa", "60"],
    );
    bad(
        |s| s.eyring_stress_mpa = f64::INFINITY,
        &["eyring_stress_mpa", "finite"],
    );
    bad(
        |s| s.solid_conductivity_w_per_m_k = 0.0,
        &["solid_conductivity_w_per_m_k"],
    );
    // a film at zero entraining speed
    let mut i = film_input(0.00468, 10.0, 5e-3, 5e-3, 1000.0, 0.0);
    let e = film_thickness(FilmModel::Chittenden, &i).unwrap_err();
    println!("{e}");
    assert!(matches!(e, FlankError::Model(_)));
    assert!(e.to_string().contains("entraining speed"), "{e}");
    // no load, no film
    i.entraining_speed = 1e4;
    i.load = 0.0;
    let e = film_thickness(FilmModel::HamrockDowson, &i).unwrap_err();
    assert!(e.to_string().contains("contact load"), "{e}");
    // a NaN film thickness into the traction formula
    let lub = Lubricant::from_si(&oil()).unwrap();
    let e = traction(
        &lub,
        &TractionInput {
            central_film: f64::NAN,
            radius_x: 5.0,
            reduced_modulus: e_prime(),
            mean_pressure: 1000.0,
            entraining_speed: 1e4,
            sliding_speed: 0.0,
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("central film thickness"), "{e}");
}
