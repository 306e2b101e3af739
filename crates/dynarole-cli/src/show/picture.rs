//! A picture of a configuration (`dynarole show`), drawn as SVG with plotters like the
//! campaign's plots (PNG through the same `dynarole_campaign::rasterise_svg`). The view
//! direction is chosen per configuration so that no module hides another; modules are
//! painted far ones first and paler with distance; every module is labelled, every latch is a
//! bar between the two modules with its connector numbers at each end, and an axis gizmo and
//! a legend explain the picture. The canvas has a fixed maximum size whatever the
//! coordinates. What differs from robot to robot (the bodies, their shapes, the legend's
//! words) is in `picture/robots.rs`.

mod bodies;

use dynarole_campaign::bounds;
use dynarole_world::Configuration;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Pixels per lattice unit when the robot is small (larger robots are scaled down to fit).
const MAX_SCALE_PX: f64 = 120.0;
/// The largest picture, in pixels, whatever the coordinates.
const MAX_CANVAS_PX: (f64, f64) = (1400.0, 1000.0);
/// Wide enough for the legend.
const MIN_WIDTH_PX: f64 = 760.0;
/// White space around the robot.
const MARGIN_PX: f64 = 30.0;
/// Room for the title above the robot.
const HEADER_PX: f64 = 40.0;
/// Room for the gizmo and the legend below the robot.
const FOOTER_PX: f64 = 110.0;
/// A module stays visible however far apart the robot is spread.
const MIN_RADIUS_PX: f64 = 4.0;
/// A module drawn smaller than this radius (pixels) has its name beside it rather than on it.
const SMALL_BODY_PX: f64 = 14.0;
/// Size of the modules' names.
const LABEL_PT: i32 = 15;
/// Above this many module bodies the view search (quadratic in them) is skipped.
const MAX_BODIES_FOR_VIEW_SEARCH: usize = 200;
/// Above this many bodies names and connector numbers are left out: nobody could read them at
/// that scale, and their text is most of the cost of a large picture (60,000 modules: a
/// 93 MB SVG that does not rasterise in minutes).
const MAX_LABELLED_BODIES: usize = 400;
/// The preferred view, used when several separate the modules equally well.
const PREFERRED_VIEW_DEG: (f64, f64) = (30.0, 35.0);
/// How much paler the farthest body is than the nearest.
const FADE_FAR: f64 = 0.55;
const LATCH: RGBColor = RGBColor(30, 30, 30);
const LINK: RGBColor = RGBColor(140, 140, 140);
const AXES: [(RGBColor, &str); 3] = [
    (RGBColor(200, 30, 30), "x"),
    (RGBColor(20, 150, 20), "y"),
    (RGBColor(40, 40, 220), "z"),
];

/// An orthographic view from a direction given by azimuth (about y, from +z towards +x) and
/// elevation (above the horizontal plane).
struct View {
    azimuth_deg: f64,
    elevation_deg: f64,
    /// Screen right, screen up and towards the viewer, in world coordinates.
    right: [f64; 3],
    up: [f64; 3],
    toward: [f64; 3],
}

impl View {
    fn new(azimuth_deg: f64, elevation_deg: f64) -> View {
        let (sa, ca) = azimuth_deg.to_radians().sin_cos();
        let (se, ce) = elevation_deg.to_radians().sin_cos();
        View {
            azimuth_deg,
            elevation_deg,
            right: [ca, 0.0, -sa],
            up: [-se * sa, ce, -se * ca],
            toward: [ce * sa, se, ce * ca],
        }
    }

    /// Screen coordinates in lattice units, y downwards.
    fn screen(&self, p: [f64; 3]) -> (f64, f64) {
        (dot(p, self.right), -dot(p, self.up))
    }

