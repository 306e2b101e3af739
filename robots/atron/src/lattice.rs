//! The ATRON module model of the ATRON domain notes: orientation constants, connector offsets
//! as a function of orientation and joint angle, connector gender and the lattice phase.

use dynarole_world::geometry::{add, Rotation, Vec3};
use std::fmt;

/// Joint units in one revolution (ATRON hardware units).
pub const JOINT_UNITS_PER_TURN: u16 = 432;
/// Joint units in a quarter turn; the only joint positions are multiples of it.
pub const QUARTER_TURN_UNITS: u16 = 108;
/// Number of connectors of a module: 0-3 on the north hemisphere, 4-7 on the south one.
pub const CONNECTOR_COUNT: u8 = 8;
/// Metres per lattice unit (`ATRON.UNIT`).
pub const LATTICE_UNIT_M: f64 = 0.08;
/// Smallest centre-to-centre distance, in lattice units, that a module on the turning side may
/// come to a module that stays still during a joint turn. Every sequence of the original
/// simulator passes it (closest: 1.236 in eight2car, atron.md a.7); a solid-sphere test at the
/// quoted 110 mm diameter (1.375 units) would wrongly reject Fig. 5.
pub const MIN_SWEEP_DISTANCE_LATTICE: f64 = 1.2;

/// The six named base orientations of USSR, one per direction of the north->south axis.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub enum OrientationBase {
    /// Axis +z (north at -z).
    Ns,
    /// Axis -z.
    Sn,
    /// Axis +x (north at -x, "east").
    Ew,
    /// Axis -x.
    We,
    /// Axis -y (north up).
    Ud,
    /// Axis +y (north down).
    Du,
}

impl OrientationBase {
    /// The six bases in the order used in messages.
    pub const ALL: [OrientationBase; 6] = [
        OrientationBase::Ns,
        OrientationBase::Sn,
        OrientationBase::Ew,
        OrientationBase::We,
        OrientationBase::Ud,
        OrientationBase::Du,
    ];

    /// The USSR constant's name (`NS`, `SN`, ...).
    pub fn name(self) -> &'static str {
        match self {
            OrientationBase::Ns => "NS",
            OrientationBase::Sn => "SN",
            OrientationBase::Ew => "EW",
            OrientationBase::We => "WE",
            OrientationBase::Ud => "UD",
            OrientationBase::Du => "DU",
        }
    }

    /// Parses a base name (exact spelling).
    pub fn from_name(name: &str) -> Option<OrientationBase> {
        OrientationBase::ALL.into_iter().find(|b| b.name() == name)
    }

    /// The lattice frame of the constant: the USSR rotation R(BASE) followed by the 45 degree
    /// twist Rz(45) that turns the connector directions into lattice offsets
    /// (`R(BASE) = frame * Rz(-45)`). Columns are the world images of local x, y, z; the table
    /// of atron.md a.3 is reproduced by `frame * u_i` (checked by a test, which also rebuilds
    /// each frame from the Euler angles).
    pub fn frame(self) -> Rotation {
        let rows = match self {
            OrientationBase::Ns => [[-1, 0, 0], [0, -1, 0], [0, 0, 1]],
            OrientationBase::Sn => [[1, 0, 0], [0, -1, 0], [0, 0, -1]],
            OrientationBase::Ew => [[0, 0, 1], [1, 0, 0], [0, 1, 0]],
            OrientationBase::We => [[0, 0, -1], [1, 0, 0], [0, -1, 0]],
            OrientationBase::Du => [[0, -1, 0], [0, 0, 1], [-1, 0, 0]],
            OrientationBase::Ud => [[0, 1, 0], [0, 0, -1], [-1, 0, 0]],
        };
        Rotation::from_rows_unchecked(rows)
    }

    /// The base whose north->south axis is `axis`.
    fn for_axis(axis: Vec3) -> Option<OrientationBase> {
        OrientationBase::ALL
            .into_iter()
            .find(|b| b.frame().column(2) == axis)
    }
}

/// The frame of a module's south hemisphere, as one of the 24 lattice rotations (every one of
/// them is some `BASE@k`). Stored with the 45 degree twist removed, so it is an exact integer
/// matrix; see [`OrientationBase::frame`].
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub struct Orientation {
    frame: Rotation,
}

/// The message for an orientation name that cannot be parsed.
fn unknown_orientation(name: &str) -> String {
    format!(
        "unknown orientation \"{name}\"; expected one of NS, SN, EW, WE, UD, DU, NS_BROKEN or BASE@k"
    )
}

