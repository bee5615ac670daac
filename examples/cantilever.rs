//! Builds the C3D20 cantilever box in memory (default 100×10×10 elements,
//! 100 × 10 × 10 mm, clamped at x = 0, tip load 1 kN in −y) and solves it,
//! printing the solver figures. Usage:
//! `cargo run --release --example cantilever -- [nx ny nz] [metis|amd] [threads]`

use flank::fem::material::Material;
use flank::fem::model::{Dirichlet, Model, NodalForce};
use flank::fem::ordering::OrderingMethod;
use flank::fem::static_analysis::{solve_static, SolveOptions};
use flank::mesh::structured::{box_mesh, BoxElement};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let cells: [usize; 3] = if args.len() >= 4 {
        [
            args[1].parse().unwrap(),
            args[2].parse().unwrap(),
            args[3].parse().unwrap(),
        ]
    } else {
        [100, 10, 10]
    };
    let ordering = match args.get(4).map(String::as_str) {
        Some("amd") => OrderingMethod::Amd,
        _ => OrderingMethod::Metis,
    };
    let threads: usize = args.get(5).map(|s| s.parse().unwrap()).unwrap_or(0);
    let mesh = box_mesh([100.0, 10.0, 10.0], cells, BoxElement::Hex20);
    let ne = mesh.elements.len();
    let clamped = mesh.node_sets["X0"].clone();
    let tip = mesh.node_sets["X1"].clone();
    let mut model = Model {
        mesh,
        materials: vec![Material::new("steel", 210e3, 0.3).unwrap()],
        element_material: vec![0; ne],
        ..Default::default()
    };
    for &n in &clamped {
        for k in 0..3 {
            model.dirichlet.push(Dirichlet {
                node: n,
                component: k,
                value: 0.0,
            });
        }
    }
    for &n in &tip {
        model.forces.push(NodalForce {
            node: n,
            component: 1,
            value: -1000.0 / tip.len() as f64,
        });
    }
    let options = SolveOptions {
        ordering,
        threads,
        ..Default::default()
    };
    let sol = solve_static(&model, &options).unwrap();
    println!("{}", serde_json::to_string_pretty(&sol.stats).unwrap());
}
