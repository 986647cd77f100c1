//! Raw probe values → axis components (seed 004 §5.4.1, Eqs. 5.2–5.6; §5.1.6–5.1.8).
//!
//! All values in the printer's current frame, mm; the 3D touch probe reports the centre XY and
//! the bottom Z of its ruby sphere (radius r_p = 1 mm). Each formula is implemented as printed
//! in the thesis; where the printed formula needs an interpretation of its inputs, the doc says
//! which.
//!
//! - Eq. 5.2: the Y error of the A position method when A is turned by θ about Z, for a probed
//!   radius r: `E_y = r − (cos θ − cos(θ + 180°))/2 · r` (= r (1 − cos θ); 19 µm for 5 mm, 5°).
//! - Eq. 5.3: `A_pos = [0, (y₉₀ + y₋₉₀)/2, z₀ + (y_m − c_y)/2 + r_p]`, `y_m = |y₉₀ − y₋₉₀|`.
//! - Eq. 5.4: `m_zx = (z_{x,1} − z_{x,2})/(2 d_zx)`, `m_zy = (z_{y,1} − z_{y,2})/(2 d_zy)`,
//!   `m_yx = ((y_{x₁,2} − y_{x₁,1})/2 − (y_{x₂,2} − y_{x₂,1})/2)/d_yx`,
//!   `A_dir = normalize([1, m_yx, m_zx])`. Inputs as the thesis names them: `z_{x,1}`, `z_{x,2}`
//!   probed from the top 2·d_zx apart along X (`z_{y,·}` 2·d_zy apart along Y), `y_{x_k,1}`,
//!   `y_{x_k,2}` the two Y probes at the X position x_k, the positions x₁, x₂ d_yx apart. Note:
//!   as printed, m_yx is the difference of the *half differences* of the two Y probes; it is
//!   the slope of the centre line when the scripts record the two side probes with opposite
//!   signs (e.g. as probe travel), not when both are plain Y coordinates (then the centre is
//!   their half *sum*). The formula is kept as printed; check against your probe script.
//! - Eq. 5.5: `B_pos = [(x_{p₁} + x_{p₂})/2, (y_{p₁} + y_{p₂})/2, −10]` (Z is the commanded probe
//!   height, −10 mm by default).
//! - Eq. 5.6: `p₁, p₂` = means of the four side points at the heights z₁, z₂;
//!   `B_dir = normalize(p₂ − p₁)`, turned to point up (+Z) when p₂ is the lower height (the
//!   thesis' B_dir ≈ +Z; the line is the same).
//! - §5.1.6: `z_bias = ½(mean z₉₀ + mean z₋₉₀ − d_f)` (d_f = 4 mm, the width across the flats of
//!   the B axle), `z_shift = ½(mean z₉₀ + mean z₋₉₀)`.
//! - §5.1.7: `α = asin((z₂ − z₁)/10 mm)` (z₂ at the larger Y; the distance is a parameter).
//! - §5.1.8: `z_d` = the difference of the A–B distance from the Z-bias probing (z_shift) and
//!   from the step-by-step measurements (the Z component of A^B_pos, Eq. 5.7):
//!   `z_d = z_shift − A^B_pos.z`; the correction of Eq. 5.1 is then
//!   [`crate::machine::abtable::AbTable::z_wobble`] (±z_d at A = ±90°).
//! - §6.2.2 (A axis orientation test, appendix A "Z Rotation Offset"): a straight line drawn
//!   across a cylinder slice with the A axis as the main movement, "approximating the length of
//!   the line as 40 mm" (L), and the caliper distances of its two ends to the side of the
//!   object, d_start and d_end; "calculating the slope on the surfaces gives an orientation
//!   error" α_{A,z}, the Z-plane rotation the origin applies to A_dir (Eq. 5.7,
//!   `A'_dir = R_z(α_{A,z}) A_dir`): `α_{A,z} = atan((d_start − d_end) / L)`. The sign is
//!   not printed in the seed; it follows from the kinematics (see [`a_z_rotation`]) with
//!   d measured from the object's −X side and the line's start at the smaller A.

