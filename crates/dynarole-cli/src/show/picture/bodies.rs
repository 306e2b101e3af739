//! What a picture of a configuration draws of its modules, from the robot's drawing
//! (`dynarole_world::Drawing::picture`) and the poses of its parts: the bodies (a disc split
//! between two parts' colours, or a cube per part with bars between them), where its latches
//! end and the legend's words. The rest of the picture (`picture.rs`: view, layout, depth
//! order, labels, gizmo) is the same for every robot.

use super::{dot, ipx, pale, Area, Body, DrawResult, LatchBar, Layout, Scene};
use dynarole_world::{Configuration, Drawing, ModulePose, Picture, Port, View};
use plotters::prelude::*;

/// The kind of a body, which says how it is painted.
pub(super) enum BodyKind {
    /// A module as one disc, split across the projection of `axis` between the colours of
    /// parts 0 and 1.
    SplitDisc { axis: [f64; 3] },
    /// One part as a cube in its colour.
    Cube { part: usize },
}

/// Everything drawn of `config`, in world coordinates.
pub(super) fn scene(config: &Configuration) -> Scene {
    let drawing = config.kind().drawing();
    let poses = config.poses();
    let view = View::of(config);
    let (bodies, links, radius) = match drawing.picture {
        Picture::SplitDisc { radius } => (split_discs(&view, &poses), Vec::new(), radius),
        Picture::LinkedCubes { half } => {
            let (bodies, links) = linked_blocks(&view, &poses);
            (bodies, links, half)
        }
    };
    // A latch ends at the body carrying its connector: the module's disc, or the cube of the
    // part (side) the connector is on.
    let end = |p: Port| -> Option<([f64; 3], u8)> {
        let pose = poses.get(p.module)?;
        let at = match drawing.picture {
            Picture::SplitDisc { .. } => pose.centre(),
            Picture::LinkedCubes { .. } => pose.parts.get(view.side(p.connector))?.centre,
        };
        Some((at, p.connector))
    };
    Scene {
        bodies,
        links,
        latches: latch_bars(&view, end),
        radius,
        colours: part_colours(&drawing),
    }
}

/// The colour of each part, by part index.
fn part_colours(drawing: &Drawing) -> Vec<RGBColor> {
    (drawing.parts.iter())
        .map(|p| RGBColor(p.colour[0], p.colour[1], p.colour[2]))
        .collect()
}

/// A disc per module, split across part 1's up axis.
fn split_discs(view: &View, poses: &[ModulePose]) -> Vec<Body> {
    (poses.iter().enumerate())
        .map(|(m, pose)| Body {
            centre: pose.centre(),
            name: view.name(m),
            kind: BodyKind::SplitDisc {
                axis: pose.parts.get(1).map_or([0.0, 1.0, 0.0], |p| p.up),
            },
        })
        .collect()
}

/// A cube per part, and a bar between each part and the next of its module.
fn linked_blocks(view: &View, poses: &[ModulePose]) -> (Vec<Body>, Vec<[[f64; 3]; 2]>) {
    let mut bodies = Vec::new();
    let mut links = Vec::new();
    for (m, pose) in poses.iter().enumerate() {
        for (part, p) in pose.parts.iter().enumerate() {
            bodies.push(Body {
                centre: p.centre,
                name: view.name(m),
                kind: BodyKind::Cube { part },
            });
        }
        links.extend(pose.parts.windows(2).map(|w| [w[0].centre, w[1].centre]));
    }
    (bodies, links)
}

/// A bar for every latch whose two ends `end` can place (a point and the connector number),
/// ordered by the male port.
fn latch_bars(view: &View, end: impl Fn(Port) -> Option<([f64; 3], u8)>) -> Vec<LatchBar> {
    let mut bars = Vec::new();
    for module in 0..view.len() {
        for connector in (0..view.connectors()).filter(|&k| view.is_male(k)) {
            let male = Port { module, connector };
            let Some(female) = view.latched_to(male) else {
                continue;
            };
            if let (Some(a), Some(b)) = (end(male), end(female)) {
                bars.push(LatchBar { ends: [a, b] });
            }
        }
    }
    bars
}

