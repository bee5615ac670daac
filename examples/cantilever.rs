//! Builds the C3D20 benchmark cantilever in memory (default 100×10×10
//! elements, 100 × 10 × 10 mm, clamped at x = 0, tip load 1 kN in −y) and solves it,
//! printing the solver figures. Usage:
//! `cargo run --release --example cantilever -- [nx ny nz] [metis|amd] [threads]`

use flank::fem::ordering::OrderingMethod;
use flank::fem::static_analysis::{solve_static, SolveOptions};
use flank::mesh::structured::{cantilever_model, BoxElement};

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
    let model = cantilever_model(cells, BoxElement::Hex20, 1000.0).unwrap();
    let options = SolveOptions {
        ordering,
        threads,
        ..Default::default()
    };
    let sol = solve_static(&model, &options).unwrap();
    println!("{}", serde_json::to_string_pretty(&sol.stats).unwrap());
}