use glam::DVec3;

use super::{finite, CalibError};
use crate::machine::abtable::{AbTable, AbTableParams};
use crate::num;

/// Radius of the 3D touch probe's ruby sphere, mm (a 2 mm sphere).
pub const PROBE_RADIUS: f64 = 1.0;
/// Width across the flats of the B axle (§5.1.6), mm.
pub const AXLE_FLATS: f64 = 4.0;
/// Probe height of the B position and first B orientation probes (Eqs. 5.5, 5.6), mm.
pub const B_PROBE_Z: f64 = -10.0;
/// Distance between the two heights of the A scaling probe (§5.1.7), mm.
pub const A_SCALING_DISTANCE: f64 = 10.0;
/// The length of the A orientation test's line (§6.2.2: "approximated to have a length of
/// 40 mm"), mm.
pub const A_ORIENTATION_LINE: f64 = 40.0;
/// Eq. 5.4 as printed, said where it is used (CLI help and output): m_yx is the difference of
/// the two Y probes' *half differences*, which measures how the part's width changes along X (a
/// taper), not the slope of its centre line (that is the difference of the half *sums*). It is
/// the slope only when the probe script records the two side probes with opposite signs.
pub const EQ_5_4_NOTE: &str = "Eq. 5.4 as printed takes m_yx from the half *differences* of the two Y probes at each X: with plain Y coordinates that measures a taper (the width changing along X), not the slope of the centre line (the half sums). It is the slope only if your probe script records the -Y and +Y probes with opposite signs (as probe travel); check yours before trusting A_dir's Y component.";
/// The probe bias c_y of the author's printer (§6.1.1), mm: an example, never a default (each
/// probe has its own; measure it as §6.1.1 does, with an object of known size).
pub const THESIS_C_Y: f64 = 0.453;