impl Orientation {
    /// The orientation with this lattice frame (any of the 24 rotations).
    pub fn from_frame(frame: Rotation) -> Orientation {
        Orientation { frame }
    }

    /// `BASE@spin`: the base turned by `spin` quarter turns about its own axis (spin mod 4).
    pub fn from_base_spin(base: OrientationBase, spin: u8) -> Orientation {
        let twist = Rotation::about_axis([0, 0, 1], i32::from(spin % 4));
        let frame = match twist {
            Some(t) => base.frame().compose(&t),
            // Unreachable: +z is a unit axis. Fall back to the base rather than panic.
            None => base.frame(),
        };
        Orientation { frame }
    }

    /// Parses `NS`, `SN`, `EW`, `WE`, `UD`, `DU`, `NS_BROKEN` or `BASE@k` (k in 0..=3).
    pub fn parse(name: &str) -> Result<Orientation, String> {
        if name == "NS_BROKEN" {
            return Ok(Orientation::from_base_spin(OrientationBase::Ns, 2));
        }
        let (base_name, spin) = match name.split_once('@') {
            None => (name, 0),
            Some((base_name, spin_text)) => match spin_text {
                "0" | "1" | "2" | "3" => (base_name, spin_text.parse().unwrap_or(0)),
                _ => {
                    return Err(format!(
                        "orientation \"{name}\": the spin after @ must be 0, 1, 2 or 3"
                    ))
                }
            },
        };
        match OrientationBase::from_name(base_name) {
            Some(base) => Ok(Orientation::from_base_spin(base, spin)),
            None => Err(unknown_orientation(name)),
        }
    }

    /// The canonical name: the USSR constant when there is one (`NS_BROKEN` for `NS@2`),
    /// otherwise `BASE@k`.
    pub fn name(&self) -> String {
        match (self.base(), self.spin()) {
            (base, 0) => base.name().to_string(),
            (OrientationBase::Ns, 2) => "NS_BROKEN".to_string(),
            (base, spin) => format!("{}@{spin}", base.name()),
        }
    }

    /// The base constant with the same axis.
    pub fn base(&self) -> OrientationBase {
        // Every frame's axis is one of the six bases' axes.
        OrientationBase::for_axis(self.axis()).unwrap_or(OrientationBase::Ns)
    }

    /// Quarter turns about the axis relative to the base (0..=3).
    pub fn spin(&self) -> u8 {
        let base = self.base();
        (0..4u8)
            .find(|k| Orientation::from_base_spin(base, *k).frame == self.frame)
            .unwrap_or(0)
    }

    /// World direction from the north hemisphere to the south hemisphere.
    pub fn axis(&self) -> Vec3 {
        self.frame.column(2)
    }

    /// The lattice frame (see the type's documentation).
    pub fn frame(&self) -> Rotation {
        self.frame
    }

    /// The orientation after the whole module is turned by `rotation`.
    pub fn rotated(&self, rotation: &Rotation) -> Orientation {
        Orientation {
            frame: rotation.compose(&self.frame),
        }
    }

    /// World lattice offset of the neighbour site connector `connector` faces at joint
    /// `joint_units` (atron.md a.4): south connectors `F u_i`, north connectors
    /// `F Rz(-90 deg * joint/108) u_i`, i.e. north connector i takes the direction of north
    /// connector `i - joint/108` at joint 0. `None` for a connector outside 0..=7.
    pub fn connector_offset(&self, joint_units: u16, connector: u8) -> Option<Vec3> {
        if connector >= CONNECTOR_COUNT {
            return None;
        }
        let quarters = i32::from(joint_units / QUARTER_TURN_UNITS);
        let k = i32::from(connector % 4);
        let (azimuth, pole) = if connector < 4 {
            ((k - quarters).rem_euclid(4), -1)
        } else {
            (k, 1)
        };
        let local = match azimuth {
            0 => [1, 0, pole],
            1 => [0, 1, pole],
            2 => [-1, 0, pole],
            _ => [0, -1, pole],
        };
        Some(self.frame.apply(local))
    }
}

impl fmt::Display for Orientation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}

/// True for male connectors (even numbers); only a male connector extends or retracts.
pub fn is_male(connector: u8) -> bool {
    connector % 2 == 0
}

/// True for connectors 0-3, which sit on the north hemisphere.
pub fn is_north(connector: u8) -> bool {
    connector < 4
}

/// True for the four legal joint positions 0, 108, 216, 324.
pub fn is_joint_position(joint_units: u16) -> bool {
    joint_units < JOINT_UNITS_PER_TURN && joint_units % QUARTER_TURN_UNITS == 0
}

