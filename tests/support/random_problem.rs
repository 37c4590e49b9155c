//! A seeded generator of random multi-body contact problems, written as problem-file text so that
//! the loader is exercised too: 2 to 5 rectangular bodies stacked in a column or side by side on a
//! floor, with random Young's moduli (ratios 1e-12 … 1e12), a random length scale
//! (10^U(−6, 6), coordinates, gaps and prescribed displacements scaled with it), P1 or P2 meshes of
//! random and mostly non-matching sizes, random penalties, loads, gaps, friction and supports.
//! A test includes this file with `#[path = "support/random_problem.rs"] mod random_problem;`.

// Each test crate uses a part of it.
#![allow(dead_code)]

use std::fmt::Write;

/// Largest model (total nodes) the generator writes.
pub const MAX_NODES: usize = 3000;

/// xorshift64*: a few lines, deterministic, good enough to draw problems.
pub struct Rng(u64);

impl Rng {
    /// The generator of case `case`: its seed is a splitmix64 hash of the case number, so that
    /// one case can be drawn again alone.
    pub fn for_case(case: u64) -> Rng {
        let mut z = case.wrapping_add(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        Rng((z ^ (z >> 31)) | 1)
    }

    /// The next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// A uniform integer in `lo..=hi`.
    pub fn int(&mut self, lo: usize, hi: usize) -> usize {
        lo + (self.next() % (hi - lo + 1) as u64) as usize
    }

    /// A uniform number in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// 10^U(lo, hi).
    pub fn log(&mut self, lo: f64, hi: f64) -> f64 {
        10f64.powf(self.uniform(lo, hi))
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.uniform(0.0, 1.0) < p
    }

    /// One of `items`.
    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.int(0, items.len() - 1)]
    }
}

/// How the bodies are arranged.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Layout {
    /// A column: body 0 at the bottom, each body standing on the one below.
    Column,
    /// A row on a frictionless floor: body 0 on the left, each body pressed against the next.
    Row,
}

/// One body of a drawn problem.
struct Body {
    x: [f64; 2],
    y: [f64; 2],
    nx: usize,
    ny: usize,
    p2: bool,
    young: f64,
    poisson: f64,
    supports: Vec<String>,
    loads: Vec<String>,
}

impl Body {
    fn nodes(&self) -> usize {
        let k = if self.p2 { 2 } else { 1 };
        (k * self.nx + 1) * (k * self.ny + 1)
    }
}

/// A drawn problem: its file text and a one-line description.
pub struct Drawn {
    /// The problem file.
    pub text: String,
    /// Layout, bodies, orders, modulus ratio, scale, friction: a line for a failure report.
    pub what: String,
}

fn num(x: f64) -> String {
    format!("{x:e}")
}

