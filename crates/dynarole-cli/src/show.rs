//! `dynarole show`: a picture of a configuration (SVG drawn with plotters, PNG rasterised from
//! it with resvg). Modules are seen in an isometric view, far ones first; each ATRON module is a
//! disc whose two halves are its hemispheres, each M-TRAN module two blocks and their link.

use crate::load::Failure;
use crate::world::read_configuration;
use dynarole_world::{AtronConfiguration, Configuration, MtranConfiguration, Port};
use plotters::prelude::*;
use std::path::Path;
use std::process::ExitCode;

/// Pixels per lattice unit.
const SCALE_PX: f64 = 70.0;
/// Drawn radius of an ATRON module, in lattice units (smaller than the real 0.69 so that
/// neighbours do not hide each other).
const ATRON_RADIUS: f64 = 0.45;
/// Drawn half-size of an M-TRAN block, in block pitches.
const MTRAN_HALF_BLOCK: f64 = 0.4;
const MARGIN_PX: f64 = 60.0;
/// Wide enough for the legend.
const MIN_WIDTH_PX: f64 = 640.0;
const NORTH: RGBColor = RGBColor(70, 130, 180);
const SOUTH: RGBColor = RGBColor(240, 150, 40);
const LATCH: RGBColor = RGBColor(40, 40, 40);

pub fn run(config_path: &Path, output: &Path) -> Result<ExitCode, Failure> {
    let config = read_configuration(config_path)?;
    let svg = render_svg(&config)
        .map_err(|e| Failure::Input(format!("cannot draw {}: {e}", config_path.display())))?;
    let extension = output.extension().and_then(|e| e.to_str()).unwrap_or("");
    let bytes = match extension {
        "svg" => svg.into_bytes(),
        "png" => rasterise(&svg)
            .map_err(|e| Failure::Input(format!("cannot make {}: {e}", output.display())))?,
        _ => {
            return Err(Failure::Usage(format!(
                "{}: the picture must be a .svg or .png file",
                output.display()
            )))
        }
    };
    std::fs::write(output, bytes)
        .map_err(|e| Failure::Input(format!("cannot write {}: {e}", output.display())))?;
    println!("wrote {}", output.display());
    Ok(ExitCode::SUCCESS)
}

/// Something to draw, at a depth (larger is farther from the viewer).
struct Shape {
    depth: f64,
    kind: ShapeKind,
}

enum ShapeKind {
    /// An ATRON module: centre, north->south axis, name.
    Sphere {
        centre: [f64; 3],
        axis: [f64; 3],
        name: String,
    },
    /// An M-TRAN block: centre, which block, and the module's name (on the north block only).
    Block {
        centre: [f64; 3],
        north: bool,
        name: Option<String>,
    },
    /// A latch or an M-TRAN link between two points.
    Segment {
        from: [f64; 3],
        to: [f64; 3],
        latch: bool,
    },
    /// Where two latched connectors meet.
    Contact { at: [f64; 3] },
}

/// Isometric projection (y up): screen x to the right, screen y downwards.
fn project(p: [f64; 3]) -> (f64, f64) {
    let cos30 = 3f64.sqrt() / 2.0;
    ((p[0] - p[2]) * cos30, -(p[1] + (p[0] + p[2]) * 0.5))
}

fn depth(p: [f64; 3]) -> f64 {
    // Towards the viewer is +x, +y, +z.
    -(p[0] + p[1] + p[2])
}

