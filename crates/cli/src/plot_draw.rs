//! What every figure of `contactdd plot` shares: the backends (SVG as text, PNG through a pixel
//! buffer and the `png` encoder), the embedded font, the frame of a chart, and a series drawn as
//! a line and markers with its legend entry.

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Once;

use anyhow::{anyhow, Context, Result};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::{Drawable, PointCollection};
use plotters::prelude::*;
use plotters_backend::{BackendCoord, DrawingErrorKind};

use contactdd_io::output::write_atomic;

use crate::args::Format;

/// Pixel size of every figure.
pub const SIZE: (u32, u32) = (800, 500);

/// A figure: draws itself on any backend.
pub trait Figure {
    /// Draws the figure on `root` (already white).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>;
}

/// Turns a plotters error (generic in the backend) into an error of ours.
pub fn ok<T, E: std::fmt::Display>(r: std::result::Result<T, E>) -> Result<T> {
    r.map_err(|e| anyhow!("cannot draw: {e}"))
}

/// Registers DejaVu Sans as the sans-serif font, once: plotters' `ab_glyph` text needs it for
/// the layout of every backend and for the glyphs of PNG, and a fresh machine may have no fonts.
fn register_font() -> Result<()> {
    static ONCE: Once = Once::new();
    let mut result = Ok(());
    ONCE.call_once(|| {
        result = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        )
        .map_err(|_| anyhow!("the embedded font cannot be read"));
    });
    result
}

/// Writes `fig` as `dir/<stem>.<ext>` in each format; returns the paths written.
pub fn render(
    fig: &impl Figure,
    dir: &Path,
    stem: &str,
    formats: &[Format],
) -> Result<Vec<PathBuf>> {
    register_font()?;
    let mut written = Vec::new();
    for format in formats {
        let (bytes, ext) = match format {
            Format::Svg => (svg(fig)?, "svg"),
            Format::Png => (png(fig)?, "png"),
        };
        let path = dir.join(format!("{stem}.{ext}"));
        write_atomic(&path, &bytes)
            .with_context(|| format!("cannot write '{}'", path.display()))?;
        written.push(path);
    }
    Ok(written)
}

fn svg(fig: &impl Figure) -> Result<Vec<u8>> {
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, SIZE).into_drawing_area();
        ok(root.fill(&WHITE))?;
        fig.draw(&root)?;
        ok(root.present())?;
    }
    Ok(text.into_bytes())
}

fn png(fig: &impl Figure) -> Result<Vec<u8>> {
    let (w, h) = SIZE;
    let mut pixels = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, SIZE).into_drawing_area();
        ok(root.fill(&WHITE))?;
        fig.draw(&root)?;
        ok(root.present())?;
    }
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = ok(encoder.write_header())?;
    ok(writer.write_image_data(&pixels))?;
    ok(writer.finish())?;
    Ok(bytes)
}

/// Caption and axes of a chart.
pub struct Frame {
    /// Title above the chart.
    pub caption: String,
    /// Horizontal axis label (with its unit).
    pub x_label: String,
    /// Vertical axis label (with its unit).
    pub y_label: String,
}

/// A linear chart over `x` × `y` with its mesh drawn.
pub fn linear<'a, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    frame: &Frame,
    x: Range<f64>,
    y: Range<f64>,
) -> Result<ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>> {
    let (xr, yr) = (x.clone(), y.clone());
    let mut chart = ok(ChartBuilder::on(root)
        .caption(&frame.caption, ("sans-serif", 22))
        .margin(12)
        .margin_right(30)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(x, y))?;
    ok(chart
        .configure_mesh()
        .x_desc(&frame.x_label)
        .y_desc(&frame.y_label)
        .x_label_formatter(&|v| tick(*v, &xr))
        .y_label_formatter(&|v| tick(*v, &yr))
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .bold_line_style(RGBColor(225, 225, 225))
        .light_line_style(TRANSPARENT)
        .draw())?;
    Ok(chart)
}