/// Draws problem `case`.
pub fn draw(case: u64) -> Drawn {
    let mut rng = Rng::for_case(case);
    let layout = if rng.chance(0.7) {
        Layout::Column
    } else {
        Layout::Row
    };
    let n = rng.int(2, 5);
    let scale = rng.log(-6.0, 6.0);
    let e0 = rng.log(-3.0, 12.0);
    // A third of the problems have moduli of one order; the others spread them over ±6 decades
    // around the base, so that two bodies differ by up to 1e12 either way.
    let spread = if rng.chance(0.33) { 0.5 } else { 6.0 };
    let origin = [
        rng.uniform(-5.0, 5.0) * scale,
        rng.uniform(-5.0, 5.0) * scale,
    ];
    let mut bodies = Vec::new();
    let (mut cx, mut cy) = (origin[0], origin[1]);
    let width = scale * rng.uniform(1.0, 4.0);
    for b in 0..n {
        let young = e0 * rng.log(-spread, spread);
        let (x, y) = match layout {
            Layout::Column => {
                let h = scale * rng.uniform(0.25, 1.0);
                // Bodies above the bottom one are sometimes narrower: the contact zone then ends
                // inside the lower body's top.
                let inset = if b > 0 && rng.chance(0.3) {
                    [rng.uniform(0.0, 0.2), rng.uniform(0.0, 0.2)]
                } else {
                    [0.0, 0.0]
                };
                let x = [
                    origin[0] + inset[0] * width,
                    origin[0] + (1.0 - inset[1]) * width,
                ];
                let y = [cy, cy + h];
                cy += h;
                (x, y)
            }
            Layout::Row => {
                let w = scale * rng.uniform(0.25, 1.0);
                let h = width * rng.uniform(0.3, 1.0);
                let x = [cx, cx + w];
                cx += w;
                ([x[0], x[1]], [origin[1], origin[1] + h])
            }
        };
        bodies.push(Body {
            x,
            y,
            nx: rng.int(2, 20),
            ny: rng.int(1, 8),
            p2: rng.chance(0.4),
            young,
            poisson: rng.uniform(0.0, 0.45),
            supports: Vec::new(),
            loads: Vec::new(),
        });
    }
    while bodies.iter().map(Body::nodes).sum::<usize>() > MAX_NODES {
        for b in &mut bodies {
            b.nx = (b.nx * 2 / 3).max(2);
            b.ny = (b.ny * 2 / 3).max(1);
        }
    }
    supports_and_loads(&mut rng, layout, &mut bodies, scale);
    let text = write(&mut rng, layout, &bodies, scale);
    let young: Vec<f64> = bodies.iter().map(|b| b.young).collect();
    let ratio = young.iter().fold(0.0f64, |a, &e| a.max(e))
        / young.iter().fold(f64::INFINITY, |a, &e| a.min(e));
    let orders: String = bodies
        .iter()
        .map(|b| if b.p2 { '2' } else { '1' })
        .collect();
    let what = format!(
        "{layout:?} of {n} bodies, orders {orders}, E ratio {ratio:.1e}, scale {scale:.1e}, {} nodes{}",
        bodies.iter().map(Body::nodes).sum::<usize>(),
        if text.contains("coulomb") { ", friction" } else { "" }
    );
    Drawn { text, what }
}

/// The supports and loads: the first body is held, the others float, held sideways (column) or
/// by the floor (row) and pressed onto the first by a pressure, a prescribed displacement or
/// their weight; sometimes extra supports, tractions and pulls.
fn supports_and_loads(rng: &mut Rng, layout: Layout, bodies: &mut [Body], scale: f64) {
    let n = bodies.len();
    let soft = bodies.iter().fold(f64::INFINITY, |a, b| a.min(b.young));
    let base = bodies.iter().map(|b| b.young).sum::<f64>() / n as f64;
    // The load level: a small strain of the softest body, or (sometimes) of the average one.
    let stress = if rng.chance(0.8) { soft } else { base } * rng.log(-7.0, -2.0);
    let (first, last, side, far, push) = match layout {
        Layout::Column => ("bottom", "top", "left", "right", [0.0, -1.0]),
        Layout::Row => ("left", "right", "bottom", "top", [-1.0, 0.0]),
    };
    let support = |boundary: &str, component: &str, value: f64| {
        format!(
            "{{ boundary = \"{boundary}\", component = \"{component}\", value = {} }}",
            num(value)
        )
    };
    bodies[0].supports.push(match rng.int(0, 2) {
        0 => support(first, "both", 0.0),
        1 => support(first, "normal", 0.0),
        _ => support(first, if layout == Layout::Column { "y" } else { "x" }, 0.0),
    });
    for (b, body) in bodies.iter_mut().enumerate() {
        let lateral = match layout {
            Layout::Column => "x",
            Layout::Row => "y",
        };
        // Column: every body held sideways on its left (the first one too unless clamped).
        // Row: every body stands on the frictionless floor.
        if b > 0 || !body.supports[0].contains("both") {
            body.supports.push(support(side, lateral, 0.0));
        }
        if rng.chance(0.1) {
            let which = *rng.pick(&[side, far]);
            body.supports.push(support(which, lateral, 0.0));
        }
    }
    let top = &mut bodies[n - 1];
    let length = (top.x[1] - top.x[0]).max(top.y[1] - top.y[0]);
    match rng.int(0, 9) {
        0 | 1 => {
            // A prescribed displacement presses the last body onto the others.
            let d = -length * rng.log(-6.0, -3.0);
            let component = if layout == Layout::Column { "y" } else { "x" };
            top.supports.push(support(last, component, d));
        }
        2 => {
            // A pull: the contact opens and the floating bodies are not held.
            top.loads.push(format!(
                "{{ kind = \"pressure\", boundary = \"{last}\", value = {} }}",
                num(-stress)
            ));
        }
        _ => top.loads.push(format!(
            "{{ kind = \"pressure\", boundary = \"{last}\", value = {} }}",
            num(stress)
        )),
    }
    for body in bodies.iter_mut() {
        if rng.chance(0.25) {
            let g = stress / scale * rng.log(-2.0, 0.0);
            body.loads.push(format!(
                "{{ kind = \"body-force\", value = [{}, {}] }}",
                num(push[0] * g),
                num(push[1] * g)
            ));
        }
        if rng.chance(0.15) {
            let t = stress * rng.uniform(-0.5, 0.5);
            let tangent = [-push[1] * t, push[0] * t];
            body.loads.push(format!(
                "{{ kind = \"traction\", boundary = \"{far}\", value = [{}, {}] }}",
                num(tangent[0]),
                num(tangent[1])
            ));
        }
    }
}

