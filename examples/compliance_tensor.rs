//! A body's full nodal compliance tensor: computed through the library
//! for seed 002's pinion (coarse: 1 mm flank, 4 mm base elements), written
//! to a file and read back, then one 3 × 3 block C_ij (mm/N) read from it:
//! the displacement of flank node i per unit force at flank node j.
//!
//! Run: `cargo run --release --example compliance_tensor`
//! (writes `out/example_compliance/`: `pinion.compliance.bin`, or `.h5`
//! with the Cargo feature `hdf5`; `summary.json`).

use std::path::Path;

use flank::api::{
    compliance, read_compliance_tensor, BodyMeshOptions, ComplianceOptions, FileFormat,
};

fn main() -> anyhow::Result<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = root.join("out/example_compliance");
    let options = ComplianceOptions {
        out: out.clone(),
        mesh: BodyMeshOptions {
            flank_size: Some(1.0),
            base_size: Some(4.0),
            ..Default::default()
        },
        bodies: vec!["pinion".into()],
        ..Default::default()
    };
    compliance(root.join("papers/seed002-spur/scene.toml"), &options)?;
    let format = options.format.unwrap_or_else(FileFormat::default_format);
    let file = out.join(format!("pinion.compliance.{}", format.extension()));
    let tensor = read_compliance_tensor(&file)?;
    let n = tensor.node_count();
    println!(
        "{}: {} flank nodes, C is {} × {} ({}), asymmetry {:.1e}",
        file.display(),
        n,
        tensor.dim(),
        tensor.dim(),
        tensor.meta.units,
        tensor.asymmetry()
    );
    // the flank node nearest the middle of the flank, with itself and a neighbour
    let mid = n / 2;
    for j in [mid, (mid + 1).min(n - 1)] {
        let c = tensor.block(mid, j);
        println!(
            "C[{mid}][{j}] (nodes {} at {:?} mm, {}):",
            tensor.flank.labels[mid], tensor.flank.positions[mid], tensor.flank.labels[j]
        );
        for row in c {
            println!("  {:>12.4e} {:>12.4e} {:>12.4e}", row[0], row[1], row[2]);
        }
    }
    Ok(())
}