    /// Larger is farther from the viewer.
    fn depth(&self, p: [f64; 3]) -> f64 {
        -dot(p, self.toward)
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The view whose picture keeps the bodies' centres farthest apart (up to `clearance`, beyond
/// which separation no longer helps), nearest to the preferred view among equals.
fn choose_view(centres: &[[f64; 3]], clearance: f64) -> View {
    let preferred = View::new(PREFERRED_VIEW_DEG.0, PREFERRED_VIEW_DEG.1);
    if centres.len() > MAX_BODIES_FOR_VIEW_SEARCH {
        return preferred;
    }
    let mut best = (separation(&preferred, centres).min(clearance), preferred);
    for elevation in [20.0, 35.0, 50.0, 65.0] {
        for step in 0..24 {
            let view = View::new(f64::from(step) * 15.0, elevation);
            let score = separation(&view, centres).min(clearance);
            let better = score > best.0 + 1e-9
                || (score > best.0 - 1e-9 && closeness(&view) < closeness(&best.1) - 1e-9);
            if better {
                best = (score, view);
            }
        }
    }
    best.1
}

/// Smallest on-screen distance between two centres.
fn separation(view: &View, centres: &[[f64; 3]]) -> f64 {
    let screen: Vec<(f64, f64)> = centres.iter().map(|&c| view.screen(c)).collect();
    let mut smallest = f64::INFINITY;
    for (i, a) in screen.iter().enumerate() {
        for b in &screen[i + 1..] {
            smallest = smallest.min((a.0 - b.0).hypot(a.1 - b.1));
        }
    }
    smallest
}

/// How far a view is from the preferred one (degrees, azimuth wrapped).
fn closeness(view: &View) -> f64 {
    let turn = (view.azimuth_deg - PREFERRED_VIEW_DEG.0).rem_euclid(360.0);
    turn.min(360.0 - turn) + (view.elevation_deg - PREFERRED_VIEW_DEG.1).abs()
}

/// Everything that is drawn, in world coordinates (the robot's drawing unit).
struct Scene {
    bodies: Vec<Body>,
    /// Bars between the parts of a module.
    links: Vec<[[f64; 3]; 2]>,
    latches: Vec<LatchBar>,
    /// Half-size of a body.
    radius: f64,
    /// The colour of each part, by part index.
    colours: Vec<RGBColor>,
}

/// One module, or one part of a module, as the robot's drawing says.
struct Body {
    centre: [f64; 3],
    name: String,
    kind: bodies::BodyKind,
}

/// A latch between two bodies, with the connector number at each end.
struct LatchBar {
    ends: [([f64; 3], u8); 2],
}

/// Where the scene lands on the canvas.
struct Layout {
    view: View,
    /// Pixels per world unit.
    scale: f64,
    /// Pixel position of world screen coordinate (0, 0).
    offset: (f64, f64),
    size: (u32, u32),
    /// Depths of the nearest and farthest body, for shading.
    depths: (f64, f64),
}

impl Layout {
    fn new(scene: &Scene, view: View) -> Layout {
        let screen: Vec<(f64, f64)> = scene.bodies.iter().map(|b| view.screen(b.centre)).collect();
        let (x0, x1) = bounds(screen.iter().map(|p| p.0));
        let (y0, y1) = bounds(screen.iter().map(|p| p.1));
        let (w, h) = (x1 - x0 + 2.0 * scene.radius, y1 - y0 + 2.0 * scene.radius);
        let room_x = MAX_CANVAS_PX.0 - 2.0 * MARGIN_PX;
        let room_y = MAX_CANVAS_PX.1 - 2.0 * MARGIN_PX - HEADER_PX - FOOTER_PX;
        let scale = MAX_SCALE_PX.min(room_x / w).min(room_y / h);
        let width = (w * scale + 2.0 * MARGIN_PX).max(MIN_WIDTH_PX);
        let height = h * scale + 2.0 * MARGIN_PX + HEADER_PX + FOOTER_PX;
        let offset = (
            (width - (x1 - x0) * scale) / 2.0 - x0 * scale,
            HEADER_PX + MARGIN_PX + scene.radius * scale - y0 * scale,
        );
        let depths = bounds(scene.bodies.iter().map(|b| view.depth(b.centre)));
        Layout {
            view,
            scale,
            offset,
            size: (width.ceil() as u32, height.ceil() as u32),
            depths,
        }
    }

    fn px(&self, p: [f64; 3]) -> (f64, f64) {
        let (x, y) = self.view.screen(p);
        (
            self.offset.0 + x * self.scale,
            self.offset.1 + y * self.scale,
        )
    }

    fn radius_px(&self, radius: f64) -> f64 {
        (radius * self.scale).max(MIN_RADIUS_PX)
    }

    /// `colour` made paler the farther `p` is.
    fn shade(&self, colour: RGBColor, p: [f64; 3]) -> RGBColor {
        let (near, far) = self.depths;
        let t = if far - near > 1e-9 {
            (self.view.depth(p) - near) / (far - near)
        } else {
            0.0
        };
        pale(colour, t * FADE_FAR)
    }
}

/// `colour` mixed with white (`amount` 0: unchanged, 1: white).
fn pale(colour: RGBColor, amount: f64) -> RGBColor {
    let mix = |c: u8| (f64::from(c) + (255.0 - f64::from(c)) * amount).round() as u8;
    RGBColor(mix(colour.0), mix(colour.1), mix(colour.2))
}

fn ipx(p: (f64, f64)) -> (i32, i32) {
    (p.0.round() as i32, p.1.round() as i32)
}

/// The configuration as an SVG document.
pub fn render_svg(config: &Configuration) -> Result<String, String> {
    let scene = bodies::scene(config);
    let centres: Vec<[f64; 3]> = scene.bodies.iter().map(|b| b.centre).collect();
    let view = choose_view(&centres, 2.6 * scene.radius);
    let layout = Layout::new(&scene, view);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, layout.size).into_drawing_area();
        draw_picture(&root, config, &scene, &layout).map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;
type DrawResult<'a> =
    Result<(), DrawingAreaErrorKind<<SVGBackend<'a> as DrawingBackend>::ErrorType>>;

fn draw_picture<'a>(
    root: &Area<'a>,
    config: &Configuration,
    scene: &Scene,
    layout: &Layout,
) -> DrawResult<'a> {
    root.fill(&WHITE)?;
    draw_in_depth_order(root, scene, layout)?;
    let labelled = scene.bodies.len() <= MAX_LABELLED_BODIES;
    let latches = if labelled { &scene.latches[..] } else { &[] };
    for latch in latches {
        draw_connector_numbers(root, latch, scene.radius, layout)?;
    }
    let r = layout.radius_px(scene.radius);
    let bodies = if labelled { &scene.bodies[..] } else { &[] };
    for body in bodies {
        let (x, y) = layout.px(body.centre);
        // A module too small to hold its name has it beside it.
        let at = if r >= SMALL_BODY_PX {
            (x, y)
        } else {
            (x + r + 4.0 + label_half_width(&body.name, LABEL_PT), y)
        };
        halo_text(root, &body.name, ipx(at), LABEL_PT)?;
    }
    let mut title = format!(
        "{} ({}, {} modules)",
        config.metadata().name,
        config.kind().file_tag(),
        dynarole_world::View::of(config).len()
    );
    if !labelled {
        title.push_str(&format!(
            "; names and connector numbers left out above {MAX_LABELLED_BODIES} bodies"
        ));
    }
    root.draw(&Text::new(title, (12, 12), ("sans-serif", 20).into_font()))?;
    let bottom = i32::try_from(layout.size.1).unwrap_or(i32::MAX);
    draw_gizmo(root, &layout.view, (55, bottom - 50))?;
    draw_legend(root, config, layout, (130, bottom - FOOTER_PX as i32 + 12))
}