/// A tick label on an axis over `range`, in one style for the whole axis: powers of ten when
/// the axis reaches no further than 0.01 or beyond 1e5, else decimals as fine as the axis needs,
/// without trailing zeros. A rounding error away from 0 (−2.2e−16) is 0.
pub fn tick(v: f64, range: &Range<f64>) -> String {
    let reach = range.start.abs().max(range.end.abs());
    if v.abs() < 1e-9 * reach || !v.is_finite() {
        return if v.is_finite() {
            "0".into()
        } else {
            v.to_string()
        };
    }
    if !(1e-2..1e5).contains(&reach) {
        return format!("{v:.1e}");
    }
    let decimals = (2 - reach.log10().floor() as i32).clamp(0, 6) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A marker shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Marker {
    /// No marker.
    None,
    /// ●
    Circle,
    /// ■
    Square,
    /// ▲
    Triangle,
    /// ◆
    Diamond,
    /// ×
    Cross,
    /// +
    Plus,
}

/// How a series' points are joined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Line {
    /// Markers only.
    None,
    /// A solid line.
    Solid,
    /// A dashed line.
    Dashed,
    /// A dotted line (short dashes).
    Dotted,
}

/// The look of a series.
#[derive(Clone, Copy, Debug)]
pub struct Look {
    /// Colour of line and markers.
    pub color: RGBColor,
    /// Line style.
    pub line: Line,
    /// Marker shape.
    pub marker: Marker,
    /// Filled markers (else outlines).
    pub filled: bool,
    /// Marker size in pixels.
    pub size: i32,
}

impl Look {
    /// A look with a `line` and filled `marker` of size 4 in `color`.
    pub fn new(color: RGBColor, line: Line, marker: Marker) -> Look {
        Look {
            color,
            line,
            marker,
            filled: true,
            size: 4,
        }
    }

    /// The same look with outlined markers of `size` pixels.
    pub fn hollow(self, size: i32) -> Look {
        Look {
            filled: false,
            size,
            ..self
        }
    }

    fn marker_style(&self) -> ShapeStyle {
        let style = ShapeStyle::from(&self.color).stroke_width(2);
        if self.filled {
            style.filled()
        } else {
            style
        }
    }
}

/// Line colours that stay apart in print and for the common colour blindnesses.
pub const COLORS: [RGBColor; 6] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(230, 159, 0),
];

/// Draws `points` with `look`: its line, then its markers.
pub fn series<'a, DB, CT>(
    chart: &mut ChartContext<'a, DB, CT>,
    points: &[(f64, f64)],
    look: Look,
) -> Result<()>
where
    DB: DrawingBackend + 'a,
    CT: CoordTranslate<From = (f64, f64)>,
{
    let line_style = ShapeStyle::from(&look.color).stroke_width(2);
    let pts = points.to_vec();
    match look.line {
        Line::Solid => ok(chart
            .draw_series(LineSeries::new(pts, line_style))
            .map(drop))?,
        Line::Dashed => ok(chart
            .draw_series(DashedLineSeries::new(pts, 9, 5, line_style))
            .map(drop))?,
        Line::Dotted => ok(chart
            .draw_series(DashedLineSeries::new(pts, 3, 4, line_style))
            .map(drop))?,
        Line::None => {}
    }
    if look.marker != Marker::None {
        let markers = points.iter().map(|&at| MarkerAt {
            at,
            look,
            with_line: false,
        });
        ok(chart.draw_series(markers))?;
    }
    Ok(())
}

/// A marker of a [`Look`] at a point, optionally on a short stretch of its line (a legend's
/// sample). An element of our own: plotters' shapes are each their own type, and its dynamic
/// elements must outlive the backend.
struct MarkerAt<C> {
    at: C,
    look: Look,
    with_line: bool,
}

impl<'a, C> PointCollection<'a, C> for &'a MarkerAt<C> {
    type Point = &'a C;
    type IntoIter = std::iter::Once<&'a C>;
    fn point_iter(self) -> Self::IntoIter {
        std::iter::once(&self.at)
    }
}