/// The lattice phase of a structure (atron.md a.1): site p is legal iff `p + c` has exactly one
/// odd coordinate, and the module there has its axis along that coordinate. Stored as the index
/// (0 = x, 1 = y, 2 = z) of the unit vector c.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct LatticePhase {
    coordinate: usize,
}

impl LatticePhase {
    /// The phase vector c.
    pub fn vector(&self) -> Vec3 {
        let mut c = [0; 3];
        c[self.coordinate] = 1;
        c
    }

    /// The only phase under which a module at `position` with axis `axis` is legal, if any.
    pub fn for_module(position: Vec3, axis: Vec3) -> Option<LatticePhase> {
        let axis_coordinate = axis.iter().position(|c| *c != 0)?;
        // c = parity(p) + e_axis (mod 2) must be a unit vector.
        let mut c = position.map(|x| x.rem_euclid(2));
        c[axis_coordinate] = (c[axis_coordinate] + 1) % 2;
        let coordinate = c.iter().position(|x| *x == 1)?;
        (c.iter().sum::<i32>() == 1).then_some(LatticePhase { coordinate })
    }

    /// The axis coordinate a module at `position` must have, or `None` for a hole.
    pub fn axis_coordinate_at(&self, position: Vec3) -> Option<usize> {
        let shifted = add(position, self.vector());
        let odd: Vec<usize> = (0..3).filter(|i| shifted[*i].rem_euclid(2) == 1).collect();
        match odd.as_slice() {
            [only] => Some(*only),
            _ => None,
        }
    }

