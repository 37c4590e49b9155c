//! The two-block problem file that the tests of several crates share: a lower block clamped at
//! its bottom and an upper block held in x on its left and pressed on its top, both of one steel,
//! in contact along the lower block's top and the upper block's bottom (plane strain). A test
//! includes this file with `#[path = ".../tests/support/two_blocks.rs"] mod two_blocks;` and
//! changes what it needs; the numbers are kept as the text the file says.

// Each test crate uses a part of it.
#![allow(dead_code)]

use std::sync::LazyLock;

/// A problem file's text built on first use, for a `static` that reads as a `str`.
pub struct Text(LazyLock<String>);

impl Text {
    /// The text that `build` makes.
    pub const fn new(build: fn() -> String) -> Self {
        Text(LazyLock::new(build))
    }
}

impl std::ops::Deref for Text {
    type Target = str;
    fn deref(&self) -> &str {
        &self.0
    }
}

impl std::fmt::Display for Text {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self)
    }
}

/// The parameters of the two-block file, each as it is written in the file.
pub struct TwoBlocks {
    /// The problem's `name` (absent: the file name's stem).
    pub name: Option<&'static str>,
    /// Young's modulus of the steel.
    pub young: String,
    /// The blocks' common width.
    pub width: String,
    /// The y ranges of the lower and upper blocks.
    pub lower: [String; 2],
    /// See `lower`.
    pub upper: [String; 2],
    /// Cells per block in x and y.
    pub cells: [usize; 2],
    /// Whether the upper block's mesh is mirrored (its diagonals the other way).
    pub mirror: bool,
    /// The pressure on the upper block's top.
    pub pressure: String,
    /// The contact pair's boundaries on the lower and the upper block.
    pub boundaries: [&'static str; 2],
    /// The rod model's c and h of the pair's penalty.
    pub penalty: [String; 2],
    /// Text appended after the contact pair (a `[solver]` table, say).
    pub tail: &'static str,
}

impl Default for TwoBlocks {
    /// Two 2 × 0.5 steel blocks of 8 × 2 cells, the upper one mirrored and pressed by 100, with
    /// the paper's iteration (`newton-kurchatov`, γ 0.5) to 1e-8.
    fn default() -> Self {
        TwoBlocks {
            name: Some("pair"),
            young: "2.1e5".into(),
            width: "2.0".into(),
            lower: ["0.0".into(), "0.5".into()],
            upper: ["0.5".into(), "1.0".into()],
            cells: [8, 2],
            mirror: true,
            pressure: "100.0".into(),
            boundaries: ["top", "bottom"],
            penalty: ["0.05".into(), "0.5".into()],
            tail: "\n[solver]\nmethod = \"newton-kurchatov\"\ngamma = 0.5\ntol = 1e-8\n",
        }
    }
}

impl TwoBlocks {
    /// The problem file's text.
    pub fn toml(&self) -> String {
        let name = self
            .name
            .map_or(String::new(), |n| format!("name = \"{n}\"\n"));
        let [nx, ny] = self.cells;
        let mirror = if self.mirror { ", mirror = true" } else { "" };
        let rectangle = |y: &[String; 2], mirror: &str| {
            format!(
                "mesh = {{ kind = \"rectangle\", x = [0.0, {}], y = [{}, {}], nx = {nx}, ny = {ny}{mirror} }}",
                self.width, y[0], y[1]
            )
        };
        format!(
            r#"
{name}plane = "strain"

[materials.steel]
young = {young}
poisson = 0.3

[[bodies]]
name = "lower"
material = "steel"
{lower}
supports = [{{ boundary = "bottom", component = "both" }}]

[[bodies]]
name = "upper"
material = "steel"
{upper}
supports = [{{ boundary = "left", component = "x" }}]
loads = [{{ kind = "pressure", boundary = "top", value = {pressure} }}]

[[contact]]
bodies = ["lower", "upper"]
boundaries = ["{a}", "{b}"]
penalty = {{ c = {c}, h = {h} }}
{tail}"#,
            young = self.young,
            lower = rectangle(&self.lower, ""),
            upper = rectangle(&self.upper, mirror),
            pressure = self.pressure,
            a = self.boundaries[0],
            b = self.boundaries[1],
            c = self.penalty[0],
            h = self.penalty[1],
            tail = self.tail,
        )
    }
}
