//! Blank design tests through [`blank_design`]: zero-offset reduction,
//! self-consistency of the hypoid methods, bad input.

use super::*;

const F2: &str = r#"{"method":0,"Sigma_deg":90,"a_mm":0,"z1":14,"z2":39,"de2_mm":176.893,
    "b2_mm":25.4,"beta_m2_deg":35.0,"rc0_mm":114.3,"data_type":"II","alpha_dD_deg":20,
    "alpha_dC_deg":20,"f_alim":0,"c_ham":0.24737,"k_d":2.0,"k_c":0.125,"k_t":0.0915,
    "backlash":"outer normal jen 0.127","theta_a2_deg":2.1342,"theta_f2_deg":6.4934}"#;

fn edit(text: &str, changes: &[(&str, serde_json::Value)]) -> BlankInputs {
    let mut v: serde_json::Value = serde_json::from_str(text).unwrap();
    for (k, x) in changes {
        if x.is_null() {
            v.as_object_mut().unwrap().remove(*k);
        } else {
            v[*k] = x.clone();
        }
    }
    serde_json::from_value(v).unwrap()
}

/// A zero offset with methods 1–3 gives the method-0 cones.
#[test]
fn zero_offset_gives_the_method0_cones() {
    use serde_json::json;
    let m0 = blank_design(&edit(F2, &[])).unwrap().cones;
    for (method, extra) in [
        (
            1,
            vec![
                ("beta_m2_deg", json!(null)),
                ("beta_m1_desired_deg", json!(35.0)),
            ],
        ),
        (3, vec![]),
        (2, vec![("z0", json!(5))]),
    ] {
        let mut changes = vec![("method", json!(method))];
        changes.extend(extra);
        if method >= 2 {
            changes.push(("theta_a2_deg", json!(null)));
            changes.push(("theta_f2_deg", json!(null)));
        }
        let d = blank_design(&edit(F2, &changes)).unwrap().cones;
        for (x, y) in [
            (d.delta1, m0.delta1),
            (d.delta2, m0.delta2),
            (d.rm1, m0.rm1),
            (d.rm2, m0.rm2),
            (d.beta_m1, m0.beta_m1),
            (d.beta_m2, m0.beta_m2),
        ] {
            assert!((x - y).abs() < 1e-9, "method {method}: {x} vs {y}");
        }
    }
}

/// The summary for the machine settings is the design's own data: face
/// widths span the cone distances, the face and root cones bracket the
/// pitch cone, depths and thickness are the clause 7 values.
#[test]
fn cutting_blank_summary_is_consistent() {
    let d = blank_design(&edit(F2, &[])).unwrap();
    let s = d.cutting_blank();
    for (m, b) in [(&s.pinion, d.widths.b1), (&s.wheel, d.widths.b2)] {
        assert!((m.re - m.ri - b).abs() < 1e-12 && (m.be + m.bi - b).abs() < 1e-12);
        assert!((m.re - m.rm - m.be).abs() < 1e-12);
        assert!(m.delta_f < m.delta && m.delta < m.delta_a);
        assert!(m.ham > 0.0 && m.hfm > m.ham.min(m.hfm) - 1e-12 && m.smn > 0.0);
    }
    assert!((s.wheel.re - 176.893 / (2.0 * s.wheel.delta.sin())).abs() < 1e-9);
    assert!((s.m_mn - d.cones.m_mn).abs() < 1e-15 && s.rc0 == 114.3 && s.z0.is_none());
    assert!((s.pinion.ham + s.wheel.ham - d.depth.hmw).abs() < 1e-12);
    // Pointed-teeth guard: the F2 top lands are positive.
    let (l1, l2) = d.outer_top_lands();
    assert!(l1 > 0.0 && l2 > 0.0);
}

/// The tooth trace of clause 7.6 passes the mean point with the mean spiral
/// angle, for the circular arc (F2) and the extended epicycloid (method 2,
/// F4's inputs).
#[test]
fn end_spiral_angle_formula_gives_beta_m2_at_the_mean_point() {
    let f4 = r#"{"method":2,"Sigma_deg":90,"a_mm":31.75,"z1":9,"z2":34,"dm2_mm":146.7,
        "b2_mm":26.0,"beta_m2_deg":21.009,"rc0_mm":76.0,"z0":13,"data_type":"II",
        "alpha_dD_deg":20,"alpha_dC_deg":20,"f_alim":1.0,"c_ham":0.275,"k_d":2.0,
        "k_c":0.125,"k_t":0.1}"#;
    for text in [F2, f4] {
        let d = blank_design(&edit(text, &[])).unwrap();
        let c = &d.cones;
        let b = spiral_angles::wheel_spiral_angle(c, d.rc0, d.hobbing.as_ref(), c.rm2).unwrap();
        assert!((b - c.beta_m2).abs() < 1e-12, "{b} vs {}", c.beta_m2);
    }
}
