//! The plots (SVG drawn with plotters, PNG rasterised from it with resvg): success rate
//! against each swept axis with Wilson 95 % intervals, and median completion time and mean
//! packets sent against packet loss; one line per protocol, each with its own colour, marker
//! shape and dashes and shifted a little sideways, so that lines lying on each other stay
//! apart; the legend beside the data, never over it.

use crate::plan::Axis;
use crate::stats::PointSummary;
use crate::Error;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// The whole picture; the legend takes the right-hand strip, outside the data.
const SIZE: (u32, u32) = (1000, 540);
const LEGEND_WIDTH: u32 = 190;
const COLOURS: [RGBColor; LOOKS] = [
    RGBColor(31, 119, 180),
    RGBColor(230, 120, 20),
    RGBColor(44, 160, 44),
    RGBColor(200, 40, 40),
    RGBColor(148, 103, 189),
    RGBColor(120, 120, 120),
    RGBColor(140, 86, 75),
    RGBColor(210, 80, 170),
];
/// Dash and gap lengths in pixels per line (0: solid), so that lines lying on each other
/// (at 0 % or 100 %, say) still show both.
const DASHES: [(u32, u32); LOOKS] = [
    (0, 0),
    (12, 6),
    (3, 4),
    (18, 4),
    (8, 3),
    (2, 7),
    (14, 3),
    (5, 5),
];
/// Colours, dashes and marker shapes there are of each: eight lines differ in all three (the
/// reproduction campaign draws seven protocols), and up to 64 in colour and marker together.
const LOOKS: usize = 8;

/// How line `k` is drawn: its colour, its marker shape and its dashes.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Look {
    colour: RGBColor,
    shape: usize,
    dash: (u32, u32),
}

/// Line `k`'s look: decided here once, for the line, its markers and its legend row. Past
/// eight lines the shape and the dashes move on by one per round of colours, so that no two
/// of the first 64 lines share both colour and marker.
fn look(k: usize) -> Look {
    let round = k / LOOKS;
    Look {
        colour: COLOURS[k % LOOKS],
        shape: (k + round) % LOOKS,
        dash: DASHES[(k + 2 * round) % LOOKS],
    }
}
/// Each line's points are shifted sideways by this fraction of the x range (times its rank
/// from the middle line), so coinciding points stay apart.
const DODGE: f64 = 0.02;

/// The value measured at a point, its interval (low, high) if any, and whether it rests on a
/// single run (drawn hollow).
type Mark = (f64, Option<(f64, f64)>, bool);

/// A point of a line: x and what was measured there.
type Point = (f64, Mark);

/// One line of a plot.
struct Line {
    name: String,
    points: Vec<Point>,
}

/// What the y axis holds, which decides its range and its tick labels.
#[derive(Clone, Copy, PartialEq)]
enum YKind {
    /// A proportion, shown 0 % to 100 %.
    Rate,
    /// A whole number, from 0 up, with integer ticks.
    Count,
    /// A non-negative quantity, from 0 up.
    Amount,
}

/// What one plot shows.
struct Figure<'a> {
    title: String,
    x_label: &'a str,
    y_label: &'a str,
    y_kind: YKind,
    lines: Vec<Line>,
    /// What a hollow mark means, for the legend.
    hollow: Option<&'static str>,
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
            y_kind: YKind::Rate,
            lines: lines(&on_axis, |s| {
                Some((s.success_rate, Some((s.success_low, s.success_high)), false))
            }),
            hollow: None,
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
        title: format!(
            "median completion time of successful runs against {}",
            Axis::Loss.label()
        ),
        x_label: Axis::Loss.label(),
        y_label: "completion (s)",
        y_kind: YKind::Amount,
        lines: lines(on_axis, |s| {
            s.median_completion_ms
                .map(|t| (t / 1000.0, None, s.successes == 1))
        }),
        hollow: Some("hollow: n=1, median\nof one successful run"),
    };
    let packets = Figure {
        title: format!("mean packets sent per run against {}", Axis::Loss.label()),
        x_label: Axis::Loss.label(),
        y_label: "packets sent",
        y_kind: YKind::Count,
        lines: lines(on_axis, |s| Some((s.mean_packets_sent, None, false))),
        hollow: None,
    };
    let mut written = save(&completion, dir, "completion-loss")?;
    written.extend(save(&packets, dir, "packets-loss")?);
    Ok(written)
}

type Measure = fn(&PointSummary) -> Option<Mark>;