/// One probe computation: its inputs (JSON tag `kind`, the names the thesis uses).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
#[non_exhaustive]
pub enum ProbeInput {
    /// Eq. 5.2.
    APosError {
        /// r: the probed radius, mm.
        radius: f64,
        /// θ: how far the A axis is turned about Z, degrees.
        z_rotation_deg: f64,
    },
    /// Eq. 5.3.
    APos {
        /// z₀: the probed Z (sphere bottom) that A_pos.z is measured up from, mm.
        z0: f64,
        /// y₉₀: Y reported by the probe (sphere centre) with A turned to +90°, mm.
        y90: f64,
        /// y₋₉₀: Y reported by the probe (sphere centre) with A turned to −90°, mm.
        y_minus90: f64,
        /// c_y: the probe's Y bias, subtracted from y_m (0.453 mm on the thesis printer), mm.
        c_y: f64,
        /// r_p: radius of the probe's ruby sphere, mm (default [`PROBE_RADIUS`]).
        #[serde(default = "probe_radius")]
        r_p: f64,
    },
    /// Eq. 5.4: `z_x = [z_{x,1}, z_{x,2}]`, `z_y = [z_{y,1}, z_{y,2}]`,
    /// `y_x1 = [y_{x₁,1}, y_{x₁,2}]`, `y_x2 = [y_{x₂,1}, y_{x₂,2}]`.
    ADir {
        /// [z_{x,1}, z_{x,2}]: Z probed from the top at two X positions 2·d_zx apart, mm.
        z_x: [f64; 2],
        /// d_zx: half the X spacing of the `z_x` probes, mm (non-zero).
        d_zx: f64,
        /// [z_{y,1}, z_{y,2}]: Z probed from the top at two Y positions 2·d_zy apart, mm.
        z_y: [f64; 2],
        /// d_zy: half the Y spacing of the `z_y` probes, mm (non-zero).
        d_zy: f64,
        /// [y_{x₁,1}, y_{x₁,2}]: the two side (Y) probes at the X position x₁, mm.
        y_x1: [f64; 2],
        /// [y_{x₂,1}, y_{x₂,2}]: the two side (Y) probes at the X position x₂, mm.
        y_x2: [f64; 2],
        /// d_yx: the X distance between x₁ and x₂, mm (non-zero).
        d_yx: f64,
    },
    /// Eq. 5.5.
    BPos {
        /// [x_{p₁}, x_{p₂}]: X of the two probe points p₁, p₂, mm.
        x_p: [f64; 2],
        /// [y_{p₁}, y_{p₂}]: Y of the two probe points p₁, p₂, mm.
        y_p: [f64; 2],
        /// The commanded probe height, taken as B_pos.z, mm (default [`B_PROBE_Z`]).
        #[serde(default = "b_probe_z")]
        z: f64,
    },
    /// Eq. 5.6: four side points at each of two heights.
    BDir {
        /// The four side points probed at the first height z₁, mm.
        p_z1: [DVec3; 4],
        /// The four side points probed at the second height z₂, mm.
        p_z2: [DVec3; 4],
    },
    /// §5.1.6.
    ZBias {
        /// Z values probed with A at +90° (their mean is used), mm.
        z90: Vec<f64>,
        /// Z values probed with A at −90° (their mean is used), mm.
        z_minus90: Vec<f64>,
        /// d_f: width across the flats of the B axle, mm (default [`AXLE_FLATS`]).
        #[serde(default = "axle_flats")]
        d_f: f64,
    },
    /// §5.1.7.
    AScaling {
        /// z₁: Z probed at the smaller Y, mm.
        z1: f64,
        /// z₂: Z probed at the larger Y, mm.
        z2: f64,
        /// Distance between the two probe points, mm (default [`A_SCALING_DISTANCE`]).
        #[serde(default = "a_scaling_distance")]
        distance: f64,
    },
    /// §5.1.7: the A axis' steps per degree from the α of its ±90° orientations.
    AStepsPerDegree {
        /// α₊: the α (§5.1.7) measured with A at +90°, degrees.
        alpha_plus_deg: f64,
        /// α₋: the α measured with A at −90°, degrees.
        alpha_minus_deg: f64,
        /// The steps per degree the firmware had when they were measured (`M92 A…`).
        steps_per_deg: f64,
    },
    /// §6.2.2: α_{A,z} from the caliper readings of the A orientation test print.
    AOrientation {
        /// d_start: caliper distance from the line's start (drawn at the smaller A) to the
        /// object's −X side, mm.
        d_start: f64,
        /// d_end: caliper distance from the line's end (the larger A) to the same side, mm.
        d_end: f64,
        /// L: the line's length, mm (default [`A_ORIENTATION_LINE`], the seed's 40 mm).
        #[serde(default = "a_orientation_line")]
        line_length: f64,
    },
    /// §5.1.8.
    Wobble {
        /// z_shift from the Z-bias probing (§5.1.6), mm.
        z_shift: f64,
        /// Z component of A^B_pos from Eq. 5.7 (the step-by-step measurements), mm.
        ab_z: f64,
    },
}

fn probe_radius() -> f64 {
    PROBE_RADIUS
}
fn b_probe_z() -> f64 {
    B_PROBE_Z
}
fn axle_flats() -> f64 {
    AXLE_FLATS
}
fn a_scaling_distance() -> f64 {
    A_SCALING_DISTANCE
}
fn a_orientation_line() -> f64 {
    A_ORIENTATION_LINE
}

