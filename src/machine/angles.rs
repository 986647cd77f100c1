//! Angle helpers shared by the machines: wrapping, unwrapping next to a previous value, and
//! rotations written with `crate::num` (libm) so native and wasm give identical bits.

use glam::DVec3;

use crate::num;

/// Wrap an angle in degrees into (−180°, 180°].
pub fn wrap180(deg: f64) -> f64 {
    let mut a = deg % 360.0;
    if a <= -180.0 {
        a += 360.0;
    } else if a > 180.0 {
        a -= 360.0;
    }
    a
}

/// The representative of `target` (degrees, modulo 360°) nearest to `previous`:
/// `previous + wrap180(target − previous)` — the continuous unwrap of a rotary axis.
pub fn unwrap_near(target: f64, previous: f64) -> f64 {
    previous + wrap180(target - previous)
}

/// How much nearer (degrees) the flipped branch of [`nearer_half_turn`] must be to be taken, so
/// that rounding does not flip between two equally near branches.
pub const BRANCH_TIE_DEG: f64 = 1e-9;

/// Of `angle` and `angle + 180°` (degrees), each unwrapped next to `previous`, the nearer one,
/// with the sign `s` (±1) that goes with it: `(unwrap_near(angle, previous), 1)` or
/// `(unwrap_near(angle + 180°, previous), −1)`. For an axis whose value `(a, x)` and
/// `(a + 180°, −x)` mean the same pose (a tilt or a radius `x` across the centre); ties keep
/// `angle`.
pub fn nearer_half_turn(angle: f64, previous: f64) -> (f64, f64) {
    let a = unwrap_near(angle, previous);
    let flipped = unwrap_near(angle + 180.0, previous);
    if (flipped - previous).abs() < (a - previous).abs() - BRANCH_TIE_DEG {
        (flipped, -1.0)
    } else {
        (a, 1.0)
    }
}

/// Rodrigues: rotate `v` about the unit `axis` by `angle` radians (right-hand rule).
/// `v cos θ + (a × v) sin θ + a (a·v)(1 − cos θ)`.
pub fn rotate(v: DVec3, axis: DVec3, angle: f64) -> DVec3 {
    Turn::new(axis, angle).apply(v)
}

/// Rotate about +Z by `angle` radians: (x cos − y sin, x sin + y cos, z).
pub fn rot_z(v: DVec3, angle: f64) -> DVec3 {
    Turn::new(DVec3::Z, angle).about_z(v)
}

/// A rotation about a unit axis with its sine and cosine computed once, for kinematics that
/// turn several vectors by the same angle ([`rotate`] and [`rot_z`] give the same bits).
#[derive(Clone, Copy, Debug)]
pub struct Turn {
    axis: DVec3,
    sin: f64,
    cos: f64,
}

impl Turn {
    /// The rotation about the unit `axis` by `angle` radians (right-hand rule).
    pub fn new(axis: DVec3, angle: f64) -> Turn {
        Turn {
            axis,
            sin: num::sin(angle),
            cos: num::cos(angle),
        }
    }

    /// The rotation about the unit `axis` whose cosine and sine are given (`cos² + sin² = 1`).
    pub fn from_cos_sin(axis: DVec3, cos: f64, sin: f64) -> Turn {
        Turn { axis, sin, cos }
    }

    /// The least rotation taking the unit vector `from` to +Z: about the horizontal axis
    /// `from × e₃ / |from × e₃|` by the angle whose sine is `|from_xy|` and cosine `from_z`
    /// (no inverse trigonometry). The identity for a vertical `from`.
    pub fn onto_z(from: DVec3) -> Turn {
        let s = (from.x * from.x + from.y * from.y).sqrt();
        if s == 0.0 {
            return Turn {
                axis: DVec3::X,
                sin: 0.0,
                cos: 1.0,
            };
        }
        Turn {
            axis: DVec3::new(from.y / s, -from.x / s, 0.0),
            sin: s,
            cos: from.z,
        }
    }

    /// sin θ.
    pub fn sin(&self) -> f64 {
        self.sin
    }
    /// cos θ.
    pub fn cos(&self) -> f64 {
        self.cos
    }

    /// The opposite rotation (about the same axis by −θ): the same bits as
    /// `Turn::new(axis, -angle)`, since sin is odd and cos even in libm bit for bit
    /// (`the_reversed_turn_is_the_turn_by_the_opposite_angle_bit_for_bit`), without trigonometry.
    pub fn reversed(&self) -> Turn {
        Turn {
            axis: self.axis,
            sin: -self.sin,
            cos: self.cos,
        }
    }