fn lines(on_axis: &[&PointSummary], measure: Measure) -> Vec<Line> {
    let mut names: Vec<&str> = on_axis.iter().map(|s| s.protocol.as_str()).collect();
    names.sort_unstable();
    names.dedup();
    names
        .into_iter()
        .map(|name| Line {
            name: name.to_string(),
            points: on_axis
                .iter()
                .filter(|s| s.protocol == name)
                .filter_map(|s| measure(s).map(|mark| (s.value, mark)))
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

/// Smallest and largest value; (0, 0) when there is none (shared with `dynarole show`).
pub fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if lo.is_finite() {
        (lo, hi)
    } else {
        (0.0, 0.0)
    }
}

/// The y range: rates with a little room beyond 0 % and 100 % so that marks there are not cut
/// by the frame; counts and amounts from 0.
fn y_range(figure: &Figure) -> (f64, f64) {
    if figure.y_kind == YKind::Rate {
        return (-0.04, 1.06);
    }
    let all = figure.lines.iter().flat_map(|l| l.points.iter());
    let highest = all
        .flat_map(|p| [p.1 .0, p.1 .1.map_or(p.1 .0, |i| i.1)])
        .fold(0.0_f64, f64::max);
    (0.0, if highest > 0.0 { highest * 1.1 } else { 1.0 })
}

fn tick_label(kind: YKind, v: f64) -> String {
    match kind {
        YKind::Rate => format!("{:.0} %", v * 100.0),
        YKind::Count => format!("{v:.0}"),
        YKind::Amount => short_number(v),
    }
}

/// A tick value in at most four decimals, never "-0".
fn short_number(v: f64) -> String {
    // Adding 0.0 turns -0.0 into 0.0.
    let rounded = (v * 1e4).round() / 1e4 + 0.0;
    format!("{rounded}")
}

/// The x range: the swept values with some room, never left of 0 by more than the room kept
/// for the marks (the axes are probabilities and levels).
fn x_range(figure: &Figure) -> (f64, f64) {
    let all = figure.lines.iter().flat_map(|l| l.points.iter());
    let (lo, hi) = bounds(all.map(|p| p.0));
    let room = if hi - lo > 1e-9 {
        (hi - lo) * 0.05
    } else {
        0.05_f64.max(lo.abs() * 0.5)
    };
    (lo - room, hi + room)
}

fn render_svg(figure: &Figure) -> Result<String, String> {
    let (x0, x1) = x_range(figure);
    let dodge = (x1 - x0) * DODGE;
    let (y0, y1) = y_range(figure);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let (plot_area, legend_area) = root.split_horizontally(SIZE.0 - LEGEND_WIDTH);
        let kind = figure.y_kind;
        let ticks = move |v: &f64| tick_label(kind, *v);
        let mut chart = ChartBuilder::on(&plot_area)
            .caption(&figure.title, ("sans-serif", 17))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc(figure.x_label)
            .y_desc(figure.y_label)
            .y_label_formatter(&ticks)
            .x_label_formatter(&|v| short_number(*v))
            .light_line_style(WHITE)
            .draw()
            .map_err(|e| e.to_string())?;
        for (k, line) in figure.lines.iter().enumerate() {
            let shift = dodge * (k as f64 - (figure.lines.len() as f64 - 1.0) / 2.0);
            draw_line(&mut chart, &root, line, k, shift).map_err(|e| e.to_string())?;
        }
        draw_legend(&legend_area, figure).map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

type Chart<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;
type Area<'b> = DrawingArea<SVGBackend<'b>, plotters::coord::Shift>;
type DrawResult<'b> =
    Result<(), DrawingAreaErrorKind<<SVGBackend<'b> as DrawingBackend>::ErrorType>>;

/// Line `k`: its dashes, its intervals, its markers (in pixels on `root`) and their notes.
fn draw_line<'b>(
    chart: &mut Chart<'_, 'b>,
    root: &Area<'b>,
    line: &Line,
    k: usize,
    shift: f64,
) -> DrawResult<'b> {
    let colour = look(k).colour;
    let style = colour.stroke_width(2);
    let points: Vec<(f64, f64)> = line.points.iter().map(|p| (p.0 + shift, p.1 .0)).collect();
    match look(k).dash {
        (0, _) => chart.draw_series(LineSeries::new(points.clone(), style))?,
        (dash, gap) => {
            chart.draw_series(DashedLineSeries::new(points.clone(), dash, gap, style))?
        }
    };
    chart.draw_series(line.points.iter().filter_map(|p| {
        p.1 .1.map(|(lo, hi)| {
            ErrorBar::new_vertical(p.0 + shift, lo, p.1 .0, hi, colour.stroke_width(1), 8)
        })
    }))?;
    for (at, point) in points.iter().zip(&line.points) {
        let centre = chart.backend_coord(at);
        draw_marker(root, k, centre, point.1 .2)?;
    }
    Ok(())
}

/// Line `k`'s marker at `c`, filled, or hollow (white inside) for a value from a single run.
fn draw_marker<'b>(area: &Area<'b>, k: usize, c: (i32, i32), hollow: bool) -> DrawResult<'b> {
    let Look { colour, shape, .. } = look(k);
    let outline = marker(shape, c);
    if hollow {
        area.draw(&Polygon::new(outline.clone(), WHITE.filled()))?;
        let mut closed = outline;
        closed.push(closed[0]);
        area.draw(&PathElement::new(closed, colour.stroke_width(2)))
    } else {
        area.draw(&Polygon::new(outline, colour.filled()))
    }
}

