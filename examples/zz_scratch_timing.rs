use std::path::Path;
use flank::compliance::body::BodyMeshOptions;
use flank::ltca::cycle::{LtcaCycle, LtcaOptions};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let flank: f64 = args.get(1).map(|a| a.parse().unwrap()).unwrap_or(1.0);
    let base: f64 = args.get(2).map(|a| a.parse().unwrap()).unwrap_or(2.0);
    let k: usize = args.get(3).map(|a| a.parse().unwrap()).unwrap_or(20);
    let scene = flank::scene::read_scene(Path::new("papers/seed002-spur/scene.toml")).unwrap();
    let o = LtcaOptions { out: "/tmp/scr/b".into(), mesh: BodyMeshOptions { flank_size: Some(flank), base_size: Some(base), ..Default::default() }, points_per_line: Some(k), cache: Some("/tmp/scr/cache".into()), quiet: true, ..Default::default() };
    let c = LtcaCycle::new(&scene, &o).unwrap();
    println!("flank nodes {:?}", c.setup.flank_nodes);
    let (a, e) = c.kin.engagement(c.kin.middle);
    let pitch = c.kin.angular_pitch[0].to_degrees();
    let start = 0.5 * (a + e).to_degrees() - 0.5 * pitch;
    let angles: Vec<f64> = (0..30).map(|i| start + pitch * i as f64 / 30.0).collect();
    for _ in 0..3 {
        let t = std::time::Instant::now();
        let (mut cells, mut f, mut h, mut q, mut tot, mut n) = (0.0, 0.0, 0.0, 0.0, 0.0, 0);
        for &x in &angles { let r = c.solve(x).unwrap(); cells += r.cells_s; f += r.compliance_s; h += r.local_s; q += r.qp_s; tot += r.time_s; n += r.candidates; }
        println!("cycle {:.4} s (sum {:.4}): cells {:.4} F {:.4} H {:.4} QP {:.4}; mean candidates {}", t.elapsed().as_secs_f64(), tot, cells, f, h, q, n / angles.len());
    }
}
