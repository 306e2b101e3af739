//! The plots (SVG drawn with plotters, PNG rasterised from it with resvg): success rate
//! against each swept axis with Wilson 95 % intervals, and median completion time and mean
//! packets sent against packet loss; one line per protocol.

use crate::plan::Axis;
use crate::stats::PointSummary;
use crate::Error;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

const SIZE: (u32, u32) = (800, 520);
const COLOURS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(230, 120, 20),
    RGBColor(44, 160, 44),
    RGBColor(200, 40, 40),
    RGBColor(148, 103, 189),
    RGBColor(120, 120, 120),
];

/// A point of a line: x, y, and an optional interval (low, high) of y.
type Point = (f64, f64, Option<(f64, f64)>);

/// One line of a plot.
struct Line {
    name: String,
    points: Vec<Point>,
}

/// What one plot shows.
struct Figure<'a> {
    title: String,
    x_label: &'a str,
    y_label: &'a str,
    lines: Vec<Line>,
}

/// Writes every plot into `dir`; returns the files written.
pub fn write_all(summaries: &[PointSummary], dir: &Path) -> Result<Vec<PathBuf>, Error> {
    let mut written = Vec::new();
    for axis in Axis::ALL {
        let on_axis: Vec<&PointSummary> =
            summaries.iter().filter(|s| s.axis == axis.name()).collect();
        if on_axis.is_empty() {
            continue;
        }
        let success = Figure {
            title: format!("success rate against {} (95 % Wilson)", axis.label()),
            x_label: axis.label(),
            y_label: "success rate",
            lines: lines(&on_axis, |s| {
                Some((s.success_rate, Some((s.success_low, s.success_high))))
            }),
        };
        written.extend(save(&success, dir, &format!("success-{}", axis.name()))?);
        if axis == Axis::Loss {
            written.extend(loss_figures(&on_axis, dir)?);
        }
    }
    Ok(written)
}

fn loss_figures(on_axis: &[&PointSummary], dir: &Path) -> Result<Vec<PathBuf>, Error> {
    let completion = Figure {
        title: "median completion time of successful runs".into(),
        x_label: Axis::Loss.label(),
        y_label: "completion (s)",
        lines: lines(on_axis, |s| {
            s.median_completion_ms.map(|t| (t / 1000.0, None))
        }),
    };
    let packets = Figure {
        title: "mean packets sent per run".into(),
        x_label: Axis::Loss.label(),
        y_label: "packets sent",
        lines: lines(on_axis, |s| Some((s.mean_packets_sent, None))),
    };
    let mut written = save(&completion, dir, "completion-loss")?;
    written.extend(save(&packets, dir, "packets-loss")?);
    Ok(written)
}

type Measure = fn(&PointSummary) -> Option<(f64, Option<(f64, f64)>)>;

fn lines(on_axis: &[&PointSummary], measure: Measure) -> Vec<Line> {
    let mut names: Vec<&str> = on_axis.iter().map(|s| s.protocol.as_str()).collect();
    names.dedup();
    names.sort_unstable();
    names.dedup();
    names
        .into_iter()
        .map(|name| Line {
            name: name.to_string(),
            points: on_axis
                .iter()
                .filter(|s| s.protocol == name)
                .filter_map(|s| measure(s).map(|(y, ci)| (s.value, y, ci)))
                .collect(),
        })
        .collect()
}

/// `NAME.svg` and `NAME.png` in `dir`.
fn save(figure: &Figure, dir: &Path, name: &str) -> Result<Vec<PathBuf>, Error> {
    let svg = render_svg(figure).map_err(|e| Error::Plot(format!("{name}: {e}")))?;
    let png = rasterise_svg(&svg).map_err(|e| Error::Plot(format!("{name}: {e}")))?;
    let svg_path = dir.join(format!("{name}.svg"));
    let png_path = dir.join(format!("{name}.png"));
    std::fs::write(&svg_path, svg).map_err(|e| Error::io(&svg_path, e))?;
    std::fs::write(&png_path, png).map_err(|e| Error::io(&png_path, e))?;
    Ok(vec![svg_path, png_path])
}

fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if !lo.is_finite() {
        (0.0, 1.0)
    } else if hi - lo < 1e-9 {
        (
            lo - 0.5_f64.max(lo.abs() * 0.05),
            hi + 0.5_f64.max(hi.abs() * 0.05),
        )
    } else {
        (lo, hi)
    }
}

fn render_svg(figure: &Figure) -> Result<String, String> {
    let all = || figure.lines.iter().flat_map(|l| l.points.iter());
    let (x0, x1) = bounds(all().map(|p| p.0));
    let dodge = (x1 - x0) * 0.006;
    let (x0, x1) = (x0 - (x1 - x0) * 0.03, x1 + (x1 - x0) * 0.03);
    let (y0, y1) = if figure.y_label == "success rate" {
        (0.0, 1.05)
    } else {
        let (lo, hi) = bounds(all().map(|p| p.1));
        let pad = (hi - lo) * 0.08;
        (lo - pad, hi + pad)
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let mut chart = ChartBuilder::on(&root)
            .caption(&figure.title, ("sans-serif", 20))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(65)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc(figure.x_label)
            .y_desc(figure.y_label)
            .draw()
            .map_err(|e| e.to_string())?;
        for (k, line) in figure.lines.iter().enumerate() {
            let colour = COLOURS[k % COLOURS.len()];
            // Lines that coincide stay visible: each protocol's marks are shifted a little.
            let shift = dodge * (k as f64 - (figure.lines.len() as f64 - 1.0) / 2.0);
            draw_line(&mut chart, line, colour, shift).map_err(|e| e.to_string())?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .position(SeriesLabelPosition::LowerLeft)
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

type Chart<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;
type DrawResult<'b> =
    Result<(), DrawingAreaErrorKind<<SVGBackend<'b> as DrawingBackend>::ErrorType>>;

fn draw_line<'b>(
    chart: &mut Chart<'_, 'b>,
    line: &Line,
    colour: RGBColor,
    shift: f64,
) -> DrawResult<'b> {
    let style = colour.stroke_width(2);
    chart
        .draw_series(LineSeries::new(
            line.points.iter().map(|p| (p.0 + shift, p.1)),
            style,
        ))?
        .label(line.name.clone())
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
    chart.draw_series(
        line.points
            .iter()
            .map(|p| Circle::new((p.0 + shift, p.1), 3, colour.filled())),
    )?;
    chart.draw_series(line.points.iter().filter_map(|p| {
        p.2.map(|(lo, hi)| {
            ErrorBar::new_vertical(p.0 + shift, lo, p.1, hi, colour.stroke_width(1), 8)
        })
    }))?;
    Ok(())
}

/// An SVG document as a PNG image (resvg), with a sans-serif face that is installed. Text needs
/// a system font; without one the shapes still draw. `dynarole show` uses it too.
pub fn rasterise_svg(svg: &str) -> Result<Vec<u8>, String> {
    let mut options = resvg::usvg::Options::default();
    let fonts = options.fontdb_mut();
    fonts.load_system_fonts();
    // `sans-serif` maps to Arial by default; use a sans face that is actually installed.
    let family = fonts
        .faces()
        .flat_map(|f| f.families.iter().map(|(name, _)| name.clone()))
        .find(|n| n.contains("Sans"));
    if let Some(family) = family {
        fonts.set_sans_serif_family(family);
    }
    let tree = resvg::usvg::Tree::from_str(svg, &options).map_err(|e| e.to_string())?;
    let size = tree.size().to_int_size();
    let mut pixmap =
        resvg::tiny_skia::Pixmap::new(size.width(), size.height()).ok_or("empty picture")?;
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::default(),
        &mut pixmap.as_mut(),
    );
    pixmap.encode_png().map_err(|e| e.to_string())
}
