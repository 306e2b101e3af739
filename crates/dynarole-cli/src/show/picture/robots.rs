//! What a picture of a configuration draws differently for each robot: the bodies of its
//! modules (an ATRON module is a sphere of two hemispheres, an M-TRAN module two cubic blocks
//! and their link), where its latches end, the shapes painted and the legend's words. The
//! rest of the picture (`picture.rs`: view, layout, depth order, labels, gizmo) is the same
//! for every robot.

use super::{dot, ipx, pale, Area, Body, DrawResult, LatchBar, Layout, Scene, NORTH, SOUTH};
use dynarole_world::{AtronConfiguration, Configuration, Latch, MtranConfiguration, Port};
use plotters::prelude::*;
use std::collections::BTreeSet;

/// Drawn radius of an ATRON module, in lattice units (smaller than the real 0.69 so that
/// neighbours seen at a slant stay apart).
const ATRON_RADIUS: f64 = 0.36;

/// Drawn half-size of an M-TRAN block, in block pitches.
const MTRAN_HALF_BLOCK: f64 = 0.36;

/// The kind of a body, which says how it is painted.
pub(super) enum BodyKind {
    /// An ATRON module and its north->south axis.
    Sphere { axis: [f64; 3] },
    /// An M-TRAN block, north (male connectors) or south.
    Cube { north: bool },
}

/// Everything drawn of `config`, in world coordinates.
pub(super) fn scene(config: &Configuration) -> Scene {
    match config {
        Configuration::Atron(c) => atron_scene(c),
        Configuration::Mtran(c) => mtran_scene(c),
    }
}

/// The legend's words for the north and the south colour.
pub(super) fn legend_words(config: &Configuration) -> (&'static str, &'static str) {
    match config {
        Configuration::Atron(_) => (
            "north hemisphere (connectors 0-3)",
            "south hemisphere (connectors 4-7)",
        ),
        Configuration::Mtran(_) => (
            "north block (male connectors 0-2)",
            "south block (female connectors 3-5); grey bar: the module's link",
        ),
    }
}

/// An ATRON module is one body, a sphere.
fn atron_scene(config: &AtronConfiguration) -> Scene {
    let bodies = config
        .modules()
        .iter()
        .map(|m| Body {
            centre: m.position.map(f64::from),
            name: m.name.clone(),
            kind: BodyKind::Sphere {
                axis: m.orientation.axis().map(f64::from),
            },
        })
        .collect();
    let end = |p: Port| {
        config
            .module(p.module)
            .map(|m| (m.position.map(f64::from), p.connector))
    };
    let latches = latch_bars(config.latches(), end);
    Scene {
        bodies,
        links: Vec::new(),
        latches,
        radius: ATRON_RADIUS,
    }
}

/// A bar for every latch whose two ends `end` can place (a point and the connector number).
fn latch_bars(
    latches: &BTreeSet<Latch>,
    end: impl Fn(Port) -> Option<([f64; 3], u8)>,
) -> Vec<LatchBar> {
    latches
        .iter()
        .filter_map(|l| {
            Some(LatchBar {
                ends: [end(l.male)?, end(l.female)?],
            })
        })
        .collect()
}

/// Centres of an M-TRAN module's blocks (north, south) in block pitches.
fn block_centres(config: &MtranConfiguration, module: usize) -> Option<[[f64; 3]; 2]> {
    let pitch = |v: i32| f64::from(v) / 2.0;
    config.modules().get(module).map(|m| {
        [
            m.north_block().centre_quarter_pitch.map(pitch),
            m.south_block().centre_quarter_pitch.map(pitch),
        ]
    })
}

/// An M-TRAN module is two bodies, its blocks, and the link between them.
fn mtran_scene(config: &MtranConfiguration) -> Scene {
    let mut bodies = Vec::new();
    let mut links = Vec::new();
    for (i, m) in config.modules().iter().enumerate() {
        let Some([north, south]) = block_centres(config, i) else {
            continue;
        };
        for (centre, north) in [(north, true), (south, false)] {
            bodies.push(Body {
                centre,
                name: m.name.clone(),
                kind: BodyKind::Cube { north },
            });
        }
        links.push([north, south]);
    }
    let end = |p: Port| {
        block_centres(config, p.module)
            .map(|[n, s]| (if p.connector < 3 { n } else { s }, p.connector))
    };
    let latches = latch_bars(config.latches(), end);
    Scene {
        bodies,
        links,
        latches,
        radius: MTRAN_HALF_BLOCK,
    }
}

/// Modules, for the title (an M-TRAN module is two bodies).
pub(super) fn module_count(config: &Configuration) -> usize {
    match config {
        Configuration::Atron(c) => c.modules().len(),
        Configuration::Mtran(c) => c.modules().len(),
    }
}

/// Paints `body` in the shape of its kind.
pub(super) fn draw_body<'a>(
    root: &Area<'a>,
    body: &Body,
    radius: f64,
    layout: &Layout,
) -> DrawResult<'a> {
    match body.kind {
        BodyKind::Sphere { axis } => draw_sphere(root, body.centre, axis, radius, layout),
        BodyKind::Cube { north } => draw_cube(root, body.centre, north, radius, layout),
    }
}

/// An ATRON module: a disc whose halves are its hemispheres, split across the projected axis.
/// When the axis points (almost) at the viewer only the facing hemisphere shows.
fn draw_sphere<'a>(
    root: &Area<'a>,
    centre: [f64; 3],
    axis: [f64; 3],
    radius: f64,
    layout: &Layout,
) -> DrawResult<'a> {
    let c = layout.px(centre);
    let r = layout.radius_px(radius);
    let (north, south) = (layout.shade(NORTH, centre), layout.shade(SOUTH, centre));
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

/// An M-TRAN block: an axis-aligned cube, its visible faces lit from above.
fn draw_cube<'a>(
    root: &Area<'a>,
    centre: [f64; 3],
    north: bool,
    half: f64,
    layout: &Layout,
) -> DrawResult<'a> {
    let base = layout.shade(if north { NORTH } else { SOUTH }, centre);
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