/// The configuration as an SVG document.
pub fn render_svg(config: &Configuration) -> Result<String, String> {
    let mut shapes = match config {
        Configuration::Atron(c) => atron_shapes(c),
        Configuration::Mtran(c) => mtran_shapes(c),
    };
    shapes.sort_by(|a, b| b.depth.total_cmp(&a.depth));
    let points: Vec<(f64, f64)> = shapes
        .iter()
        .flat_map(|s| s.points())
        .map(project)
        .collect();
    let (min_x, max_x) = bounds(points.iter().map(|p| p.0));
    let (min_y, max_y) = bounds(points.iter().map(|p| p.1));
    let to_px = move |p: [f64; 3]| -> (i32, i32) {
        let (x, y) = project(p);
        (
            (MARGIN_PX + (x - min_x + 1.0) * SCALE_PX) as i32,
            (MARGIN_PX + (y - min_y + 1.0) * SCALE_PX) as i32,
        )
    };
    let width = (2.0 * MARGIN_PX + (max_x - min_x + 2.0) * SCALE_PX).max(MIN_WIDTH_PX) as u32;
    let height = (2.0 * MARGIN_PX + (max_y - min_y + 2.0) * SCALE_PX + 40.0) as u32;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        for shape in &shapes {
            draw(&root, shape, &to_px).map_err(|e| e.to_string())?;
        }
        let title = format!(
            "{} ({}, {} modules)",
            config.metadata().name,
            config.robot().name(),
            module_count(config)
        );
        root.draw(&Text::new(title, (10, 10), ("sans-serif", 18).into_font()))
            .map_err(|e| e.to_string())?;
        let legend = match config {
            Configuration::Atron(_) => "blue: north hemisphere (connectors 0-3); orange: south (4-7); black: latches",
            Configuration::Mtran(_) => "blue: north block (male 0-2); orange: south block (female 3-5); grey: link; black: latches",
        };
        let bottom = i32::try_from(height).unwrap_or(i32::MAX) - 24;
        root.draw(&Text::new(
            legend,
            (10, bottom),
            ("sans-serif", 13).into_font(),
        ))
        .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

fn module_count(config: &Configuration) -> usize {
    match config {
        Configuration::Atron(c) => c.modules().len(),
        Configuration::Mtran(c) => c.modules().len(),
    }
}

fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    })
}

impl Shape {
    fn points(&self) -> Vec<[f64; 3]> {
        match &self.kind {
            ShapeKind::Sphere { centre, .. } | ShapeKind::Block { centre, .. } => vec![*centre],
            ShapeKind::Segment { from, to, .. } => vec![*from, *to],
            ShapeKind::Contact { at } => vec![*at],
        }
    }
}

fn atron_shapes(config: &AtronConfiguration) -> Vec<Shape> {
    let mut shapes = Vec::new();
    for m in config.modules() {
        let centre = m.position.map(f64::from);
        let axis = m.orientation.axis().map(f64::from);
        let name = m.name.clone();
        shapes.push(Shape {
            depth: depth(centre),
            kind: ShapeKind::Sphere { centre, axis, name },
        });
    }
    for latch in config.latches() {
        let centre = |p: Port| config.module(p.module).map(|m| m.position.map(f64::from));
        if let (Some(from), Some(to)) = (centre(latch.male), centre(latch.female)) {
            push_latch(&mut shapes, from, to);
        }
    }
    shapes
}

fn mtran_shapes(config: &MtranConfiguration) -> Vec<Shape> {
    let blocks = |i: usize| {
        config.modules().get(i).map(|m| {
            let north = m
                .north_block()
                .centre_quarter_pitch
                .map(|v| f64::from(v) / 2.0);
            let south = m
                .south_block()
                .centre_quarter_pitch
                .map(|v| f64::from(v) / 2.0);
            (north, south)
        })
    };
    let mut shapes = Vec::new();
    for (i, m) in config.modules().iter().enumerate() {
        let Some((north, south)) = blocks(i) else {
            continue;
        };
        shapes.push(Shape {
            depth: depth(north),
            kind: ShapeKind::Block {
                centre: north,
                north: true,
                name: Some(m.name.clone()),
            },
        });
        shapes.push(Shape {
            depth: depth(south),
            kind: ShapeKind::Block {
                centre: south,
                north: false,
                name: None,
            },
        });
        shapes.push(Shape {
            depth: f64::INFINITY,
            kind: ShapeKind::Segment {
                from: north,
                to: south,
                latch: false,
            },
        });
    }
    for latch in config.latches() {
        let block = |p: Port| blocks(p.module).map(|(n, s)| if p.connector < 3 { n } else { s });
        if let (Some(from), Some(to)) = (block(latch.male), block(latch.female)) {
            push_latch(&mut shapes, from, to);
        }
    }
    shapes
}

