//! Contact bands (`verification/contact_band/README.md`): a banded mesh
//! reproduces the plain mesh's TE and load share (a band only refines),
//! and p_max at a seed 002 single-contact position converges with the
//! band size towards Hertz p₀ of the FE's own line load.

use flank::compliance::body::BodyMeshOptions;
use flank::mesh_cycle::contact_band::{run_contact_band, BandOptions, BandPosition};
use flank::scene::{read_scene, ElementKind, Scene};

fn scene(teeth: u32) -> Scene {
    let mut s = read_scene(std::path::Path::new("papers/seed002-spur/scene.toml")).unwrap();
    s.mesh.teeth_in_sector = teeth;
    s
}

fn options(flank: f64, base: f64, band: Option<f64>) -> BandOptions {
    BandOptions {
        size_mm: band,
        mesh: BodyMeshOptions {
            flank_size: Some(flank),
            base_size: Some(base),
            with_load: false,
            element: Some(ElementKind::Hex20),
        },
        threads: 2,
        ..Default::default()
    }
}

fn print(tag: &str, r: &BandPosition) {
    println!(
        "{tag}: roll {:.3}°, band {:?} mm, {} nodes, {} DOFs, min scaled J {:.3}, max aspect {:.1}, setup {:.1} s, solve {:.1} s, peak {:.0} MB, TE {:.2} µrad",
        r.roll_deg,
        r.band_size_mm,
        r.nodes,
        r.dofs,
        r.min_scaled_jacobian,
        r.max_aspect_ratio,
        r.setup_s,
        r.solve_s,
        r.peak_memory_mb,
        r.te_urad
    );
    for p in &r.pairs {
        println!(
            "  pair {}: F {:.1} N, share {:.4}, w {:.2} N/mm, Hertz p0 {:?} MPa, b {:?} mm, p_max {:.1} / mid-face {:.1} / nodal {:.1} MPa, closed mid-face nodes {}, 2b/size {:?}",
            p.pinion_tooth,
            p.force_n,
            p.load_share,
            p.line_load_n_per_mm,
            p.hertz_p0_mpa.map(|v| (v * 10.0).round() / 10.0),
            p.hertz_half_width_mm.map(|v| (v * 1e4).round() / 1e4),
            p.p_max_mpa,
            p.p_max_mid_face_mpa,
            p.p_max_nodal_mpa,
            p.closed_nodes_mid_face,
            p.elements_across_2b.map(|v| (v * 10.0).round() / 10.0)
        );
    }
}

/// CI size: at the double-contact position −8.43° (flank 0.5 mm, base
/// 2 mm, hex20), a 0.25 mm band on both bodies moves the TE by less than
/// 1 % and the load shares by less than 0.02 — tolerances from the plain
/// meshes' own sensitivity (papers/seed002-spur: TE within 0.7 %,
/// double-contact forces within 4.4 % from flank 0.75 to 0.1 mm). The
/// first version ran at flank 1 mm, outside that range, and failed
/// (TE 1.47 %, share 0.035; README): not loosened, the check was moved to
/// the flank size the tolerances come from.
#[test]
fn band_reproduces_plain_mesh_ci() {
    let s = scene(3);
    let roll = [-8.43];
    let plain = &run_contact_band(&s, &roll, &options(0.5, 2.0, None)).unwrap()[0];
    let band = &run_contact_band(&s, &roll, &options(0.5, 2.0, Some(0.25))).unwrap()[0];
    print("plain", plain);
    print("band", band);
    let dte = (band.te_urad - plain.te_urad).abs() / plain.te_urad;
    let dshare = plain
        .pairs
        .iter()
        .zip(&band.pairs)
        .map(|(a, b)| (a.load_share - b.load_share).abs())
        .fold(0.0, f64::max);
    println!(
        "TE change {:.3} %, largest share change {dshare:.4}",
        100.0 * dte
    );
    assert!(dte < 0.01, "{dte}");
    assert!(dshare < 0.02, "{dshare}");
    assert!(band.min_scaled_jacobian > 0.2);
}

/// p_max at 5.415° (single contact) against the band size.
#[test]
#[ignore = "minutes and GBs: the p_max study of the README"]
fn p_max_converges_with_band_size() {
    let teeth: u32 = std::env::var("BAND_TEETH")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3);
    let sizes: Vec<f64> = std::env::var("BAND_SIZES")
        .unwrap_or_else(|_| "0.2,0.1,0.05".into())
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    let roll: f64 = std::env::var("BAND_ROLL")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(5.415);
    let s = scene(teeth);
    for size in sizes {
        let band = size.is_finite().then_some(size);
        let r = &run_contact_band(&s, &[roll], &options(0.5, 2.0, band)).unwrap()[0];
        print(&format!("teeth {teeth}"), r);
    }
}