/// What a probe computation gives.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
#[non_exhaustive]
pub enum ProbeOutput {
    /// Eq. 5.2: E_y, mm.
    APosError {
        /// E_y: the Y error of the A position method, mm.
        e_y: f64,
    },
    /// Eq. 5.3: A_pos and y_m, mm.
    APos {
        /// A_pos: a point of the A axis line (printer's current frame), mm.
        a_pos: DVec3,
        /// y_m = |y₉₀ − y₋₉₀|, mm.
        y_m: f64,
    },
    /// Eq. 5.4.
    ADir {
        /// m_zx: slope of the A axis in Z over X.
        m_zx: f64,
        /// m_zy: slope of the A axis in Z over Y, its levelness (`a_z_in_y`).
        m_zy: f64,
        /// m_yx: slope of the A axis in Y over X.
        m_yx: f64,
        /// A_dir = normalize([1, m_yx, m_zx]) (unit).
        a_dir: DVec3,
    },
    /// Eq. 5.5.
    BPos {
        /// B_pos: a point of the B axis line at the probe height, mm.
        b_pos: DVec3,
    },
    /// Eq. 5.6: the two mean points and B_dir.
    BDir {
        /// p₁: mean of the four side points at z₁, mm.
        p1: DVec3,
        /// p₂: mean of the four side points at z₂, mm.
        p2: DVec3,
        /// B_dir: unit direction of the B axis, turned to point up (+Z).
        b_dir: DVec3,
    },
    /// §5.1.6.
    ZBias {
        /// z_bias = ½(mean z₉₀ + mean z₋₉₀ − d_f), mm (for `calibrate origin --bias`).
        z_bias: f64,
        /// z_shift = ½(mean z₉₀ + mean z₋₉₀), mm (the A–B distance the wobble needs).
        z_shift: f64,
    },
    /// §5.1.7: α, degrees.
    AScaling {
        /// α: the signed angle error of the A axis, degrees.
        alpha_deg: f64,
    },
    /// §5.1.7: the corrected steps per degree and the zero-point shift left.
    AStepsPerDegree {
        /// k: the A axis turns k degrees per commanded degree.
        k: f64,
        /// The corrected steps per degree: the old over k.
        steps_per_deg: f64,
        /// The symmetric part of the error (α₊ + α₋)/2, degrees: a zero-point shift, not a
        /// scaling (§5.1.7: redetermine the zero point, §5.1.2).
        zero_shift_deg: f64,
    },
    /// §6.2.2: α_{A,z}, degrees.
    AOrientation {
        /// The slope (d_start − d_end) / L of the line against the object's side.
        slope: f64,
        /// α_{A,z} = atan(slope), degrees (`calibrate origin --a-z-correction`).
        alpha_a_z_deg: f64,
    },
    /// §5.1.8: z_d and the Eq. 5.1 correction at A = −90°, −45°, 0°, 45°, 90°.
    Wobble {
        /// z_d = z_shift − A^B_pos.z, mm (the machine JSON's `z_wobble_mm`).
        z_d: f64,
        /// [A in degrees, Eq. 5.1 Z correction in mm] at A = −90°, −45°, 0°, 45°, 90°.
        correction: Vec<[f64; 2]>,
    },
}

/// Eq. 5.2: `E_y = r − (cos θ − cos(θ + 180°))/2 · r`, θ in degrees.
pub fn a_pos_error(radius: f64, z_rotation_deg: f64) -> f64 {
    let t = num::rad(z_rotation_deg);
    radius - (num::cos(t) - num::cos(t + core::f64::consts::PI)) / 2.0 * radius
}

/// Eq. 5.3: `(A_pos, y_m)`.
pub fn a_pos(z0: f64, y90: f64, y_minus90: f64, c_y: f64, r_p: f64) -> (DVec3, f64) {
    let y_m = (y90 - y_minus90).abs();
    (
        DVec3::new(0.0, (y90 + y_minus90) / 2.0, z0 + (y_m - c_y) / 2.0 + r_p),
        y_m,
    )
}

