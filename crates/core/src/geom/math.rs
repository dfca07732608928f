//! The one vocabulary of the crate: scalar and vector types, and the
//! default fit tolerances (the numerical ones are in `geom::tolerance`).
//! Nothing else in the core spells out raw `[f64; 3]` except at
//! file boundaries (`From`/`Into` conversions live here).

use serde::{Deserialize, Serialize};
use std::ops::{Add, AddAssign, Div, Index, Mul, Neg, Sub, SubAssign};

/// The scalar type of every computation in the core.
pub type Real = f64;

/// Default average relative error tolerance `E_a` (paper Eq. 12): 1 %.
pub const DEFAULT_EA: Real = 0.01;
/// Default maximum relative error tolerance `E_M` (paper Eq. 12): 5 %.
pub const DEFAULT_EM: Real = 0.05;

/// A loop's mean (equivalent) radius: the radius `√(|A|/π)` of the circle
/// of its area's magnitude.
pub fn mean_radius(area: Real) -> Real {
    (area.abs() / std::f64::consts::PI).sqrt()
}

/// A point or vector in the plane.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Vec2 {
    pub x: Real,
    pub y: Real,
}

/// A point or vector in space.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Vec3 {
    pub x: Real,
    pub y: Real,
    pub z: Real,
}

/// A point in space (same representation as [`Vec3`]).
pub type Point3 = Vec3;
/// A point in the plane (same representation as [`Vec2`]).
pub type Point2 = Vec2;

impl Vec2 {
    pub const ZERO: Vec2 = Vec2 { x: 0.0, y: 0.0 };

    #[inline]
    pub const fn new(x: Real, y: Real) -> Self {
        Vec2 { x, y }
    }
    #[inline]
    pub fn dot(self, o: Vec2) -> Real {
        self.x * o.x + self.y * o.y
    }
    /// The z component of the 3D cross product (signed parallelogram area).
    #[inline]
    pub fn cross(self, o: Vec2) -> Real {
        self.x * o.y - self.y * o.x
    }
    #[inline]
    pub fn norm(self) -> Real {
        self.x.hypot(self.y)
    }
    #[inline]
    pub fn norm_squared(self) -> Real {
        self.dot(self)
    }
    #[inline]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite()
    }
    /// The unit vector along `self`, or `None` for a zero or non-finite vector.
    #[inline]
    pub fn normalized(self) -> Option<Vec2> {
        let n = self.norm();
        (n > 0.0 && n.is_finite()).then(|| self / n)
    }
    /// Rotate by +90°.
    #[inline]
    pub fn perp(self) -> Vec2 {
        Vec2::new(-self.y, self.x)
    }
    #[inline]
    pub fn to_array(self) -> [Real; 2] {
        [self.x, self.y]
    }
}

impl Vec3 {
    pub const ZERO: Vec3 = Vec3 {
        x: 0.0,
        y: 0.0,
        z: 0.0,
    };
    pub const X: Vec3 = Vec3 {
        x: 1.0,
        y: 0.0,
        z: 0.0,
    };
    pub const Y: Vec3 = Vec3 {
        x: 0.0,
        y: 1.0,
        z: 0.0,
    };
    pub const Z: Vec3 = Vec3 {
        x: 0.0,
        y: 0.0,
        z: 1.0,
    };

    #[inline]
    pub const fn new(x: Real, y: Real, z: Real) -> Self {
        Vec3 { x, y, z }
    }
    #[inline]
    pub fn dot(self, o: Vec3) -> Real {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    #[inline]
    pub fn cross(self, o: Vec3) -> Vec3 {
        Vec3::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }
    #[inline]
    pub fn norm(self) -> Real {
        self.norm_squared().sqrt()
    }
    #[inline]
    pub fn norm_squared(self) -> Real {
        self.dot(self)
    }
    /// The unit vector along `self`, or `None` for a zero or non-finite vector.
    #[inline]
    pub fn normalized(self) -> Option<Vec3> {
        let n = self.norm();
        (n > 0.0 && n.is_finite()).then(|| self / n)
    }
    #[inline]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
    #[inline]
    pub fn distance(self, o: Vec3) -> Real {
        (self - o).norm()
    }
    /// Component-wise minimum.
    #[inline]
    pub fn min(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x.min(o.x), self.y.min(o.y), self.z.min(o.z))
    }
    /// Component-wise maximum.
    #[inline]
    pub fn max(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x.max(o.x), self.y.max(o.y), self.z.max(o.z))
    }
    #[inline]
    pub fn to_array(self) -> [Real; 3] {
        [self.x, self.y, self.z]
    }
    /// A unit vector perpendicular to `self` (which need not be unit length);
    /// chosen from the coordinate axis least aligned with `self`, the first
    /// of axes aligned alike to within 1e-9 of `self`'s largest component
    /// (an up of `(-2e-15, 1, 3e-15)` takes X as `(0, 1, 0)` does, not the
    /// axis its rounding happens to favour).
    pub fn any_perpendicular(self) -> Vec3 {
        let a = Vec3::new(self.x.abs(), self.y.abs(), self.z.abs());
        let tie = 1e-9 * a.x.max(a.y).max(a.z);
        let helper = if a.x <= a.y + tie && a.x <= a.z + tie {
            Vec3::X
        } else if a.y <= a.z + tie {
            Vec3::Y
        } else {
            Vec3::Z
        };
        self.cross(helper).normalized().unwrap_or(Vec3::X)
    }
}

