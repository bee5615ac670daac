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
    ] {
        let mut changes = vec![("method", json!(method))];
        changes.extend(extra);
        if method == 3 {
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