/// Eq. 5.4: `(m_zx, m_zy, m_yx, A_dir)`.
pub fn a_dir(
    z_x: [f64; 2],
    d_zx: f64,
    z_y: [f64; 2],
    d_zy: f64,
    y_x1: [f64; 2],
    y_x2: [f64; 2],
    d_yx: f64,
) -> Result<(f64, f64, f64, DVec3), CalibError> {
    for (what, d) in [("d_zx", d_zx), ("d_zy", d_zy), ("d_yx", d_yx)] {
        if !(d.is_finite() && d != 0.0) {
            return Err(CalibError::BadInput {
                what: what.to_string(),
                message: format!("the probe spacing {d} must be a non-zero number (mm)"),
            });
        }
    }
    let m_zx = (z_x[0] - z_x[1]) / (2.0 * d_zx);
    let m_zy = (z_y[0] - z_y[1]) / (2.0 * d_zy);
    let m_yx = ((y_x1[1] - y_x1[0]) / 2.0 - (y_x2[1] - y_x2[0]) / 2.0) / d_yx;
    let v = DVec3::new(1.0, m_yx, m_zx);
    Ok((m_zx, m_zy, m_yx, v / v.length()))
}

/// Eq. 5.5.
pub fn b_pos(x_p: [f64; 2], y_p: [f64; 2], z: f64) -> DVec3 {
    DVec3::new((x_p[0] + x_p[1]) / 2.0, (y_p[0] + y_p[1]) / 2.0, z)
}

/// Eq. 5.6: `(p₁, p₂, B_dir)`, B_dir pointing up.
pub fn b_dir(p_z1: &[DVec3; 4], p_z2: &[DVec3; 4]) -> Result<(DVec3, DVec3, DVec3), CalibError> {
    let p1 = p_z1.iter().copied().sum::<DVec3>() / 4.0;
    let p2 = p_z2.iter().copied().sum::<DVec3>() / 4.0;
    let d = p2 - p1;
    if !(d.length() > crate::tolerance::LENGTH_EPSILON) {
        return Err(CalibError::BadInput {
            what: "B orientation probes".to_string(),
            message: "the two heights have the same mean point; probe at two different heights (−10 and −15 mm)".to_string(),
        });
    }
    let mut dir = d / d.length();
    if dir.z < 0.0 {
        dir = -dir;
    }
    Ok((p1, p2, dir))
}

fn mean(what: &str, v: &[f64]) -> Result<f64, CalibError> {
    if v.is_empty() {
        return Err(CalibError::BadInput {
            what: what.to_string(),
            message: "needs at least one probed value".to_string(),
        });
    }
    Ok(v.iter().sum::<f64>() / v.len() as f64)
}

/// §5.1.6: `(z_bias, z_shift)`.
pub fn z_bias(z90: &[f64], z_minus90: &[f64], d_f: f64) -> Result<(f64, f64), CalibError> {
    let s = mean("z90", z90)? + mean("z_minus90", z_minus90)?;
    Ok((0.5 * (s - d_f), 0.5 * s))
}

/// §5.1.7: α = asin((z₂ − z₁)/distance), degrees.
pub fn a_scaling(z1: f64, z2: f64, distance: f64) -> Result<f64, CalibError> {
    let r = (z2 - z1) / distance;
    if !(r.abs() <= 1.0) {
        return Err(CalibError::BadInput {
            what: "A scaling".to_string(),
            message: format!(
                "|z2 − z1| = {} exceeds the probe distance {distance} mm",
                (z2 - z1).abs()
            ),
        });
    }
    Ok(num::deg(num::asin(r)))
}

