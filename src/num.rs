//! Deterministic floating-point helpers.
//!
//! Output must be byte-identical natively and in wasm, so every transcendental function goes
//! through the pure-Rust `libm` crate (the platform libm may differ in the last bit). `sqrt`,
//! `+ − × ÷` are IEEE-754 exact everywhere and are used directly.

/// Tangent (radians).
#[inline]
pub fn tan(x: f64) -> f64 {
    libm::tan(x)
}
/// Sine (radians).
#[inline]
pub fn sin(x: f64) -> f64 {
    libm::sin(x)
}
/// Cosine (radians).
#[inline]
pub fn cos(x: f64) -> f64 {
    libm::cos(x)
}
/// Arc tangent of y/x in (−π, π].
#[inline]
pub fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}
/// Arc sine.
#[inline]
pub fn asin(x: f64) -> f64 {
    libm::asin(x)
}
/// Arc cosine.
#[inline]
pub fn acos(x: f64) -> f64 {
    libm::acos(x)
}
/// Arc tangent.
#[inline]
pub fn atan(x: f64) -> f64 {
    libm::atan(x)
}
/// Degrees to radians.
#[inline]
pub fn rad(deg: f64) -> f64 {
    deg * (core::f64::consts::PI / 180.0)
}
/// Radians to degrees.
#[inline]
pub fn deg(rad: f64) -> f64 {
    rad * (180.0 / core::f64::consts::PI)
}

/// Angle between two unit vectors in radians, accurate near 0 and π (uses atan2 of |a×b|, a·b).
#[inline]
pub fn angle_between(a: glam::DVec3, b: glam::DVec3) -> f64 {
    atan2(a.cross(b).length(), a.dot(b))
}

/// Full precision (shortest round-trip text), `-0` written as `0`: numbers in messages and
/// file headers that a user copies back into a file.
pub fn fmt_shortest(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v}")
    }
}
