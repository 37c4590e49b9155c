//! Times the reading of a Gmsh `.msh` file: the text read from disk, parsed and built into a
//! validated mesh (`contactdd::fem::gmsh::parse_msh`), then promoted to P2 (`Mesh::to_p2`).
//! Each phase is run `RUNS` times (default 3) and its median printed.
//!
//! Run: `python3 big_gen.py 1000` (a 1000 × 1000 square, 1e6 nodes, 2e6 triangles, in
//! `sq1000.msh`), then `cargo run --release --example read_mesh -- sq1000.msh [RUNS]`.

use std::time::Instant;

use contactdd::fem::gmsh::parse_msh;

fn median(mut times: Vec<f64>) -> f64 {
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args.next().ok_or("usage: read_mesh FILE.msh [RUNS]")?;
    let runs: usize = match args.next() {
        Some(r) => r.parse()?,
        None => 3,
    };
    let (mut read, mut parse, mut p2) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        let text = std::fs::read_to_string(&path)?;
        read.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let mesh = parse_msh(&text)?;
        parse.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let promoted = mesh.to_p2();
        p2.push(t.elapsed().as_secs_f64());
        println!(
            "{} nodes, {} triangles ({} P2 nodes)",
            mesh.num_nodes(),
            mesh.num_cells(),
            promoted.num_nodes()
        );
    }
    println!(
        "medians of {} runs: read {:.3} s, parse_msh {:.3} s, to_p2 {:.3} s",
        read.len(),
        median(read),
        median(parse),
        median(p2)
    );
    Ok(())
}