impl<DB: DrawingBackend, C> Drawable<DB> for MarkerAt<C> {
    fn draw<I: Iterator<Item = BackendCoord>>(
        &self,
        mut pos: I,
        backend: &mut DB,
        _: (u32, u32),
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        let Some((mut x, y)) = pos.next() else {
            return Ok(());
        };
        if self.with_line {
            // Keep the sample inside the legend box, clear of the label.
            x += 4;
        }
        let look = self.look;
        let line = ShapeStyle::from(&look.color).stroke_width(2);
        if self.with_line {
            // The legend's line sample: dashes as on the chart.
            let pieces: &[(i32, i32)] = match look.line {
                Line::None => &[],
                Line::Solid => &[(-14, 14)],
                Line::Dashed => &[(-14, -5), (5, 14)],
                Line::Dotted => &[(-14, -11), (-6, -3), (3, 6), (11, 14)],
            };
            for &(a, b) in pieces {
                backend.draw_line((x + a, y), (x + b, y), &line)?;
            }
        }
        let (s, style) = (look.size, look.marker_style());
        let fill = look.filled;
        let diamond = [
            (x, y - s - 1),
            (x + s + 1, y),
            (x, y + s + 1),
            (x - s - 1, y),
        ];
        match look.marker {
            Marker::None => Ok(()),
            Marker::Circle => backend.draw_circle((x, y), s.unsigned_abs(), &style, fill),
            Marker::Square => backend.draw_rect((x - s, y - s), (x + s, y + s), &style, fill),
            Marker::Triangle => {
                let h = s + 1;
                let tri = [(x, y - h), (x + h, y + h * 2 / 3), (x - h, y + h * 2 / 3)];
                outline(backend, &tri, &style, fill)
            }
            Marker::Diamond => outline(backend, &diamond, &style, fill),
            Marker::Cross => {
                let l = s + 1;
                backend.draw_line((x - l, y - l), (x + l, y + l), &style)?;
                backend.draw_line((x - l, y + l), (x + l, y - l), &style)
            }
            Marker::Plus => {
                let l = s + 2;
                backend.draw_line((x - l, y), (x + l, y), &style)?;
                backend.draw_line((x, y - l), (x, y + l), &style)
            }
        }
    }
}

/// A closed polygon, filled or outlined.
fn outline<DB: DrawingBackend>(
    backend: &mut DB,
    corners: &[BackendCoord],
    style: &ShapeStyle,
    fill: bool,
) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
    if fill {
        backend.fill_polygon(corners.iter().copied(), style)
    } else {
        backend.draw_path(corners.iter().chain(corners.first()).copied(), style)
    }
}

/// The legend of a figure: its entries (label and look), drawn in a panel right of the chart,
/// where it never hides a curve.
#[derive(Default)]
pub struct Legend(pub Vec<(String, Look)>);

impl Legend {
    /// Adds an entry.
    pub fn add(&mut self, label: impl Into<String>, look: Look) {
        self.0.push((label.into(), look));
    }

    /// Splits `root` into the chart's area and the legend's, as wide as the longest label.
    pub fn split<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> (DrawingArea<DB, Shift>, DrawingArea<DB, Shift>) {
        let longest = self
            .0
            .iter()
            .map(|(l, _)| l.chars().count())
            .max()
            .unwrap_or(0);
        let width = (48 + 8 * longest as u32).clamp(110, 300);
        let (w, _) = root.dim_in_pixel();
        root.split_horizontally(w.saturating_sub(width))
    }

    /// Draws the entries from the top of `area`: each its sample and its label.
    pub fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Result<()> {
        for (i, (label, look)) in self.0.iter().enumerate() {
            let y = 50 + 22 * i as i32;
            ok(area.draw(&MarkerAt {
                at: (2, y),
                look: *look,
                with_line: true,
            }))?;
            let text = Text::new(label.as_str(), (36, y - 8), ("sans-serif", 15));
            ok(area.draw(&text))?;
        }
        Ok(())
    }
}

/// The range of `values` (finite ones only) widened by `pad` of its width on both sides; `empty`
/// when there is none.
pub fn span(values: impl IntoIterator<Item = f64>, pad: f64, empty: Range<f64>) -> Range<f64> {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return empty;
    }
    let width = if hi > lo { hi - lo } else { lo.abs().max(1.0) };
    (lo - pad * width)..(hi + pad * width)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels() {
        assert_eq!(tick(5000.0, &(0.0..6000.0)), "5000");
        assert_eq!(tick(0.5, &(0.0..4.0)), "0.5");
        assert_eq!(tick(-2.2e-16, &(-1.0..1.0)), "0");
        assert_eq!(tick(0.0015, &(-0.0025..0.0015)), "1.5e-3");
        assert_eq!(tick(5e-4, &(-0.0025..0.0015)), "5.0e-4");
        assert_eq!(tick(0.002, &(0.0..0.014)), "0.002");
    }
}
