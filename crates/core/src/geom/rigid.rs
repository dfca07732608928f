//! Rigid motions (a rotation then a translation) of points, directions,
//! meshes and clouds: how a body is brought into its own frame and its
//! model taken back.

use crate::geom::math::{Point3, Vec3};
use crate::geom::mesh::{Mesh, PointCloud};
use crate::geom::tolerance::DIRECTION_EPS;

/// `p ↦ R p + t` with `R` a proper rotation, stored by its rows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rigid {
    rows: [Vec3; 3],
    shift: Vec3,
}

impl Rigid {
    /// The motion that changes nothing.
    pub const IDENTITY: Rigid = Rigid {
        rows: [Vec3::X, Vec3::Y, Vec3::Z],
        shift: Vec3::ZERO,
    };

    /// The motion taking `origin` to zero and the axes `x`, `y` (made
    /// orthonormal: `y` kept, `x` made square to it) and `x × y` to the
    /// coordinate axes. `None` when an axis is zero, non-finite or the two
    /// are parallel.
    pub fn into_axes(origin: Point3, x: Vec3, y: Vec3) -> Option<Rigid> {
        if !origin.is_finite() {
            return None;
        }
        let y = y.normalized()?;
        let x = x - y * x.dot(y);
        if !(x.norm() > DIRECTION_EPS) {
            return None;
        }
        let x = x.normalized()?;
        let rows = [x, y, x.cross(y)];
        let mut m = Rigid {
            rows,
            shift: Vec3::ZERO,
        };
        m.shift = -m.vector(origin);
        Some(m)
    }

    /// The turn by `angle` radians about the line through `centre` along
    /// `axis` (right-handed); `None` when the axis is zero or non-finite.
    pub fn turn_about(centre: Point3, axis: Vec3, angle: f64) -> Option<Rigid> {
        let a = axis.normalized()?;
        if !(centre.is_finite() && angle.is_finite()) {
            return None;
        }
        let (s, c) = angle.sin_cos();
        let k = 1.0 - c;
        let rows = [
            Vec3::new(
                c + k * a.x * a.x,
                k * a.x * a.y - s * a.z,
                k * a.x * a.z + s * a.y,
            ),
            Vec3::new(
                k * a.y * a.x + s * a.z,
                c + k * a.y * a.y,
                k * a.y * a.z - s * a.x,
            ),
            Vec3::new(
                k * a.z * a.x - s * a.y,
                k * a.z * a.y + s * a.x,
                c + k * a.z * a.z,
            ),
        ];
        let mut m = Rigid {
            rows,
            shift: Vec3::ZERO,
        };
        m.shift = centre - m.vector(centre);
        Some(m)
    }

    /// The image of a point.
    #[inline]
    pub fn point(&self, p: Point3) -> Point3 {
        self.vector(p) + self.shift
    }

    /// The image of a direction (rotated, not moved).
    #[inline]
    pub fn vector(&self, v: Vec3) -> Vec3 {
        Vec3::new(
            self.rows[0].dot(v),
            self.rows[1].dot(v),
            self.rows[2].dot(v),
        )
    }

    /// The `i`-th row of the rotation: the direction that becomes axis `i`.
    #[inline]
    pub fn row(&self, i: usize) -> Vec3 {
        self.rows[i]
    }

    /// The motion undoing this one.
    pub fn inverse(&self) -> Rigid {
        let [a, b, c] = self.rows;
        let rows = [
            Vec3::new(a.x, b.x, c.x),
            Vec3::new(a.y, b.y, c.y),
            Vec3::new(a.z, b.z, c.z),
        ];
        let mut m = Rigid {
            rows,
            shift: Vec3::ZERO,
        };
        m.shift = -m.vector(self.shift);
        m
    }

    /// A mesh moved (triangles and their order unchanged).
    pub fn mesh(&self, m: &Mesh) -> Mesh {
        Mesh {
            positions: m.positions.iter().map(|&p| self.point(p)).collect(),
            normals: m
                .normals
                .as_ref()
                .map(|n| n.iter().map(|&v| self.vector(v)).collect()),
            triangles: m.triangles.clone(),
        }
    }

    /// A cloud moved (point order unchanged).
    pub fn cloud(&self, c: &PointCloud) -> PointCloud {
        PointCloud {
            positions: c.positions.iter().map(|&p| self.point(p)).collect(),
            normals: c
                .normals
                .as_ref()
                .map(|n| n.iter().map(|&v| self.vector(v)).collect()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_turn_about_a_line_keeps_the_line_and_turns_the_rest() {
        let c = Point3::new(1.0, 2.0, 3.0);
        let t =
            Rigid::turn_about(c, Vec3::new(0.0, 0.0, 2.0), std::f64::consts::FRAC_PI_2).unwrap();
        let on = c + Vec3::Z * 5.0;
        assert!(t.point(on).distance(on) < 1e-12);
        // +x from the centre goes to +y (right-handed about +z).
        let p = t.point(c + Vec3::X);
        assert!(p.distance(c + Vec3::Y) < 1e-12, "{p:?}");
        let back = t.inverse().point(p);
        assert!(back.distance(c + Vec3::X) < 1e-12);
        assert!(Rigid::turn_about(c, Vec3::ZERO, 1.0).is_none());
    }

    fn near(a: Vec3, b: Vec3) -> bool {
        (a - b).norm() < 1e-12
    }

    #[test]
    fn into_axes_takes_the_axes_to_the_coordinate_axes() {
        let (x, y) = (Vec3::new(0.0, 0.0, 2.0), Vec3::new(0.0, 3.0, 0.1));
        let o = Vec3::new(1.0, 2.0, 3.0);
        let m = Rigid::into_axes(o, x, y).unwrap();
        assert!(near(m.point(o), Vec3::ZERO));
        assert!(near(m.vector(y.normalized().unwrap()), Vec3::Y));
        // x is made square to y; x × y becomes z: a proper rotation.
        assert!(m.vector(x).x > 0.0 && m.vector(x).y.abs() < 0.1);
        let z = m.row(0).cross(m.row(1));
        assert!(near(m.vector(z), Vec3::Z));
        assert!(Rigid::into_axes(o, y, y).is_none());
        assert!(Rigid::into_axes(o, Vec3::ZERO, y).is_none());
    }

    #[test]
    fn the_inverse_undoes_the_motion() {
        let m = Rigid::into_axes(
            Vec3::new(-4.0, 0.5, 9.0),
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(-2.0, 1.0, 0.0),
        )
        .unwrap();
        let p = Vec3::new(0.3, -7.0, 2.5);
        assert!(near(m.inverse().point(m.point(p)), p));
        assert!(near(m.point(m.inverse().point(p)), p));
        assert!(near(m.inverse().inverse().point(p), m.point(p)));
        let v = Vec3::new(1.0, 1.0, -1.0);
        assert!((m.vector(v).norm() - v.norm()).abs() < 1e-12);
        assert_eq!(Rigid::IDENTITY.point(p), p);
    }
}
