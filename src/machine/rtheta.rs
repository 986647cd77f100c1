//! `core-r-theta`: a polar printer (Core R-Theta, cited in seeds 000 and 001) with a tilting
//! nozzle. The bed turns by C about the vertical through the output origin; the head moves
//! radially (X) on the line y = 0 and vertically (Z) and tilts by B in the XZ plane.
//! Axes X C Z B.
//!
//! ## Convention
//! C is a right-hand (counter-clockwise seen from above) rotation of the bed, degrees:
//! `q = R_z(C)·p` is the tip in the machine frame and must lie on y = 0, so
//! `C = −atan2(p_y, p_x)` and `q_x = |p_xy|`; the other branch `(C + 180°, q_x = −|p_xy|)` is
//! taken when it keeps C nearer the previous value (C is unwrapped, unlimited), so a path
//! through the centre does not spin the bed. In the machine frame the tool axis is
//! `m = R_z(C)·n`; only its XZ part can be realised (the Y component is dropped):
//! `B = atan2(m_x, m_z)` (B > 0 leans the nozzle body towards +X, as [`super::bhead`]).
//! The pivot sits `L` (pivot-to-tip, 43 mm default) up the nozzle:
//!
//! ```text
//! inverse: X = q_x + L sin B,  Z = p_z + L cos B − L
//! forward: q = (X − L sin B, 0, Z − L cos B + L),  p = R_z(−C)·q,  n = R_z(−C)·(sin B, 0, cos B)
//! ```
//! At the centre (|p_xy| = 0) C is held.

use glam::DVec3;

use super::angles::{nearer_half_turn, rot_z, wrap180};
use super::{
    require, AxisLimit, AxisSet, Capabilities, InverseResult, Machine, MachineError, Workspace,
    POLE_EPSILON, UNLIMITED,
};
use crate::num;

/// Parameters of [`RTheta`] (JSON `"kind": "r-theta"`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct RThetaParams {
    /// Pivot-to-tip distance L, mm.
    pub pivot_to_tip_mm: f64,
    /// Largest |B|, degrees.
    pub max_tilt_deg: f64,
    /// Largest |X| (bed radius reach), mm.
    pub max_radius_mm: f64,
}

impl Default for RThetaParams {
    fn default() -> Self {
        RThetaParams {
            pivot_to_tip_mm: 43.0,
            max_tilt_deg: 90.0,
            max_radius_mm: f64::INFINITY,
        }
    }
}

/// The polar machine.
#[derive(Clone, Debug)]
pub struct RTheta {
    axis_set: AxisSet,
    params: RThetaParams,
}

impl RTheta {
    /// Build with axis letters `names` (X C Z B).
    pub fn new(name: &str, names: &[String], params: RThetaParams) -> Result<RTheta, MachineError> {
        let (r, t) = (params.max_radius_mm, params.max_tilt_deg);
        require(
            name,
            params.pivot_to_tip_mm.is_finite() && t > 0.0 && r > 0.0,
            "pivot_to_tip_mm must be finite, max_tilt_deg and max_radius_mm positive",
        )?;
        let [x, c, z, b] = names else {
            return Err(MachineError::WrongAxisCount {
                machine: name.to_string(),
                expected: 4,
                got: names.len(),
            });
        };
        let (c_min, c_max) = UNLIMITED;
        let limits = vec![
            AxisLimit {
                name: x.clone(),
                rotary: false,
                min: -r,
                max: r,
            },
            AxisLimit::rotary(c, c_min, c_max),
            AxisLimit::linear(z),
            AxisLimit::rotary(b, -t, t),
        ];
        let axis_set = AxisSet::new(name, limits);
        Ok(RTheta { axis_set, params })
    }

    /// (C degrees, q_x) for `p`, branch chosen next to `prev_c`.
    fn c_of(p: DVec3, prev_c: Option<f64>) -> (f64, f64) {
        let rho = (p.x * p.x + p.y * p.y).sqrt();
        if rho < POLE_EPSILON {
            return (prev_c.unwrap_or(0.0), 0.0);
        }
        let c1 = -num::deg(num::atan2(p.y, p.x));
        match prev_c {
            None => (wrap180(c1), rho),
            Some(pc) => {
                let (c, s) = nearer_half_turn(c1, pc);
                (c, s * rho)
            }
        }
    }

    /// B (degrees) of `n` with the bed at C (degrees), holding `held` when undefined.
    fn b_of(n: DVec3, c: f64, held: f64) -> f64 {
        let m = rot_z(n, num::rad(c));
        if (m.x * m.x + m.z * m.z).sqrt() < POLE_EPSILON {
            held
        } else {
            num::deg(num::atan2(m.x, m.z))
        }
    }
}