/// A latch: a bar behind every module, and a dot on top where the connectors meet.
fn push_latch(shapes: &mut Vec<Shape>, from: [f64; 3], to: [f64; 3]) {
    shapes.push(Shape {
        depth: f64::INFINITY,
        kind: ShapeKind::Segment {
            from,
            to,
            latch: true,
        },
    });
    let middle = std::array::from_fn(|k| (from[k] + to[k]) / 2.0);
    shapes.push(Shape {
        depth: f64::NEG_INFINITY,
        kind: ShapeKind::Contact { at: middle },
    });
}

type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;
type DrawResult<'a> =
    Result<(), DrawingAreaErrorKind<<SVGBackend<'a> as DrawingBackend>::ErrorType>>;

fn draw<'a>(
    root: &Area<'a>,
    shape: &Shape,
    to_px: &dyn Fn([f64; 3]) -> (i32, i32),
) -> DrawResult<'a> {
    match &shape.kind {
        ShapeKind::Sphere { centre, axis, name } => {
            let radius_px = (ATRON_RADIUS * SCALE_PX) as i32;
            let c = to_px(*centre);
            root.draw(&Circle::new(c, radius_px, NORTH.filled()))?;
            root.draw(&Polygon::new(
                south_half(*centre, *axis, to_px),
                SOUTH.filled(),
            ))?;
            root.draw(&Circle::new(c, radius_px, BLACK.stroke_width(1)))?;
            label(root, name, c)
        }
        ShapeKind::Block {
            centre,
            north,
            name,
        } => {
            let half = (MTRAN_HALF_BLOCK * SCALE_PX) as i32;
            let c = to_px(*centre);
            let color = if *north { NORTH } else { SOUTH };
            root.draw(&Rectangle::new(
                [(c.0 - half, c.1 - half), (c.0 + half, c.1 + half)],
                color.filled(),
            ))?;
            root.draw(&Rectangle::new(
                [(c.0 - half, c.1 - half), (c.0 + half, c.1 + half)],
                BLACK.stroke_width(1),
            ))?;
            match name {
                Some(name) => label(root, name, c),
                None => Ok(()),
            }
        }
        ShapeKind::Contact { at } => root.draw(&Circle::new(to_px(*at), 5, LATCH.filled())),
        ShapeKind::Segment { from, to, latch } => {
            let style = if *latch {
                LATCH.stroke_width(4)
            } else {
                RGBColor(150, 150, 150).stroke_width(6)
            };
            root.draw(&PathElement::new(vec![to_px(*from), to_px(*to)], style))
        }
    }
}

fn label<'a>(root: &Area<'a>, name: &str, centre: (i32, i32)) -> DrawResult<'a> {
    let width = i32::try_from(name.len()).unwrap_or(0) * 4;
    root.draw(&Text::new(
        name.to_string(),
        (centre.0 - width, centre.1 - 7),
        ("sans-serif", 16).into_font().color(&BLACK),
    ))
}

/// The half of the module's disc on the south side, as seen: the points of the projected
/// circle whose direction from the centre leans towards the projected axis.
fn south_half(
    centre: [f64; 3],
    axis: [f64; 3],
    to_px: &dyn Fn([f64; 3]) -> (i32, i32),
) -> Vec<(i32, i32)> {
    let c = to_px(centre);
    let tip = to_px(std::array::from_fn(|k| centre[k] + axis[k]));
    let (ax, ay) = (f64::from(tip.0 - c.0), f64::from(tip.1 - c.1));
    let base = ay.atan2(ax);
    let radius = ATRON_RADIUS * SCALE_PX;
    (0..=36)
        .map(|i| {
            let angle =
                base - std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * f64::from(i) / 36.0;
            (
                c.0 + (radius * angle.cos()) as i32,
                c.1 + (radius * angle.sin()) as i32,
            )
        })
        .collect()
}

/// PNG bytes of an SVG document. Text needs a system font; without one the shapes still draw.
/// (Shared with the campaign plots.)
fn rasterise(svg: &str) -> Result<Vec<u8>, String> {
    dynarole_campaign::rasterise_svg(svg)
}
