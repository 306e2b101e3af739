//! One joint turn as a rigid motion of part of the robot, and the connector a free one mates
//! with: what the robot model needs to move, draw and connect. The shoe of the pinned module
//! (shoe A of the lowest ID, the spanning tree's root) never moves: a turn moves the side of
//! its joint away from it, about the joint's axis.
//!
//! Why the axes are these: from shoe A, shoe B is A·Rx(α)·Rz(γ)·T(0,0,1)·Ry(π)·Rx(−β)
//! (`tree.rs`). Turning α by δ turns all beyond shoe A by δ about A's X axis through A's centre;
//! γ by δ about the Z axis of A·Rx(α) (the line through both shoe centres); β by −δ about
//! shoe B's X axis through B's centre (β enters as Rx(−β)). From shoe B the roles of α and β
//! swap. A unit test checks each against the kinematics after the turn.

use crate::module::{Connection, Connector, Joint, Orientation, RofiConfiguration, Side};
use crate::tree::{across_connection, Shoe, Tree, LOOP_TOLERANCE};
use nalgebra::{Matrix4, Point3, Vector3};

/// Where a turn moves what it moves.
#[derive(Clone, Debug, PartialEq)]
pub struct TurnMotion {
    /// A point of the joint's axis (a shoe's centre).
    pub pivot: Point3<f64>,
    /// The axis, a unit vector.
    pub axis: Vector3<f64>,
    /// Degrees the moving side turns about `axis` (right-handed), for a turn of the joint by
    /// `by` degrees.
    pub angle_deg: f64,
    /// The shoes that move, in shoe order; the turning module's own moving shoe among them.
    pub moving: Vec<Shoe>,
    /// A connection between the moving side and the rest (a loop the turn would open).
    pub opens: Option<Connection>,
}

/// The motion of `joint` of module `id` turning by `by` degrees in `config` (connected, its
/// loops closed); `None` for an unknown module or a configuration that is not connected.
pub fn turn_motion(
    config: &RofiConfiguration,
    id: u32,
    joint: Joint,
    by: f64,
) -> Option<TurnMotion> {
    let tree = Tree::of(config).ok()?;
    let (a, b) = (
        tree.shoe_index((id, Side::A))?,
        tree.shoe_index((id, Side::B))?,
    );
    // The module's own link is a tree edge: the shoe whose parent is the other one moves.
    let (fixed, child) = if tree.parent[b] == Some(a) {
        (a, b)
    } else {
        (b, a)
    };
    let poses = tree.poses(&tree.modules);
    let module = tree.modules[a / 2];
    let fixed_side = if fixed == a { Side::A } else { Side::B };
    let (pose, sign, about) = axis_of(joint, fixed_side, &module, (&poses[a], &poses[b]));
    let moving: Vec<Shoe> = (0..poses.len())
        .filter(|&s| tree.within(s, child))
        .map(|s| tree.shoe_of(s))
        .collect();
    let opens = tree.loops().iter().copied().find(|c| {
        let end = |(m, k): (u32, Connector)| tree.shoe_index((m, k.side()));
        match (end(c.from), end(c.to)) {
            (Some(x), Some(y)) => tree.within(x, child) != tree.within(y, child),
            _ => false,
        }
    });
    let rotation = pose.fixed_view::<3, 3>(0, 0);
    Some(TurnMotion {
        pivot: crate::kinematics::centre_of(pose),
        axis: (rotation * about).normalize(),
        angle_deg: sign * by,
        moving,
        opens,
    })
}

/// The pose whose frame holds the axis, the sign of the moving side's turn and the axis in
/// that frame, for `joint` with the module's `fixed` shoe still; `poses` are (shoe A, shoe B).
fn axis_of<'p>(
    joint: Joint,
    fixed: Side,
    module: &crate::module::Module,
    (a, b): (&'p Matrix4<f64>, &'p Matrix4<f64>),
) -> (&'p Matrix4<f64>, f64, Vector3<f64>) {
    let near_x = |angle: f64| {
        let (s, c) = angle.to_radians().sin_cos();
        // Rx(angle)·z: the long axis after the shoe joint's turn.
        Vector3::new(0.0, -s, c)
    };
    match (joint, fixed) {
        (Joint::Alpha, Side::A) => (a, 1.0, Vector3::x()),
        (Joint::Beta, Side::A) => (b, -1.0, Vector3::x()),
        (Joint::Gamma, Side::A) => (a, 1.0, near_x(module.alpha)),
        (Joint::Beta, Side::B) => (b, 1.0, Vector3::x()),
        (Joint::Alpha, Side::B) => (a, -1.0, Vector3::x()),
        (Joint::Gamma, Side::B) => (b, 1.0, near_x(module.beta)),
    }
}

/// The connection a free connector `port` would make: the free connector of another module
/// whose shoe mates with it (one unit along its face, faces opposed, within RoFI's loop
/// tolerance) and the twist between them. `None` when no free connector mates.
pub fn mate_of(config: &RofiConfiguration, port: (u32, Connector)) -> Option<Connection> {
    let tree = Tree::of(config).ok()?;
    let poses = tree.poses(&tree.modules);
    let here = poses[tree.shoe_index((port.0, port.1.side()))?];
    for other in config.modules().filter(|m| m.id != port.0) {
        for index in 0..Connector::COUNT {
            let Some(connector) = Connector::from_index(index) else {
                continue;
            };
            let there = (other.id, connector);
            if config.connection_at(there).is_some() {
                continue;
            }
            let Some(shoe) = tree.shoe_index((other.id, connector.side())) else {
                continue;
            };
            for orientation in Orientation::ALL {
                let step =
                    across_connection(port.1.dock(), orientation.quarter_turns(), connector.dock());
                if (here * step - poses[shoe]).abs().max() <= LOOP_TOLERANCE {
                    return Some(Connection {
                        from: port,
                        orientation,
                        to: there,
                    });
                }
            }
        }
    }
    None
}

/// Where connector `connector`'s face is on a shoe at `pose`: half a unit out of the shoe's
/// centre along the face's outward normal.
pub fn face_centre(pose: &Matrix4<f64>, connector: Connector) -> Point3<f64> {
    let out =
        crate::tree::face_to_dock(connector.dock()) * nalgebra::Vector4::new(0.0, 0.0, -0.5, 1.0);
    let world = pose * out;
    Point3::new(world[0], world[1], world[2])
}