impl super::spec::Kind for RThetaParams {
    fn default_axis_names(&self) -> &'static [&'static str] {
        &["X", "C", "Z", "B"]
    }
    fn build(&self, name: &str, axis_names: &[String]) -> Result<Box<dyn Machine>, MachineError> {
        Ok(Box::new(RTheta::new(name, axis_names, self.clone())?))
    }
}

impl Machine for RTheta {
    fn axis_set(&self) -> &AxisSet {
        &self.axis_set
    }
    /// (R, 0, Z): the head moves along the radius, the bed turns.
    fn head_position(&self, axes: &[f64]) -> DVec3 {
        let a = |i: usize| axes.get(i).copied().unwrap_or(0.0);
        DVec3::new(a(0), 0.0, a(2))
    }

    /// X is the radius and C the turntable angle, written raw: each letter one motor, not the firmware's polar kinematics.
    fn axis_drive(&self) -> super::config::AxisDrive {
        super::config::AxisDrive::RawPolar
    }

    fn capabilities(&self) -> Capabilities {
        Capabilities {
            summary: "polar printer (turning bed, radial head) with a tilting nozzle".into(),
            max_tilt_deg: Some(self.params.max_tilt_deg),
            fixed_tilt_deg: None,
            moving_bed: true,
            warps: super::all_warps(),
            notes: vec![format!(
                "polar printer, tilt up to {}°, reach r ≤ {} mm; place the part off the centre (--place)",
                self.params.max_tilt_deg, self.params.max_radius_mm
            )],
        }
    }
    fn inverse(&self, p: DVec3, n: DVec3, previous: Option<&[f64]>) -> InverseResult {
        let n = self.axis_set.check_input(p, n)?;
        let (c, qx) = RTheta::c_of(p, previous.and_then(|a| a.get(1).copied()));
        let b = RTheta::b_of(
            n,
            c,
            previous.and_then(|a| a.get(3).copied()).unwrap_or(0.0),
        );
        let l = self.params.pivot_to_tip_mm;
        let br = num::rad(b);
        let axes = vec![qx + l * num::sin(br), c, p.z + l * num::cos(br) - l, b];
        self.axis_set.check_limits(axes, p)
    }
    fn forward(&self, axes: &[f64]) -> Result<(DVec3, DVec3), MachineError> {
        self.axis_set.check_count(4, axes)?;
        let l = self.params.pivot_to_tip_mm;
        let br = num::rad(axes[3]);
        let (s, co) = (num::sin(br), num::cos(br));
        let q = DVec3::new(axes[0] - l * s, 0.0, axes[2] - l * co + l);
        let c = num::rad(axes[1]);
        Ok((rot_z(q, -c), rot_z(DVec3::new(s, 0.0, co), -c)))
    }
    fn realised_axis(&self, p: DVec3, n: DVec3) -> DVec3 {
        let (c, _) = RTheta::c_of(p, None);
        let br = num::rad(RTheta::b_of(n / n.length(), c, 0.0));
        rot_z(DVec3::new(num::sin(br), 0.0, num::cos(br)), -num::rad(c))
    }
    fn branch_freedom(&self, p: DVec3, n: DVec3) -> f64 {
        let (c, _) = RTheta::c_of(p, None);
        let m = rot_z(n / n.length(), num::rad(c));
        if (p.x * p.x + p.y * p.y).sqrt() < POLE_EPSILON
            || (m.x * m.x + m.z * m.z).sqrt() < POLE_EPSILON
        {
            core::f64::consts::PI
        } else {
            0.0
        }
    }
    /// The head does not turn about its tool axis in the machine: its x axis is the machine's
    /// +X ([`super::head::fixed_head_frame`]).
    fn head_frame(&self, axes: &[f64]) -> Option<glam::DMat3> {
        super::head::fixed_head_frame(self, axes)
    }
    /// The tip computed once for the frame too ([`super::head::fixed_head_pose`]).
    fn pose(&self, axes: &[f64]) -> Result<(DVec3, DVec3, Option<glam::DMat3>), MachineError> {
        super::head::fixed_head_pose(self, axes)
    }
    /// Rotary axes fixed ⇒ the tip is affine in the linear axes (law 3).
    fn linear_at_fixed_pose(&self) -> bool {
        true
    }
    fn workspace(&self) -> Workspace {
        // A square inside the reach: |p_xy| + L ≤ max_radius.
        let h = ((self.params.max_radius_mm - self.params.pivot_to_tip_mm.abs()) / 2f64.sqrt())
            .clamp(1.0, 100.0);
        Workspace {
            min: DVec3::new(-h, -h, 0.0),
            max: DVec3::new(h, h, 200.0),
            max_tilt_deg: self.params.max_tilt_deg.min(90.0),
        }
    }
}
