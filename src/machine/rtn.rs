//! `rtn-slicer4rtn` and `rotbot`: the rotating tilted nozzle (seed 002). Axes X Y Z R, with the
//! rotation letter R = `A` (Slicer4RTN `--rot-gcode`) or `U` (RotBot).
//!
//! ## Convention
//! The nozzle has a fixed tilt α (45°) from vertical and turns about the vertical line through
//! its tip. φ is the azimuth of the tool axis (tip → nozzle body) in XY, measured
//! counter-clockwise from +X: on an outward cone it is the azimuth of the point about the cone's
//! centre, on an inward cone that + 180°. The nozzle opening faces the other way, φ + 180°.
//! The rotation value is
//!
//! `R = φ + c + rot_offset`, with `c` set by `rot_convention`:
//! - `"slicer4rtn"` (the default): `c = 180°`, so `R − rot_offset` is the azimuth the nozzle
//!   opening faces. This is Slicer4RTN 0.6.0's formula (`atan2` of the point about the cone
//!   centre, + 180° for its inside mode, + 180° + `--rot-offset`); with its default
//!   `rot_offset = −90°`, R = 0° puts the nozzle body in front (−Y) and R = ±180° has the
//!   opening looking forward, as seed 002 describes its RTN.
//! - `"rotbot"`: `c = 0°`, so `R − rot_offset` is the azimuth of the tool axis. This is RotBot's
//!   back-transformation (ZHAW Transform scripts: U = atan2(y, x) of the point for outward
//!   cones, 180° more for inward ones) with `rot_offset = 0`. It is also the formula of
//!   warpslice's files before `rot_convention` existed.
//!
//! Only the azimuth of a requested axis is realised:
//! `realised n = (sin α cos φ, sin α sin φ, cos α)`; with `|n_xy| = 0` (planar moves) φ is held
//! from the previous point (0 without one).
//!
//! ## Revolutions (`--rot-revolv`)
//! - `single` (1): R ∈ [−180°, 180°] (the cables allow one turn). When consecutive points cross
//!   ±180° the head must turn around the other way: [`Rtn::must_rotate_around`] tells the
//!   emitter to insert Slicer4RTN's lifted rotate-around move.
//! - `unlimited` (0, RotBot's slip ring): R is unwrapped continuously next to the previous value
//!   (the emitter may `G92` it back modulo 360° at a layer change).
//!
//! ## Nozzle misalignment (RotBot)
//! The tip sits off the rotation axis by `e_parallel` along the azimuth direction and
//! `e_perpendicular` 90° counter-clockwise from it; the offset turns with R:
//! `tip = (X, Y, Z) + R_z(φ)·(e_par, e_perp, 0)`, hence `(X, Y) = p_xy − R_z(φ)·(e_par, e_perp)`.

use glam::DVec3;

use super::angles::{rot_z, unwrap_near, wrap180};
use super::{
    require, AxisSet, Capabilities, InverseResult, Machine, MachineError, Workspace, POLE_EPSILON,
    UNLIMITED,
};
use crate::num;

/// How far the rotation may turn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Revolution {
    /// One turn, R ∈ [−180°, 180°].
    Single,
    /// Unlimited turns, continuous unwrap.
    Unlimited,
}

/// Which reference's formula turns the tool axis' azimuth φ into a rotation value
/// (JSON `"rot_convention"`, shared by the `rtn` and `pax` kinds): `R = φ + c + rot_offset`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RotConvention {
    /// Slicer4RTN 0.6.0: `c = 180°` (`R − rot_offset` is the azimuth the nozzle opening faces).
    #[default]
    Slicer4rtn,
    /// RotBot's Transform scripts: `c = 0°` (`R − rot_offset` is the azimuth of the tool axis).
    Rotbot,
}

impl RotConvention {
    /// The constant `c` of `R = φ + c + rot_offset`, degrees.
    pub fn base_deg(self) -> f64 {
        match self {
            RotConvention::Slicer4rtn => 180.0,
            RotConvention::Rotbot => 0.0,
        }
    }
}

/// Parameters of [`Rtn`] (JSON `"kind": "rtn"`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct RtnParams {
    /// Fixed nozzle tilt α from vertical, degrees.
    pub tilt_deg: f64,
    /// Which formula gives the rotation value (see the module documentation).
    pub rot_convention: RotConvention,
    /// Slicer4RTN's `--rot-offset` (or RotBot's, 0): `R = φ + c + rot_offset`, degrees.
    pub rot_offset_deg: f64,
    /// Single or unlimited revolutions.
    pub revolution: Revolution,
    /// Tip offset along the azimuth direction, mm (RotBot calibration).
    pub e_parallel_mm: f64,
    /// Tip offset 90° counter-clockwise from the azimuth direction, mm.
    pub e_perpendicular_mm: f64,
}

impl Default for RtnParams {
    fn default() -> Self {
        RtnParams {
            tilt_deg: 45.0,
            rot_convention: RotConvention::Slicer4rtn,
            rot_offset_deg: -90.0,
            revolution: Revolution::Single,
            e_parallel_mm: 0.0,
            e_perpendicular_mm: 0.0,
        }
    }
}

/// The rotating tilted nozzle.
#[derive(Clone, Debug)]
pub struct Rtn {
    axis_set: AxisSet,
    params: RtnParams,
}

impl Rtn {
    /// Build with axis letters `names` (X Y Z R).
    pub fn new(name: &str, names: &[String], params: RtnParams) -> Result<Rtn, MachineError> {
        require(
            name,
            params.tilt_deg > 0.0 && params.tilt_deg < 90.0,
            format!("tilt_deg = {} must be in (0, 90)", params.tilt_deg),
        )?;
        let r = match params.revolution {
            Revolution::Single => (-180.0, 180.0),
            Revolution::Unlimited => UNLIMITED,
        };
        let axis_set = AxisSet::linear_then_rotary(name, names, &[r]);
        Ok(Rtn { axis_set, params })
    }