impl From<[Real; 3]> for Vec3 {
    fn from(a: [Real; 3]) -> Self {
        Vec3::new(a[0], a[1], a[2])
    }
}
impl From<Vec3> for [Real; 3] {
    fn from(v: Vec3) -> Self {
        v.to_array()
    }
}
impl From<[Real; 2]> for Vec2 {
    fn from(a: [Real; 2]) -> Self {
        Vec2::new(a[0], a[1])
    }
}
impl From<Vec2> for [Real; 2] {
    fn from(v: Vec2) -> Self {
        v.to_array()
    }
}

impl Index<usize> for Vec3 {
    type Output = Real;
    fn index(&self, i: usize) -> &Real {
        match i {
            0 => &self.x,
            1 => &self.y,
            2 => &self.z,
            _ => panic!("Vec3 index {i} out of range 0..3"),
        }
    }
}

macro_rules! impl_ops {
    ($t:ident, $($f:ident),+) => {
        impl Add for $t {
            type Output = $t;
            #[inline]
            fn add(self, o: $t) -> $t { $t { $($f: self.$f + o.$f),+ } }
        }
        impl Sub for $t {
            type Output = $t;
            #[inline]
            fn sub(self, o: $t) -> $t { $t { $($f: self.$f - o.$f),+ } }
        }
        impl Neg for $t {
            type Output = $t;
            #[inline]
            fn neg(self) -> $t { $t { $($f: -self.$f),+ } }
        }
        impl Mul<Real> for $t {
            type Output = $t;
            #[inline]
            fn mul(self, s: Real) -> $t { $t { $($f: self.$f * s),+ } }
        }
        impl Mul<$t> for Real {
            type Output = $t;
            #[inline]
            fn mul(self, v: $t) -> $t { v * self }
        }
        impl Div<Real> for $t {
            type Output = $t;
            #[inline]
            fn div(self, s: Real) -> $t { $t { $($f: self.$f / s),+ } }
        }
        impl AddAssign for $t {
            #[inline]
            fn add_assign(&mut self, o: $t) { $(self.$f += o.$f;)+ }
        }
        impl SubAssign for $t {
            #[inline]
            fn sub_assign(&mut self, o: $t) { $(self.$f -= o.$f;)+ }
        }
    };
}
impl_ops!(Vec2, x, y);
impl_ops!(Vec3, x, y, z);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    #[test]
    fn cross_product_is_right_handed() {
        assert_eq!(Vec3::X.cross(Vec3::Y), Vec3::Z);
        assert_eq!(Vec3::Y.cross(Vec3::Z), Vec3::X);
        assert_eq!(Vec2::new(1.0, 0.0).cross(Vec2::new(0.0, 1.0)), 1.0);
    }

    #[test]
    fn any_perpendicular_ignores_rounding() {
        let p = Vec3::new(-2.4e-15, 1.0, 2.9e-15).any_perpendicular();
        let q = Vec3::new(2.9e-15, 1.0, -2.4e-15).any_perpendicular();
        assert!((p - Vec3::Y.any_perpendicular()).norm() < 1e-12, "{p:?}");
        assert!((q - Vec3::Y.any_perpendicular()).norm() < 1e-12, "{q:?}");
    }

    #[test]
    fn any_perpendicular_is_unit_and_orthogonal() {
        for v in [
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(0.0, 0.0, -5.0),
            Vec3::new(1e-3, 1e3, 0.0),
        ] {
            let p = v.any_perpendicular();
            assert_near!(p.norm(), 1.0, 1e-15);
            assert_near!(p.dot(v) / v.norm(), 0.0, 1e-15);
        }
    }

    #[test]
    fn normalized_rejects_zero_and_nan() {
        assert!(Vec3::ZERO.normalized().is_none());
        assert!(Vec3::new(f64::NAN, 0.0, 0.0).normalized().is_none());
    }
}