/// The problem file of `bodies`, with a contact pair between neighbours.
fn write(rng: &mut Rng, layout: Layout, bodies: &[Body], scale: f64) -> String {
    let mut t = String::new();
    let plane = *rng.pick(&["strain", "stress"]);
    writeln!(t, "name = \"random\"\nplane = \"{plane}\"\n").unwrap();
    for (b, body) in bodies.iter().enumerate() {
        writeln!(
            t,
            "[materials.m{b}]\nyoung = {}\npoisson = {}\n",
            num(body.young),
            num(body.poisson)
        )
        .unwrap();
    }
    for (b, body) in bodies.iter().enumerate() {
        let diagonal = *rng.pick(&["right", "left", "alternate"]);
        let order = if body.p2 { "p2" } else { "p1" };
        let mirror = rng.chance(0.5);
        let grading = if rng.chance(0.15) {
            format!(
                ", grading = {{ x = {}, y = {} }}",
                num(rng.log(-0.7, 0.7)),
                num(rng.log(-0.7, 0.7))
            )
        } else {
            String::new()
        };
        writeln!(
            t,
            "[[bodies]]\nname = \"b{b}\"\nmaterial = \"m{b}\"\nmesh = {{ kind = \"rectangle\", x = [{}, {}], y = [{}, {}], nx = {}, ny = {}, diagonal = \"{diagonal}\", mirror = {mirror}, order = \"{order}\"{grading} }}",
            num(body.x[0]), num(body.x[1]), num(body.y[0]), num(body.y[1]), body.nx, body.ny
        )
        .unwrap();
        writeln!(t, "supports = [{}]", body.supports.join(", ")).unwrap();
        if !body.loads.is_empty() {
            writeln!(t, "loads = [{}]", body.loads.join(", ")).unwrap();
        }
        t.push('\n');
    }
    let (low, high) = match layout {
        Layout::Column => ("top", "bottom"),
        Layout::Row => ("right", "left"),
    };
    for b in 1..bodies.len() {
        writeln!(
            t,
            "[[contact]]\nbodies = [\"b{}\", \"b{b}\"]\nboundaries = [\"{low}\", \"{high}\"]",
            b - 1
        )
        .unwrap();
        if rng.chance(0.8) {
            let h = scale * rng.uniform(0.1, 2.0);
            writeln!(
                t,
                "penalty = {{ c = {}, h = {} }}",
                num(rng.log(-4.0, 0.0)),
                num(h)
            )
            .unwrap();
        } else {
            let compliance = 1.0 / bodies[b - 1].young + 1.0 / bodies[b].young;
            let theta = scale * compliance * rng.log(-6.0, 0.0);
            writeln!(t, "penalty = {{ theta = {} }}", num(theta)).unwrap();
        }
        if rng.chance(0.15) {
            let gap = scale * rng.log(-7.0, -4.0) * if rng.chance(0.5) { 1.0 } else { -1.0 };
            writeln!(t, "gap = {{ kind = \"uniform\", value = {} }}", num(gap)).unwrap();
        }
        if rng.chance(0.2) {
            writeln!(
                t,
                "friction = {{ law = \"coulomb\", mu = {} }}",
                num(rng.uniform(0.0, 1.0))
            )
            .unwrap();
        } else if rng.chance(0.1) {
            writeln!(t, "forces = \"own-side\"").unwrap();
        }
        t.push('\n');
    }
    t
}