/// §5.1.7: the A axis' scaling from the α of its ±90° orientations, `(k, zero_shift)`.
///
/// α is the actual minus the commanded angle (a right-hand turn δ too far about +X tilts the
/// flat, level at the ideal pose, so that z rises toward +Y: α = asin((z₂ − z₁)/d) = δ, at
/// +90° and at −90° alike). The axis turns `actual = k·commanded + c`; at ±90°:
/// `90k + c = 90 + α₊` and `−90k + c = −90 + α₋`, so
/// `k = 1 + (α₊ − α₋)/180` and `c = (α₊ + α₋)/2`. The firmware's steps per degree become
/// `S / k` (fewer degrees per step when the axis turned too far); c is the mirrored offset the
/// thesis attributes to the zero point (§5.1.7). On the thesis printer (§6.1) α₋ ≈ −0.126°,
/// α₊ ≈ −0.63°: k ≈ 0.9972, more steps ("requiring more steps", §5.1.7).
pub fn a_steps_per_degree(alpha_plus_deg: f64, alpha_minus_deg: f64) -> (f64, f64) {
    (
        1.0 + (alpha_plus_deg - alpha_minus_deg) / 180.0,
        (alpha_plus_deg + alpha_minus_deg) / 2.0,
    )
}

/// §6.2.2: `α_{A,z} = atan((d_start − d_end) / L)`, degrees, and the slope.
///
/// Why this sign (the seed gives the magnitude, "the slope"): the A axis turns the part about
/// its true direction `t = R_z(ε) x̂` while the printer believes x̂. The nozzle stays where the
/// line is drawn, `m = (x₀, 0, r)` on top of a cylinder of radius r about the axis; the part
/// point under it at A is `q = R_t(−A) m`, and to first order in ε (Rodrigues' formula,
/// `t·m = x₀`, `t × m = (ε r, −r, −ε x₀)`) `q_x = x₀ − ε r sin A`. From A = −θ to +θ the line
/// runs `2 r sin θ ≈ L` and its X changes by `−ε L`: with d measured from the −X side,
/// `d_end − d_start = −ε L`. Eq. 5.7 corrects `A'_dir = R_z(α_{A,z}) A_dir` to the true
/// direction, so `α_{A,z} = ε = atan((d_start − d_end) / L)` (atan: the slope as an angle;
/// at 0.26° it differs from the slope by 10⁻⁶ relative). Measured from the +X side, or drawn
/// from the larger A, the sign flips: swap d_start and d_end.
pub fn a_z_rotation(d_start: f64, d_end: f64, line_length: f64) -> Result<(f64, f64), CalibError> {
    if !(line_length.is_finite() && line_length > 0.0) {
        return Err(CalibError::BadInput {
            what: "A orientation line length".to_string(),
            message: format!(
                "the line length {line_length} must be a positive number (mm; the seed's is {A_ORIENTATION_LINE})"
            ),
        });
    }
    let slope = (d_start - d_end) / line_length;
    Ok((slope, num::deg(num::atan(slope))))
}

/// §5.1.8: `z_d = z_shift − ab_z`.
pub fn wobble_z_d(z_shift: f64, ab_z: f64) -> f64 {
    z_shift - ab_z
}

