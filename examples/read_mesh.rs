//! Times the reading of a Gmsh `.msh` file: the text read from disk, parsed and built into a
//! validated mesh (`contactdd::fem::gmsh::parse_msh`), then promoted to P2 (`Mesh::to_p2`).
//! Each phase is run `RUNS` times (default 3) and its median printed.
//!
//! Run: `cargo run --release --example read_mesh -- FILE.msh [RUNS]`, or with a number `N`
//! instead of a file: the MSH 4.1 text of the unit square cut into N × N squares, each into two
//! triangles ((N + 1)² nodes, 2 N² triangles, a physical line "bottom" and surface "body"), is
//! written to `sqN.msh` in the temporary folder and read from there (N = 1000: 1e6 nodes, 80 MB).

use std::time::Instant;

use contactdd::fem::gmsh::parse_msh;

/// The MSH 4.1 text of the unit square cut into `n × n` squares, each into two triangles.
fn square(n: usize) -> String {
    use std::fmt::Write;
    let nodes = (n + 1) * (n + 1);
    let mut text = String::from(
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n1 1 \"bottom\"\n\
         2 2 \"body\"\n$EndPhysicalNames\n$Entities\n0 1 1 0\n1 0 0 0 1 0 0 1 1 0\n\
         1 0 0 0 1 1 0 1 2 1 1\n$EndEntities\n",
    );
    let _ = writeln!(text, "$Nodes\n1 {nodes} 1 {nodes}\n2 1 0 {nodes}");
    for tag in 1..=nodes {
        let _ = writeln!(text, "{tag}");
    }
    let h = 1.0 / n as f64;
    for j in 0..=n {
        for i in 0..=n {
            let _ = writeln!(text, "{:?} {:?} 0", i as f64 * h, j as f64 * h);
        }
    }
    let elements = 2 * n * n + n;
    let _ = writeln!(
        text,
        "$EndNodes\n$Elements\n2 {elements} 1 {elements}\n1 1 1 {n}"
    );
    for i in 0..n {
        let _ = writeln!(text, "{} {} {}", i + 1, i + 1, i + 2);
    }
    let _ = writeln!(text, "2 1 2 {}", 2 * n * n);
    let mut tag = n + 1;
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i + 1;
            let (b, c, d) = (a + 1, a + n + 2, a + n + 1);
            let _ = writeln!(text, "{tag} {a} {b} {c}\n{} {a} {c} {d}", tag + 1);
            tag += 2;
        }
    }
    text.push_str("$EndElements\n");
    text
}

fn median(mut times: Vec<f64>) -> f64 {
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let mut path = args.next().ok_or("usage: read_mesh FILE.msh|N [RUNS]")?;
    if let Ok(n) = path.parse::<usize>() {
        let file = std::env::temp_dir().join(format!("sq{n}.msh"));
        std::fs::write(&file, square(n))?;
        path = file.display().to_string();
        println!("wrote {path}");
    }
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