    /// Rodrigues: `v cos θ + (a × v) sin θ + a (a·v)(1 − cos θ)`.
    pub fn apply(&self, v: DVec3) -> DVec3 {
        let (a, s, c) = (self.axis, self.sin, self.cos);
        v * c + a.cross(v) * s + a * (a.dot(v) * (1.0 - c))
    }

    /// The same angle about +Z, whatever the axis: (x cos − y sin, x sin + y cos, z).
    pub fn about_z(&self, v: DVec3) -> DVec3 {
        let (s, c) = (self.sin, self.cos);
        DVec3::new(v.x * c - v.y * s, v.x * s + v.y * c, v.z)
    }
}

/// Rotate about +X by `angle` radians: (x, y cos − z sin, y sin + z cos).
pub fn rot_x(v: DVec3, angle: f64) -> DVec3 {
    let (s, c) = (num::sin(angle), num::cos(angle));
    DVec3::new(v.x, v.y * c - v.z * s, v.y * s + v.z * c)
}

/// Rotate about +Y by `angle` radians: (x cos + z sin, y, −x sin + z cos).
pub fn rot_y(v: DVec3, angle: f64) -> DVec3 {
    let (s, c) = (num::sin(angle), num::cos(angle));
    DVec3::new(v.x * c + v.z * s, v.y, -v.x * s + v.z * c)
}

/// Tilt of `n` from +Z, radians in [0, π] (accurate near 0: atan2(|n_xy|, n_z)).
pub fn tilt(n: DVec3) -> f64 {
    num::atan2((n.x * n.x + n.y * n.y).sqrt(), n.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_and_unwrap() {
        assert_eq!(wrap180(180.0), 180.0);
        assert_eq!(wrap180(-180.0), 180.0);
        assert_eq!(wrap180(190.0), -170.0);
        assert_eq!(wrap180(-190.0), 170.0);
        assert_eq!(wrap180(720.0 + 10.0), 10.0);
        assert!((unwrap_near(-179.0, 179.0) - 181.0).abs() < 1e-12);
        assert!((unwrap_near(179.0, -179.0 + 720.0) - (-181.0 + 720.0)).abs() < 1e-12);
    }

    #[test]
    fn nearer_half_turn_flips_only_when_nearer() {
        assert_eq!(nearer_half_turn(10.0, 0.0), (10.0, 1.0));
        assert_eq!(nearer_half_turn(-170.0, 0.0), (10.0, -1.0));
        assert_eq!(nearer_half_turn(-170.0, 360.0), (370.0, -1.0));
        // Equally near (±90° from previous): keep `angle`.
        assert_eq!(nearer_half_turn(90.0, 0.0), (90.0, 1.0));
    }

    #[test]
    fn rotations_agree_with_rodrigues() {
        let v = DVec3::new(0.3, -1.2, 2.5);
        for a in [-2.0, -0.3, 0.0, 0.7, 3.0] {
            assert!((rot_z(v, a) - rotate(v, DVec3::Z, a)).length() < 1e-14);
            assert!((rot_x(v, a) - rotate(v, DVec3::X, a)).length() < 1e-14);
            assert!((rot_y(v, a) - rotate(v, DVec3::Y, a)).length() < 1e-14);
        }
        // Right-hand rule: +Z about +Y by +90° goes to +X.
        assert!((rot_y(DVec3::Z, core::f64::consts::FRAC_PI_2) - DVec3::X).length() < 1e-15);
    }

    #[test]
    fn the_reversed_turn_is_the_turn_by_the_opposite_angle_bit_for_bit() {
        // the kinematics build inverse rotations with `reversed` and promise unchanged output:
        // libm's sin must be odd and cos even to the bit, over every range its argument
        // reduction treats differently (tiny, < π/4, the medium and the large reductions)
        let mut x = 1e-300f64;
        let mut count = 0;
        while x < 1e6 {
            for a in [x, x * 1.000_000_7, core::f64::consts::PI * x] {
                let t = Turn::new(DVec3::Z, a);
                let r = t.reversed();
                let o = Turn::new(DVec3::Z, -a);
                assert_eq!(r.sin().to_bits(), o.sin().to_bits(), "sin at {a:e}");
                assert_eq!(r.cos().to_bits(), o.cos().to_bits(), "cos at {a:e}");
                count += 1;
            }
            x *= 1.013;
        }
        assert!(count > 10_000);
    }
}