/// Evaluate one probe computation.
pub fn evaluate(input: &ProbeInput) -> Result<ProbeOutput, CalibError> {
    Ok(match input {
        ProbeInput::APosError {
            radius,
            z_rotation_deg,
        } => {
            finite("A position error", &[*radius, *z_rotation_deg])?;
            ProbeOutput::APosError {
                e_y: a_pos_error(*radius, *z_rotation_deg),
            }
        }
        ProbeInput::APos {
            z0,
            y90,
            y_minus90,
            c_y,
            r_p,
        } => {
            finite("A position", &[*z0, *y90, *y_minus90, *c_y, *r_p])?;
            let (a, y_m) = a_pos(*z0, *y90, *y_minus90, *c_y, *r_p);
            ProbeOutput::APos { a_pos: a, y_m }
        }
        ProbeInput::ADir {
            z_x,
            d_zx,
            z_y,
            d_zy,
            y_x1,
            y_x2,
            d_yx,
        } => {
            finite(
                "A orientation",
                &[
                    z_x[0], z_x[1], z_y[0], z_y[1], y_x1[0], y_x1[1], y_x2[0], y_x2[1],
                ],
            )?;
            let (m_zx, m_zy, m_yx, d) = a_dir(*z_x, *d_zx, *z_y, *d_zy, *y_x1, *y_x2, *d_yx)?;
            ProbeOutput::ADir {
                m_zx,
                m_zy,
                m_yx,
                a_dir: d,
            }
        }
        ProbeInput::BPos { x_p, y_p, z } => {
            finite("B position", &[x_p[0], x_p[1], y_p[0], y_p[1], *z])?;
            ProbeOutput::BPos {
                b_pos: b_pos(*x_p, *y_p, *z),
            }
        }
        ProbeInput::BDir { p_z1, p_z2 } => {
            let all: Vec<f64> = p_z1
                .iter()
                .chain(p_z2.iter())
                .flat_map(|p| p.to_array())
                .collect();
            finite("B orientation", &all)?;
            let (p1, p2, d) = b_dir(p_z1, p_z2)?;
            ProbeOutput::BDir { p1, p2, b_dir: d }
        }
        ProbeInput::ZBias {
            z90,
            z_minus90,
            d_f,
        } => {
            finite("Z bias", z90)?;
            finite("Z bias", z_minus90)?;
            finite("Z bias d_f", &[*d_f])?;
            let (z_bias, z_shift) = z_bias(z90, z_minus90, *d_f)?;
            ProbeOutput::ZBias { z_bias, z_shift }
        }
        ProbeInput::AScaling { z1, z2, distance } => {
            finite("A scaling", &[*z1, *z2, *distance])?;
            ProbeOutput::AScaling {
                alpha_deg: a_scaling(*z1, *z2, *distance)?,
            }
        }
        ProbeInput::AStepsPerDegree {
            alpha_plus_deg,
            alpha_minus_deg,
            steps_per_deg,
        } => {
            finite(
                "A steps per degree",
                &[*alpha_plus_deg, *alpha_minus_deg, *steps_per_deg],
            )?;
            if !(*steps_per_deg > 0.0
                && alpha_plus_deg.abs() < 45.0
                && alpha_minus_deg.abs() < 45.0)
            {
                return Err(CalibError::BadInput {
                    what: "A steps per degree".to_string(),
                    message: format!(
                        "steps per degree {steps_per_deg} must be positive and each α (here {alpha_plus_deg}°, {alpha_minus_deg}°) a small angle error below 45°"
                    ),
                });
            }
            let (k, zero_shift_deg) = a_steps_per_degree(*alpha_plus_deg, *alpha_minus_deg);
            ProbeOutput::AStepsPerDegree {
                k,
                steps_per_deg: steps_per_deg / k,
                zero_shift_deg,
            }
        }
        ProbeInput::AOrientation {
            d_start,
            d_end,
            line_length,
        } => {
            finite("A orientation test", &[*d_start, *d_end, *line_length])?;
            let (slope, alpha_a_z_deg) = a_z_rotation(*d_start, *d_end, *line_length)?;
            ProbeOutput::AOrientation {
                slope,
                alpha_a_z_deg,
            }
        }
        ProbeInput::Wobble { z_shift, ab_z } => {
            finite("wobble", &[*z_shift, *ab_z])?;
            let z_d = wobble_z_d(*z_shift, *ab_z);
            let m = AbTable::new(
                "wobble",
                &["X", "Y", "Z", "A", "B"].map(String::from),
                AbTableParams {
                    z_wobble_mm: z_d,
                    ..AbTableParams::default()
                },
            )?;
            let correction = [-90.0, -45.0, 0.0, 45.0, 90.0]
                .iter()
                .map(|&a| [a, m.z_wobble(a)])
                .collect();
            ProbeOutput::Wobble { z_d, correction }
        }
    })
}