/// Something painted in depth order.
enum Item<'s> {
    Body(&'s Body),
    Link(&'s [[f64; 3]; 2]),
    Latch(&'s LatchBar),
}

/// Bodies, links and latch bars, farthest first, so that nearer ones cover farther ones.
fn draw_in_depth_order<'a>(root: &Area<'a>, scene: &Scene, layout: &Layout) -> DrawResult<'a> {
    let middle = |a: [f64; 3], b: [f64; 3]| std::array::from_fn(|k| (a[k] + b[k]) / 2.0);
    let mut items: Vec<(f64, Item)> = Vec::new();
    for body in &scene.bodies {
        items.push((layout.view.depth(body.centre), Item::Body(body)));
    }
    for link in &scene.links {
        items.push((
            layout.view.depth(middle(link[0], link[1])),
            Item::Link(link),
        ));
    }
    for latch in &scene.latches {
        let at = middle(latch.ends[0].0, latch.ends[1].0);
        items.push((layout.view.depth(at), Item::Latch(latch)));
    }
    // Stable: equal depths keep the order above, so the output is the same every time.
    items.sort_by(|a, b| b.0.total_cmp(&a.0));
    for (_, item) in &items {
        match item {
            Item::Body(body) => bodies::draw_body(root, body, scene, layout)?,
            Item::Link(link) => draw_bar(root, layout, **link, scene.radius, LINK, 9)?,
            Item::Latch(latch) => {
                let ends = latch.ends.map(|(p, _)| p);
                draw_bar(root, layout, ends, scene.radius, LATCH, 5)?
            }
        }
    }
    Ok(())
}

/// A bar between two bodies, from rim to rim (its depth is its middle's).
fn draw_bar<'a>(
    root: &Area<'a>,
    layout: &Layout,
    ends: [[f64; 3]; 2],
    radius: f64,
    colour: RGBColor,
    width: u32,
) -> DrawResult<'a> {
    let middle = std::array::from_fn(|k| (ends[0][k] + ends[1][k]) / 2.0);
    let colour = layout.shade(colour, middle);
    let [from, to] = rim_spots(layout, ends, radius);
    root.draw(&PathElement::new(
        vec![ipx(from), ipx(to)],
        colour.stroke_width(width),
    ))
}