/// Marker `shape` around `c`: circle, square, triangle, diamond, inverted triangle, plus,
/// hexagon, cross.
fn marker(shape: usize, c: (i32, i32)) -> Vec<(i32, i32)> {
    let at = |dx: i32, dy: i32| (c.0 + dx, c.1 + dy);
    match shape % LOOKS {
        0 => (0..16)
            .map(|i| {
                let a = std::f64::consts::PI * f64::from(i) / 8.0;
                at(
                    (5.0 * a.cos()).round() as i32,
                    (5.0 * a.sin()).round() as i32,
                )
            })
            .collect(),
        1 => vec![at(-4, -4), at(4, -4), at(4, 4), at(-4, 4)],
        2 => vec![at(0, -6), at(6, 5), at(-6, 5)],
        3 => vec![at(0, -6), at(6, 0), at(0, 6), at(-6, 0)],
        4 => vec![at(0, 6), at(6, -5), at(-6, -5)],
        6 => vec![
            at(-3, -5),
            at(3, -5),
            at(6, 0),
            at(3, 5),
            at(-3, 5),
            at(-6, 0),
        ],
        7 => vec![
            at(-4, -6),
            at(0, -2),
            at(4, -6),
            at(6, -4),
            at(2, 0),
            at(6, 4),
            at(4, 6),
            at(0, 2),
            at(-4, 6),
            at(-6, 4),
            at(-2, 0),
            at(-6, -4),
        ],
        _ => vec![
            at(-2, -6),
            at(2, -6),
            at(2, -2),
            at(6, -2),
            at(6, 2),
            at(2, 2),
            at(2, 6),
            at(-2, 6),
            at(-2, 2),
            at(-6, 2),
            at(-6, -2),
            at(-2, -2),
        ],
    }
}