    /// The parameters.
    pub fn params(&self) -> &RtnParams {
        &self.params
    }

    /// In `single` mode, whether going from rotation `from` to `to` (degrees) crosses the ±180°
    /// seam the short way, so the head must turn around the long way (the emitter lifts the
    /// nozzle and rotates around, Slicer4RTN's move at radius + 1 mm).
    pub fn must_rotate_around(&self, from: f64, to: f64) -> bool {
        self.params.revolution == Revolution::Single && (to - from).abs() > 180.0
    }

    /// The rotation value (degrees, not wrapped) for the tool-axis azimuth `phi_deg`.
    pub fn rotation_of(&self, phi_deg: f64) -> f64 {
        phi_deg + self.params.rot_convention.base_deg() + self.params.rot_offset_deg
    }

    /// The tool-axis azimuth (radians) of the rotation value `r` (degrees).
    fn azimuth_of(&self, r: f64) -> f64 {
        num::rad(r - self.params.rot_convention.base_deg() - self.params.rot_offset_deg)
    }

    fn axis_of(&self, phi: f64) -> DVec3 {
        let t = num::rad(self.params.tilt_deg);
        DVec3::new(
            num::sin(t) * num::cos(phi),
            num::sin(t) * num::sin(phi),
            num::cos(t),
        )
    }

    fn offset(&self, phi: f64) -> DVec3 {
        rot_z(
            DVec3::new(
                self.params.e_parallel_mm,
                self.params.e_perpendicular_mm,
                0.0,
            ),
            phi,
        )
    }
}

impl super::spec::Kind for RtnParams {
    fn default_axis_names(&self) -> &'static [&'static str] {
        &["X", "Y", "Z", "A"]
    }
    fn build(&self, name: &str, axis_names: &[String]) -> Result<Box<dyn Machine>, MachineError> {
        Ok(Box::new(Rtn::new(name, axis_names, self.clone())?))
    }
}

impl Machine for Rtn {
    fn axis_set(&self) -> &AxisSet {
        &self.axis_set
    }
    /// The whole hotend is tilted by the fixed tilt and turned about +Z to the azimuth φ of
    /// the tool axis: R_z(φ)·R_y(tilt).
    fn head_frame(&self, axes: &[f64]) -> Option<glam::DMat3> {
        let phi = self.azimuth_of(*axes.get(3)?);
        Some(super::head::turned_frame(
            phi,
            num::rad(self.params.tilt_deg),
        ))
    }
    fn capabilities(&self) -> Capabilities {
        Capabilities {
            summary: "rotating tilted nozzle (fixed tilt, rotary axis about Z)".into(),
            max_tilt_deg: Some(self.params.tilt_deg),
            fixed_tilt_deg: Some(self.params.tilt_deg),
            moving_bed: false,
            warps: vec!["conic"],
            notes: vec![format!(
                "nozzle fixed at {}° and rotating about Z ({:?} revolution): conic layers at that angle",
                self.params.tilt_deg,
                format!("{:?}", self.params.revolution).to_lowercase()
            )],
        }
    }
    fn inverse(&self, p: DVec3, n: DVec3, previous: Option<&[f64]>) -> InverseResult {
        let n = self.axis_set.check_input(p, n)?;
        let prev = previous.and_then(|a| a.get(3).copied());
        let target = if (n.x * n.x + n.y * n.y).sqrt() < POLE_EPSILON {
            prev.unwrap_or_else(|| self.rotation_of(0.0))
        } else {
            self.rotation_of(num::deg(num::atan2(n.y, n.x)))
        };
        let r = match (self.params.revolution, prev) {
            (Revolution::Unlimited, Some(pr)) => unwrap_near(target, pr),
            (Revolution::Single, Some(pr)) => {
                // Exactly on the seam (+180° ≡ −180°): keep the side of the previous value.
                let w = wrap180(target);
                if w == 180.0 && pr < 0.0 {
                    -180.0
                } else {
                    w
                }
            }
            _ => wrap180(target),
        };
        let phi = self.azimuth_of(r);
        let o = self.offset(phi);
        let axes = vec![p.x - o.x, p.y - o.y, p.z, r];
        self.axis_set.check_limits(axes, p)
    }
    fn forward(&self, axes: &[f64]) -> Result<(DVec3, DVec3), MachineError> {
        self.axis_set.check_count(4, axes)?;
        let phi = self.azimuth_of(axes[3]);
        Ok((
            DVec3::new(axes[0], axes[1], axes[2]) + self.offset(phi),
            self.axis_of(phi),
        ))
    }
    fn realised_axis(&self, _p: DVec3, n: DVec3) -> DVec3 {
        let phi = if (n.x * n.x + n.y * n.y).sqrt() < POLE_EPSILON * n.length() {
            0.0
        } else {
            num::atan2(n.y, n.x)
        };
        self.axis_of(phi)
    }
    fn branch_freedom(&self, _p: DVec3, n: DVec3) -> f64 {
        if (n.x * n.x + n.y * n.y).sqrt() < POLE_EPSILON * n.length() {
            core::f64::consts::PI
        } else {
            0.0
        }
    }
    /// Rotary axes fixed ⇒ the tip is affine in the linear axes (law 3).
    fn linear_at_fixed_pose(&self) -> bool {
        true
    }
    fn workspace(&self) -> Workspace {
        Workspace::desktop(180.0)
    }
}