/// Pixel points just inside each body's rim, facing the other body.
fn rim_spots(layout: &Layout, ends: [[f64; 3]; 2], radius: f64) -> [(f64, f64); 2] {
    let [a, b] = ends.map(|p| layout.px(p));
    let length = (b.0 - a.0).hypot(b.1 - a.1);
    let (dx, dy) = if length > 1e-9 {
        ((b.0 - a.0) / length, (b.1 - a.1) / length)
    } else {
        (0.0, 0.0)
    };
    let r = layout.radius_px(radius) * 0.8;
    [(a.0 + dx * r, a.1 + dy * r), (b.0 - dx * r, b.1 - dy * r)]
}

/// Each end's connector number in a small white badge on the body's rim, towards the other end.
fn draw_connector_numbers<'a>(
    root: &Area<'a>,
    latch: &LatchBar,
    radius: f64,
    layout: &Layout,
) -> DrawResult<'a> {
    let spots = rim_spots(layout, latch.ends.map(|(p, _)| p), radius);
    // Badges shrink with the modules, down to a size where a digit still reads.
    let badge = (layout.radius_px(radius) * 0.25).clamp(5.0, 8.0);
    for (k, spot) in spots.into_iter().enumerate() {
        let spot = ipx(spot);
        let size = badge.round() as i32;
        root.draw(&Circle::new(spot, size, WHITE.filled()))?;
        root.draw(&Circle::new(spot, size, LATCH.stroke_width(1)))?;
        root.draw(&Text::new(
            latch.ends[k].1.to_string(),
            spot,
            ("sans-serif", badge * 1.6)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Center)),
        ))?;
    }
    Ok(())
}

/// Roughly half the width of `text` in pixels, with a little room.
fn label_half_width(text: &str, size: i32) -> f64 {
    f64::from(i32::try_from(text.chars().count()).unwrap_or(0) * size * 3 / 10 + 3)
}

/// Text centred at `at` on a white patch, readable over any colour.
fn halo_text<'a>(root: &Area<'a>, text: &str, at: (i32, i32), size: i32) -> DrawResult<'a> {
    let half_width = label_half_width(text, size).round() as i32;
    let half_height = size * 6 / 10;
    root.draw(&Rectangle::new(
        [
            (at.0 - half_width, at.1 - half_height),
            (at.0 + half_width, at.1 + half_height),
        ],
        WHITE.mix(0.85).filled(),
    ))?;
    root.draw(&Text::new(
        text.to_string(),
        at,
        ("sans-serif", size)
            .into_font()
            .style(FontStyle::Bold)
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Center)),
    ))
}

/// Arrows for the world axes as the view shows them.
fn draw_gizmo<'a>(root: &Area<'a>, view: &View, origin: (i32, i32)) -> DrawResult<'a> {
    const LENGTH: f64 = 34.0;
    for (k, (colour, name)) in AXES.iter().enumerate() {
        let mut unit = [0.0; 3];
        unit[k] = 1.0;
        let (x, y) = view.screen(unit);
        let tip = (
            f64::from(origin.0) + x * LENGTH,
            f64::from(origin.1) + y * LENGTH,
        );
        root.draw(&PathElement::new(
            vec![origin, ipx(tip)],
            colour.stroke_width(3),
        ))?;
        root.draw(&Circle::new(ipx(tip), 3, colour.filled()))?;
        let label = (tip.0 + x * 10.0, tip.1 + y * 10.0);
        root.draw(&Text::new(
            name.to_string(),
            ipx(label),
            ("sans-serif", 14)
                .into_font()
                .color(colour)
                .pos(Pos::new(HPos::Center, VPos::Center)),
        ))?;
    }
    Ok(())
}

/// What the colours and marks mean, and where the picture is seen from.
fn draw_legend<'a>(
    root: &Area<'a>,
    config: &Configuration,
    layout: &Layout,
    at: (i32, i32),
) -> DrawResult<'a> {
    let parts = bodies::legend_rows(config);
    let mut rows: Vec<(Option<RGBColor>, String)> = (parts.into_iter())
        .map(|(c, words)| (Some(c), words))
        .collect();
    rows.extend([
        (
            Some(LATCH),
            "latch; the small numbers are the latched connectors, each at its module".into(),
        ),
        (
            None,
            format!(
                "seen from azimuth {:.0} deg, elevation {:.0} deg; paler is farther",
                layout.view.azimuth_deg, layout.view.elevation_deg
            ),
        ),
    ]);
    for (k, (swatch, text)) in rows.iter().enumerate() {
        let y = at.1 + 22 * i32::try_from(k).unwrap_or(0);
        if let Some(colour) = swatch {
            root.draw(&Rectangle::new(
                [(at.0, y - 7), (at.0 + 22, y + 7)],
                colour.filled(),
            ))?;
        }
        root.draw(&Text::new(
            text.clone(),
            (at.0 + 32, y),
            ("sans-serif", 14)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
    }
    Ok(())
}