/// One row per line (its dashes and marker, then its name), and what the notes mean, in the
/// strip right of the data.
fn draw_legend<'b>(area: &Area<'b>, figure: &Figure) -> DrawResult<'b> {
    let top = 70;
    for (k, line) in figure.lines.iter().enumerate() {
        let colour = look(k).colour;
        let y = top + 26 * i32::try_from(k).unwrap_or(0);
        let style = colour.stroke_width(2);
        let ends = vec![(8, y), (48, y)];
        match look(k).dash {
            (0, _) => area.draw(&PathElement::new(ends, style))?,
            (dash, gap) => area.draw(&plotters::element::DashedPathElement::new(
                ends, dash, gap, style,
            ))?,
        }
        draw_marker(area, k, (28, y), false)?;
        area.draw(&Text::new(
            line.name.clone(),
            (58, y - 7),
            ("sans-serif", 14).into_font(),
        ))?;
    }
    let noted = figure.lines.iter().any(|l| l.points.iter().any(|p| p.1 .2));
    if let Some(note) = figure.hollow.filter(|_| noted) {
        let y = top + 26 * i32::try_from(figure.lines.len()).unwrap_or(0) + 6;
        draw_marker(area, 0, (28, y), true)?;
        for (row, text) in note.lines().enumerate() {
            let y = y - 7 + 16 * i32::try_from(row).unwrap_or(0);
            area.draw(&Text::new(text, (58, y), ("sans-serif", 13).into_font()))?;
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A point on the loss axis: `successes` of 2 runs, median time and mean packets.
    fn summary(protocol: &str, loss: f64, successes: u64, packets: f64) -> PointSummary {
        let (success_low, success_high) = crate::stats::wilson(successes, 2);
        PointSummary {
            axis: "loss".into(),
            value: loss,
            protocol: protocol.into(),
            runs: 2,
            successes,
            success_rate: successes as f64 / 2.0,
            success_low,
            success_high,
            timeouts: 2 - successes,
            wrong_configurations: 0,
            stopped: 0,
            violations: 0,
            median_completion_ms: (successes > 0).then_some(30_000.0 + 1000.0 * loss),
            mean_packets_sent: packets,
        }
    }

    fn loss_plots() -> (tempfile::TempDir, Vec<PathBuf>) {
        let summaries = [
            summary("lattice", 0.0, 2, 4400.0),
            summary("lattice", 0.2, 1, 4500.0),
            summary("paper", 0.0, 2, 4200.0),
            summary("paper", 0.2, 2, 4600.0),
        ];
        let dir = tempfile::tempdir().expect("temp dir");
        let written = write_all(&summaries, dir.path()).expect("plots");
        (dir, written)
    }

    fn svg(written: &[PathBuf], name: &str) -> String {
        let path = written
            .iter()
            .find(|p| p.file_name().and_then(|n| n.to_str()) == Some(name))
            .expect("plot written");
        std::fs::read_to_string(path).expect("svg")
    }

    /// The texts of an SVG document, in order.
    fn texts(svg: &str) -> Vec<&str> {
        svg.split("</text>")
            .filter_map(|t| t.rsplit_once('>').map(|(_, text)| text.trim()))
            .collect()
    }

    #[test]
    fn every_title_names_its_x_axis() {
        let (_dir, written) = loss_plots();
        for name in [
            "success-loss.svg",
            "completion-loss.svg",
            "packets-loss.svg",
        ] {
            let svg = svg(&written, name);
            assert!(
                texts(&svg)
                    .iter()
                    .any(|t| t.contains(" against packet loss probability")),
                "{name}"
            );
        }
    }

    #[test]
    fn counts_start_at_zero_with_whole_ticks() {
        let (_dir, written) = loss_plots();
        let svg = svg(&written, "packets-loss.svg");
        let texts = texts(&svg);
        assert!(texts.contains(&"0") && texts.contains(&"4000"), "{texts:?}");
        assert!(
            !texts
                .iter()
                .any(|t| t.ends_with(".0") || t.starts_with('-')),
            "{texts:?}"
        );
    }

    #[test]
    fn a_median_of_one_run_is_hollow_and_explained() {
        let (_dir, written) = loss_plots();
        let completion = svg(&written, "completion-loss.svg");
        // One hollow mark on the data (lattice at 0.2) and its sample in the legend.
        assert_eq!(
            completion
                .matches(r##"<polygon opacity="1" fill="#FFFFFF""##)
                .count(),
            2
        );
        assert!(texts(&completion).contains(&"hollow: n=1, median"));
        let packets = svg(&written, "packets-loss.svg");
        assert!(!packets.contains(r##"fill="#FFFFFF" points"##));
    }

    #[test]
    fn the_legend_is_right_of_the_data_and_lines_differ_in_mark_and_dash() {
        let (_dir, written) = loss_plots();
        let svg = svg(&written, "success-loss.svg");
        let legend_x = |name: &str| -> i64 {
            let end = svg
                .find(&format!("\n{name}\n</text>"))
                .expect("legend entry");
            let start = svg[..end].rfind("<text x=\"").expect("text") + 9;
            let rest = &svg[start..];
            rest[..rest.find('"').expect("quote")].parse().expect("x")
        };
        let data_right = i64::from(SIZE.0 - LEGEND_WIDTH);
        assert!(legend_x("lattice") > data_right && legend_x("paper") > data_right);
        let shapes: Vec<usize> = (0..LOOKS).map(|k| marker(k, (0, 0)).len()).collect();
        assert_eq!(shapes, [16, 4, 3, 4, 3, 12, 6, 12]);
        assert_ne!(marker(5, (0, 0)), marker(7, (0, 0)), "plus and cross");
        assert_ne!(marker(1, (0, 0)), marker(3, (0, 0)), "square and diamond");
        assert_ne!(
            marker(2, (0, 0)),
            marker(4, (0, 0)),
            "triangles up and down"
        );
        for (k, dash) in DASHES.iter().enumerate() {
            assert!(
                !DASHES[k + 1..].contains(dash),
                "line {k} has its own dashes"
            );
        }
    }

    #[test]
    fn no_two_lines_look_alike() {
        // The reproduction campaign's seventh protocol once took the first one's look.
        let looks: Vec<Look> = (0..LOOKS).map(look).collect();
        for (k, a) in looks.iter().enumerate() {
            for b in &looks[k + 1..] {
                assert!(a.colour != b.colour && a.shape != b.shape && a.dash != b.dash);
            }
        }
        let pairs: std::collections::HashSet<((u8, u8, u8), usize)> = (0..LOOKS * LOOKS)
            .map(|k| (look(k).colour.rgb(), look(k).shape))
            .collect();
        assert_eq!(
            pairs.len(),
            LOOKS * LOOKS,
            "64 lines differ in colour or marker"
        );
    }

    #[test]
    fn tick_labels_never_read_minus_zero() {
        assert_eq!(short_number(-0.0), "0");
        assert_eq!(short_number(-1e-12), "0");
        assert_eq!(short_number(0.15000000000000002), "0.15");
        assert_eq!(tick_label(YKind::Count, 5000.0), "5000");
        assert_eq!(tick_label(YKind::Rate, 0.5), "50 %");
    }
}