    /// True when a module with `axis` may sit at `position`.
    pub fn allows(&self, position: Vec3, axis: Vec3) -> bool {
        let axis_coordinate = axis.iter().position(|c| *c != 0);
        axis_coordinate.is_some() && self.axis_coordinate_at(position) == axis_coordinate
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table of atron.md a.3, connectors 0..7 at joint 0.
    const TABLE: [(&str, [Vec3; 8]); 7] = [
        (
            "NS",
            [
                [-1, 0, -1],
                [0, -1, -1],
                [1, 0, -1],
                [0, 1, -1],
                [-1, 0, 1],
                [0, -1, 1],
                [1, 0, 1],
                [0, 1, 1],
            ],
        ),
        (
            "NS_BROKEN",
            [
                [1, 0, -1],
                [0, 1, -1],
                [-1, 0, -1],
                [0, -1, -1],
                [1, 0, 1],
                [0, 1, 1],
                [-1, 0, 1],
                [0, -1, 1],
            ],
        ),
        (
            "SN",
            [
                [1, 0, 1],
                [0, -1, 1],
                [-1, 0, 1],
                [0, 1, 1],
                [1, 0, -1],
                [0, -1, -1],
                [-1, 0, -1],
                [0, 1, -1],
            ],
        ),
        (
            "EW",
            [
                [-1, 1, 0],
                [-1, 0, 1],
                [-1, -1, 0],
                [-1, 0, -1],
                [1, 1, 0],
                [1, 0, 1],
                [1, -1, 0],
                [1, 0, -1],
            ],
        ),
        (
            "WE",
            [
                [1, 1, 0],
                [1, 0, -1],
                [1, -1, 0],
                [1, 0, 1],
                [-1, 1, 0],
                [-1, 0, -1],
                [-1, -1, 0],
                [-1, 0, 1],
            ],
        ),
        (
            "DU",
            [
                [0, -1, -1],
                [-1, -1, 0],
                [0, -1, 1],
                [1, -1, 0],
                [0, 1, -1],
                [-1, 1, 0],
                [0, 1, 1],
                [1, 1, 0],
            ],
        ),
        (
            "UD",
            [
                [0, 1, -1],
                [1, 1, 0],
                [0, 1, 1],
                [-1, 1, 0],
                [0, -1, -1],
                [1, -1, 0],
                [0, -1, 1],
                [-1, -1, 0],
            ],
        ),
    ];

    #[test]
    fn constant_frames_are_rotations() {
        for base in OrientationBase::ALL {
            let f = base.frame();
            let rebuilt = Rotation::from_columns(f.column(0), f.column(1), f.column(2));
            assert_eq!(rebuilt, Some(f), "{base:?}");
        }
    }

    #[test]
    fn connector_offsets_reproduce_the_table() -> Result<(), String> {
        for (name, offsets) in TABLE {
            let o = Orientation::parse(name)?;
            for (i, expected) in offsets.iter().enumerate() {
                let i = u8::try_from(i).map_err(|e| e.to_string())?;
                assert_eq!(o.connector_offset(0, i), Some(*expected), "{name} {i}");
            }
        }
        Ok(())
    }

    /// USSR builds rotations with jME 2.0 `fromAngles(ax, ay, az) = Ry(ay) Rz(az) Rx(ax)`;
    /// check that each lattice frame is that rotation followed by Rz(45 deg).
    #[test]
    fn frames_match_the_euler_angles() {
        use std::f64::consts::{FRAC_PI_2 as Q, FRAC_PI_4 as E, PI as H};
        type M = [[f64; 3]; 3];
        fn mul(a: M, b: M) -> M {
            let mut out = [[0.0; 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    out[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
                }
            }
            out
        }
        fn rx(t: f64) -> M {
            [
                [1.0, 0.0, 0.0],
                [0.0, t.cos(), -t.sin()],
                [0.0, t.sin(), t.cos()],
            ]
        }
        fn ry(t: f64) -> M {
            [
                [t.cos(), 0.0, t.sin()],
                [0.0, 1.0, 0.0],
                [-t.sin(), 0.0, t.cos()],
            ]
        }
        fn rz(t: f64) -> M {
            [
                [t.cos(), -t.sin(), 0.0],
                [t.sin(), t.cos(), 0.0],
                [0.0, 0.0, 1.0],
            ]
        }
        fn euler(ax: f64, ay: f64, az: f64) -> M {
            mul(ry(ay), mul(rz(az), rx(ax)))
        }
        let cases = [
            (OrientationBase::Ns, euler(0.0, 0.0, E + Q)),
            (OrientationBase::Sn, euler(0.0, H, E + Q)),
            (
                OrientationBase::Ew,
                mul(euler(E, 0.0, 0.0), euler(0.0, Q, 0.0)),
            ),
            (
                OrientationBase::We,
                mul(euler(-E, 0.0, 0.0), euler(0.0, -Q, 0.0)),
            ),
            (OrientationBase::Du, euler(-Q, E, 0.0)),
            (OrientationBase::Ud, euler(Q, E + Q, 0.0)),
        ];
        for (base, r) in cases {
            let lattice = mul(r, rz(E));
            let exact = base.frame().rows();
            for i in 0..3 {
                for j in 0..3 {
                    let diff = (lattice[i][j] - f64::from(exact[i][j])).abs();
                    assert!(diff < 1e-9, "{base:?} [{i}][{j}]");
                }
            }
        }
    }

    #[test]
    fn names_round_trip_for_all_24_frames() -> Result<(), String> {
        for frame in Rotation::all() {
            let o = Orientation::from_frame(frame);
            assert_eq!(Orientation::parse(&o.name())?, o);
        }
        assert_eq!(Orientation::parse("NS@2")?.name(), "NS_BROKEN");
        assert!(Orientation::parse("NX").is_err());
        assert!(Orientation::parse("NS@4").is_err());
        Ok(())
    }

    #[test]
    fn spin_moves_connector_i_to_where_i_plus_k_was() -> Result<(), String> {
        for base in OrientationBase::ALL {
            let plain = Orientation::from_base_spin(base, 0);
            for k in 0..4u8 {
                let spun = Orientation::from_base_spin(base, k);
                for i in 0..8u8 {
                    let same_hemisphere = (i / 4) * 4 + (i + k) % 4;
                    assert_eq!(
                        spun.connector_offset(0, i),
                        plain.connector_offset(0, same_hemisphere)
                    );
                }
            }
        }
        Ok(())
    }

    #[test]
    fn north_connector_i_at_joint_p_faces_where_i_minus_p_faced() -> Result<(), String> {
        let o = Orientation::parse("EW")?;
        for q in 0..4u16 {
            for i in 0..8u8 {
                let expected = if i < 4 {
                    let j = (i32::from(i) - i32::from(q)).rem_euclid(4);
                    o.connector_offset(0, u8::try_from(j).map_err(|e| e.to_string())?)
                } else {
                    o.connector_offset(0, i)
                };
                assert_eq!(o.connector_offset(q * 108, i), expected);
            }
        }
        Ok(())
    }

    #[test]
    fn phase_of_the_eight_is_z() {
        let phase = LatticePhase::for_module([0, 0, 0], [0, 0, 1]);
        assert_eq!(phase.map(|p| p.vector()), Some([0, 0, 1]));
        let phase = phase.map(|p| p.allows([1, 0, 1], [1, 0, 0]));
        assert_eq!(phase, Some(true));
        assert_eq!(LatticePhase::for_module([1, 1, 1], [1, 0, 0]), None);
    }
}