/// The legend's rows for the parts: each part's colour and words.
pub(super) fn legend_rows(config: &Configuration) -> Vec<(RGBColor, String)> {
    let drawing = config.kind().drawing();
    let colours = part_colours(&drawing);
    (colours.into_iter().zip(drawing.parts))
        .map(|(colour, part)| (colour, part.legend))
        .collect()
}

/// Paints `body` in the shape of its kind.
pub(super) fn draw_body<'a>(
    root: &Area<'a>,
    body: &Body,
    scene: &Scene,
    layout: &Layout,
) -> DrawResult<'a> {
    let colour = |part: usize| scene.colours.get(part).copied().unwrap_or(BLACK);
    match body.kind {
        BodyKind::SplitDisc { axis } => {
            let colours = (colour(0), colour(1));
            draw_disc(root, body.centre, axis, colours, scene.radius, layout)
        }
        BodyKind::Cube { part } => draw_cube(root, body.centre, colour(part), scene.radius, layout),
    }
}

/// A module as a disc whose halves are its two parts (`north` the colour of part 0, `south`
/// of part 1, which `axis` points to), split across the projected axis. When the axis points
/// (almost) at the viewer only the facing part shows.
fn draw_disc<'a>(
    root: &Area<'a>,
    centre: [f64; 3],
    axis: [f64; 3],
    (north, south): (RGBColor, RGBColor),
    radius: f64,
    layout: &Layout,
) -> DrawResult<'a> {
    let c = layout.px(centre);
    let r = layout.radius_px(radius);
    let (north, south) = (layout.shade(north, centre), layout.shade(south, centre));
    let (ax, ay) = layout.view.screen(axis);
    let south_faces = dot(axis, layout.view.toward) > 0.0;
    let back = if ax.hypot(ay) < 0.25 && south_faces {
        south
    } else {
        north
    };
    root.draw(&Circle::new(ipx(c), r.round() as i32, back.filled()))?;
    if ax.hypot(ay) >= 0.25 {
        root.draw(&Polygon::new(half_disc(c, r, ay.atan2(ax)), south.filled()))?;
    }
    let outline = layout.shade(BLACK, centre);
    root.draw(&Circle::new(
        ipx(c),
        r.round() as i32,
        outline.stroke_width(1),
    ))
}

/// The half of a disc (centre `c`, radius `r`) on the side of direction `towards` (radians).
fn half_disc(c: (f64, f64), r: f64, towards: f64) -> Vec<(i32, i32)> {
    (0..=36)
        .map(|i| {
            let angle =
                towards - std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * f64::from(i) / 36.0;
            ipx((c.0 + r * angle.cos(), c.1 + r * angle.sin()))
        })
        .collect()
}

/// A part as an axis-aligned cube in `colour`, its visible faces lit from above.
fn draw_cube<'a>(
    root: &Area<'a>,
    centre: [f64; 3],
    colour: RGBColor,
    half: f64,
    layout: &Layout,
) -> DrawResult<'a> {
    let base = layout.shade(colour, centre);
    let outline = layout.shade(BLACK, centre);
    for axis in 0..3 {
        let sign = if layout.view.toward[axis] >= 0.0 {
            1.0
        } else {
            -1.0
        };
        let face = cube_face(centre, half, axis, sign)
            .map(|p| ipx(layout.px(p)))
            .to_vec();
        // The top face is lightest, the two side faces apart by shade.
        let light = [0.15, 0.4, 0.0][axis];
        root.draw(&Polygon::new(face.clone(), pale(base, light).filled()))?;
        let mut closed = face;
        closed.push(closed[0]);
        root.draw(&PathElement::new(closed, outline.stroke_width(1)))?;
    }
    Ok(())
}

/// The four corners of the face of a cube normal to `axis` on the `sign` side.
fn cube_face(centre: [f64; 3], half: f64, axis: usize, sign: f64) -> [[f64; 3]; 4] {
    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
    [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(a, b)| {
        let mut p = centre;
        p[axis] += sign * half;
        p[u] += a * half;
        p[v] += b * half;
        p
    })
}
