//! Options for reading and writing, with documented defaults.

use std::fmt;
use std::str::FromStr;
use trigbody_core::{Real, Vec3};

/// Which axis of the file points up. Reading rotates the geometry (a proper
/// rotation, so handedness and triangle winding are kept) so that this axis
/// becomes +y, the convention of the core.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum UpAxis {
    /// Keep the file's axes as they are (the default).
    #[default]
    Keep,
    /// +x is up.
    PlusX,
    /// −x is up.
    MinusX,
    /// +y is up (same as `Keep`).
    PlusY,
    /// −y is up.
    MinusY,
    /// +z is up (most CAD programs, scanners and Blender):
    /// (x, y, z) ↦ (x, z, −y).
    PlusZ,
    /// −z is up.
    MinusZ,
}

impl UpAxis {
    /// Rotates a vector from the file's frame to the +y-up frame.
    #[inline]
    pub fn to_y_up(self, v: Vec3) -> Vec3 {
        let Vec3 { x, y, z } = v;
        match self {
            UpAxis::Keep | UpAxis::PlusY => v,
            UpAxis::MinusY => Vec3::new(x, -y, -z),
            UpAxis::PlusZ => Vec3::new(x, z, -y),
            UpAxis::MinusZ => Vec3::new(x, -z, y),
            UpAxis::PlusX => Vec3::new(-y, x, z),
            UpAxis::MinusX => Vec3::new(y, -x, z),
        }
    }
}

/// The text is not an axis name.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown up axis {0:?}: expected keep, x, y, z, +x, +y, +z, -x, -y or -z")]
pub struct ParseUpAxisError(pub String);

impl FromStr for UpAxis {
    type Err = ParseUpAxisError;
    /// Parses `keep`, `x`, `+x`, `-x` (and the same for y and z), any case.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Ok(match s.trim().to_ascii_lowercase().as_str() {
            "keep" | "" => UpAxis::Keep,
            "x" | "+x" => UpAxis::PlusX,
            "-x" => UpAxis::MinusX,
            "y" | "+y" => UpAxis::PlusY,
            "-y" => UpAxis::MinusY,
            "z" | "+z" => UpAxis::PlusZ,
            "-z" => UpAxis::MinusZ,
            _ => return Err(ParseUpAxisError(s.to_string())),
        })
    }
}

impl fmt::Display for UpAxis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            UpAxis::Keep => "keep",
            UpAxis::PlusX => "+x",
            UpAxis::MinusX => "-x",
            UpAxis::PlusY => "+y",
            UpAxis::MinusY => "-y",
            UpAxis::PlusZ => "+z",
            UpAxis::MinusZ => "-z",
        })
    }
}

/// How to turn a file's coordinates into the core's (meters, +y up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReadOptions {
    /// Every coordinate is multiplied by this on reading, e.g. `0.001` for a
    /// file in millimetres. Default: `1.0` (the file is in meters).
    pub scale: Real,
    /// Which axis of the file is up; it is rotated onto +y.
    /// Default: [`UpAxis::Keep`].
    pub up_axis: UpAxis,
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions {
            scale: 1.0,
            up_axis: UpAxis::Keep,
        }
    }
}

impl ReadOptions {
    /// Applies scale then rotation to positions, rotation to normals.
    pub(crate) fn apply(&self, positions: &mut [Vec3], normals: Option<&mut Vec<Vec3>>) {
        let (s, up) = (self.scale, self.up_axis);
        if s != 1.0 || !matches!(up, UpAxis::Keep | UpAxis::PlusY) {
            for p in positions.iter_mut() {
                *p = up.to_y_up(*p * s);
            }
        }
        if let Some(ns) = normals {
            if !matches!(up, UpAxis::Keep | UpAxis::PlusY) {
                for n in ns.iter_mut() {
                    *n = up.to_y_up(*n);
                }
            }
            // A negative scale mirrors the geometry; normals follow the mirror.
            if s < 0.0 {
                for n in ns.iter_mut() {
                    *n = -*n;
                }
            }
        }
    }
}

/// Numeric type for PLY vertex coordinates and normals on writing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PlyPrecision {
    /// 32-bit `float`: read by every program; about 0.1 µm resolution at
    /// 1 m. The default.
    #[default]
    Float,
    /// 64-bit `double`: exact round trip of the core's f64.
    Double,
}

/// How to write a file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct WriteOptions {
    /// Path writers only: replace an existing file. Default `false`: an
    /// existing file gives [`IoError::AlreadyExists`](crate::IoError::AlreadyExists)
    /// and is left untouched.
    pub overwrite: bool,
    /// Coordinate type of written PLY files. Default [`PlyPrecision::Float`].
    pub ply_precision: PlyPrecision,
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: [UpAxis; 7] = [
        UpAxis::Keep,
        UpAxis::PlusX,
        UpAxis::MinusX,
        UpAxis::PlusY,
        UpAxis::MinusY,
        UpAxis::PlusZ,
        UpAxis::MinusZ,
    ];

    fn axis(a: UpAxis) -> Vec3 {
        match a {
            UpAxis::Keep | UpAxis::PlusY => Vec3::Y,
            UpAxis::MinusY => -Vec3::Y,
            UpAxis::PlusX => Vec3::X,
            UpAxis::MinusX => -Vec3::X,
            UpAxis::PlusZ => Vec3::Z,
            UpAxis::MinusZ => -Vec3::Z,
        }
    }

    #[test]
    fn every_up_axis_becomes_plus_y_by_a_proper_rotation() {
        for a in ALL {
            assert_eq!(a.to_y_up(axis(a)), Vec3::Y, "{a}");
            // Columns of the map: a rotation keeps the cross product (det +1).
            let (x, y, z) = (a.to_y_up(Vec3::X), a.to_y_up(Vec3::Y), a.to_y_up(Vec3::Z));
            assert_eq!(x.cross(y), z, "{a} is not a proper rotation");
            assert_eq!(x.norm() * y.norm() * z.norm(), 1.0);
        }
    }

    #[test]
    fn up_axis_parses_what_it_displays() {
        for a in ALL {
            assert_eq!(a.to_string().parse::<UpAxis>(), Ok(a));
        }
        assert_eq!("Z".parse::<UpAxis>(), Ok(UpAxis::PlusZ));
        assert_eq!(" -y ".parse::<UpAxis>(), Ok(UpAxis::MinusY));
        assert!("up".parse::<UpAxis>().is_err());
    }

    #[test]
    fn options_scale_positions_and_rotate_normals() {
        let o = ReadOptions {
            scale: 0.001,
            up_axis: UpAxis::PlusZ,
        };
        let mut p = vec![Vec3::new(1000.0, 2000.0, 3000.0)];
        let mut n = vec![Vec3::Z];
        o.apply(&mut p, Some(&mut n));
        assert_eq!(p[0], Vec3::new(1.0, 3.0, -2.0));
        assert_eq!(n[0], Vec3::Y);
        assert_eq!(ReadOptions::default().scale, 1.0);
        assert_eq!(ReadOptions::default().up_axis, UpAxis::Keep);
    }
}