impl ProbeOutput {
    /// The human-readable result (what the CLI prints).
    pub fn to_text(&self) -> String {
        let v = |d: &DVec3| format!("({:.7}, {:.7}, {:.7})", d.x, d.y, d.z);
        match self {
            ProbeOutput::APosError { e_y } => {
                format!("E_y = {e_y:.6} mm ({:.1} µm) (Eq. 5.2)\n", e_y * 1000.0)
            }
            ProbeOutput::APos { a_pos, y_m } => {
                format!("y_m = {y_m:.6} mm\nA_pos = {} mm (Eq. 5.3)\na_axis {{{},{},{}}}\n", v(a_pos), a_pos.x, a_pos.y, a_pos.z)
            }
            ProbeOutput::ADir {
                m_zx,
                m_zy,
                m_yx,
                a_dir,
            } => format!(
                "m_zx = {m_zx:.7}\nm_zy = {m_zy:.7} (A levelness, {:.4}°)\nm_yx = {m_yx:.7}\nA_dir = {} (Eq. 5.4)\na_z_in_y {m_zy}\na_axis_dir {{{},{},{}}}\nnote: {EQ_5_4_NOTE}\n",
                num::deg(num::atan(*m_zy)),
                v(a_dir),
                a_dir.x,
                a_dir.y,
                a_dir.z
            ),
            ProbeOutput::BPos { b_pos } => format!(
                "B_pos = {} mm (Eq. 5.5)\nb_axis {{{},{},{}}}\n",
                v(b_pos),
                b_pos.x,
                b_pos.y,
                b_pos.z
            ),
            ProbeOutput::BDir { p1, p2, b_dir } => format!(
                "p1 = {} mm, p2 = {} mm\nB_dir = {} (Eq. 5.6, tilt from Z {:.4}°)\nb_axis_dir {{{},{},{}}}\n",
                v(p1),
                v(p2),
                v(b_dir),
                num::deg(num::angle_between(*b_dir, DVec3::Z)),
                b_dir.x,
                b_dir.y,
                b_dir.z
            ),
            ProbeOutput::ZBias { z_bias, z_shift } => format!(
                "z_bias = {z_bias:.6} mm (pass it to 'calibrate origin --bias x,y,{z_bias:.6}')\nz_shift = {z_shift:.6} mm (§5.1.6)\n"
            ),
            ProbeOutput::AScaling { alpha_deg } => format!(
                "α = {alpha_deg:.6}° (§5.1.7: the signed angle error of the A axis in this orientation)\n"
            ),
            ProbeOutput::AStepsPerDegree {
                k,
                steps_per_deg,
                zero_shift_deg,
            } => format!(
                "k = {k:.6} (the A axis turns k° per commanded degree, §5.1.7)
steps per degree = {steps_per_deg:.4} (set it in the firmware: M92 A{steps_per_deg:.4}, and in the homing scripts)
zero-point shift = {zero_shift_deg:.4}° (the symmetric part (α₊ + α₋)/2: redetermine the zero point after setting the scaling, §5.1.2)
"
            ),
            ProbeOutput::AOrientation {
                slope,
                alpha_a_z_deg,
            } => format!(
                "slope = {slope:.7} (d_start − d_end) / L
α_A,z = {alpha_a_z_deg:.6}° = atan(slope) (seed 004 §6.2.2, A axis orientation test; the sign: d from the object's −X side, the line's start at the smaller A; from the +X side swap d_start and d_end)
(pass it to 'calibrate origin --a-z-correction {alpha_a_z_deg:.6}': Eq. 5.7 turns A_dir by it about Z)
"
            ),
            ProbeOutput::Wobble { z_d, correction } => {
                let mut s = format!("z_d = {z_d:.6} mm (§5.1.8; set \"z_wobble_mm\": {z_d} in the machine JSON)\nEq. 5.1 correction:");
                for [a, c] in correction {
                    s.push_str(&format!(" A={a}°: {c:+.4} mm;"));
                }
                s.push('\n');
                s
            }
        }
    }
}
