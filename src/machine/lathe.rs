//! `lathe-a`: a vertical nozzle over a mandrel turning about a horizontal axis parallel to X
//! (the cylindrical warp of seed 002 "printed on a horizontal rotating rod (like a lathe)").
//! Axes X Z A (default), or X Y Z A with `with_y`.
//!
//! ## Convention
//! The mandrel axis is the line through `c = (0, axis_y, axis_z)` along +X (output frame = part
//! frame at A = 0). A turns the part by a right-hand rotation about +X, in degrees:
//! `q = c + R_x(A)·(p − c)` is the tip in the machine frame; the nozzle is vertical.
//!
//! **X Z A** (no Y axis): the tip must be on the top line y = axis_y, so A is set by the
//! position: `A = atan2((p − c)_y, (p − c)_z)`, `X = p_x`, `Z = axis_z + |(p − c)_yz|`, and the
//! realised tool axis is the radial direction `R_x(−A)·e_z = (0, sin A, cos A)` — what a layer
//! of the cylindrical warp asks for. On the mandrel axis itself A is taken from n as below.
//!
//! **X Y Z A** (`with_y`): `R_x(A)·n = e_z` ⇒ `A = atan2(n_y, n_z)` (the X component of n is
//! dropped), `(X, Y, Z) = q`.
//!
//! A is unwrapped continuously next to the previous value (unlimited); with it undefined
//! (n ∥ X, or p on the axis) it is held.
//!
//! ```text
//! forward: p = c + R_x(−A)((X, Y or axis_y, Z) − c),  n = (0, sin A, cos A)
//! ```

use glam::DVec3;

use super::angles::{rot_x, unwrap_near, wrap180};
use super::{
    require, AxisSet, Capabilities, InverseResult, Machine, MachineError, Workspace, POLE_EPSILON,
    UNLIMITED,
};
use crate::job::Job;
use crate::num;
use crate::warp::WarpSpec;

/// Largest distance between a cylindrical job's layer axis and the mandrel axis, mm.
pub const MANDREL_AXIS_TOLERANCE: f64 = 0.01;

/// Parameters of [`Lathe`] (JSON `"kind": "lathe-a"`).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct LatheParams {
    /// Y of the mandrel axis, mm.
    pub axis_y_mm: f64,
    /// Z of the mandrel axis, mm.
    pub axis_z_mm: f64,
    /// The machine also has a Y axis (axes X Y Z A instead of X Z A).
    pub with_y: bool,
}

/// The rotating-mandrel machine.
#[derive(Clone, Debug)]
pub struct Lathe {
    axis_set: AxisSet,
    c: DVec3,
    with_y: bool,
}

/// A (degrees) making the yz vector `v` point up, `None` when it is zero.
fn up_angle(v: DVec3) -> Option<f64> {
    if (v.y * v.y + v.z * v.z).sqrt() < POLE_EPSILON {
        None
    } else {
        Some(num::deg(num::atan2(v.y, v.z)))
    }
}

impl Lathe {
    /// Build with axis letters `names` (X Z A, or X Y Z A with `with_y`).
    pub fn new(name: &str, names: &[String], params: LatheParams) -> Result<Lathe, MachineError> {
        let c = DVec3::new(0.0, params.axis_y_mm, params.axis_z_mm);
        require(name, c.is_finite(), "axis_y_mm/axis_z_mm must be finite")?;
        Ok(Lathe {
            axis_set: AxisSet::linear_then_rotary(name, names, &[UNLIMITED]),
            c,
            with_y: params.with_y,
        })
    }

    /// The A (degrees, wrapped) the machine takes for (p, n) without a previous pose.
    fn target(&self, p: DVec3, n: DVec3) -> Option<f64> {
        if self.with_y {
            up_angle(n)
        } else {
            up_angle(p - self.c).or_else(|| up_angle(n))
        }
    }
}

impl super::spec::Kind for LatheParams {
    fn default_axis_names(&self) -> &'static [&'static str] {
        if self.with_y {
            &["X", "Y", "Z", "A"]
        } else {
            &["X", "Z", "A"]
        }
    }
    fn build(&self, name: &str, axis_names: &[String]) -> Result<Box<dyn Machine>, MachineError> {
        Ok(Box::new(Lathe::new(name, axis_names, self.clone())?))
    }
}

impl Machine for Lathe {
    fn axis_set(&self) -> &AxisSet {
        &self.axis_set
    }
    /// A cylindrical job must wind its layers round the mandrel: the warp's axis (model frame,
    /// moved to the output by `model_to_output`) must be this machine's axis within
    /// [`MANDREL_AXIS_TOLERANCE`].
    fn check_job(&self, job: &Job, model_to_output: DVec3) -> Result<(), MachineError> {
        let WarpSpec::Cylindrical { axis, .. } = &job.warp.spec else {
            return Ok(());
        };
        let warp = [axis[0] + model_to_output.y, axis[1] + model_to_output.z];
        let mandrel = [self.c.y, self.c.z];
        if (warp[0] - mandrel[0]).hypot(warp[1] - mandrel[1]) > MANDREL_AXIS_TOLERANCE {
            return Err(MachineError::MandrelMismatch {
                machine: self.name().to_string(),
                warp,
                mandrel,
            });
        }
        Ok(())
    }

    /// X Y Z of the head (X 0 Z without a Y axis); the mandrel turns the part.
    fn head_position(&self, axes: &[f64]) -> DVec3 {
        let a = |i: usize| axes.get(i).copied().unwrap_or(0.0);
        if self.with_y {
            DVec3::new(a(0), a(1), a(2))
        } else {
            DVec3::new(a(0), 0.0, a(1))
        }
    }

    fn capabilities(&self) -> Capabilities {
        Capabilities {
            summary: "rotating mandrel about X (A axis)".into(),
            max_tilt_deg: None,
            fixed_tilt_deg: None,
            moving_bed: true,
            warps: super::all_warps(),
            notes: vec![format!(
                "rotating mandrel about X (A axis) at y = {}, z = {} mm; pair it with the cylindrical warp",
                self.c.y, self.c.z
            )],
        }
    }
    fn inverse(&self, p: DVec3, n: DVec3, previous: Option<&[f64]>) -> InverseResult {
        let n = self.axis_set.check_input(p, n)?;
        let prev = previous.and_then(|a| a.last().copied());
        let a = match (self.target(p, n), prev) {
            (None, pr) => pr.unwrap_or(0.0),
            (Some(t), Some(pr)) => unwrap_near(t, pr),
            (Some(t), None) => wrap180(t),
        };
        let q = self.c + rot_x(p - self.c, num::rad(a));
        let axes = if self.with_y {
            vec![q.x, q.y, q.z, a]
        } else {
            // q_y = axis_y by the choice of A (exactly, up to rounding).
            vec![q.x, q.z, a]
        };
        self.axis_set.check_limits(axes, p)
    }
    fn forward(&self, axes: &[f64]) -> Result<(DVec3, DVec3), MachineError> {
        self.axis_set.check_count(self.limits().len(), axes)?;
        let (q, a) = if self.with_y {
            (DVec3::new(axes[0], axes[1], axes[2]), axes[3])
        } else {
            (DVec3::new(axes[0], self.c.y, axes[1]), axes[2])
        };
        let a = num::rad(a);
        let p = self.c + rot_x(q - self.c, -a);
        Ok((p, DVec3::new(0.0, num::sin(a), num::cos(a))))
    }
    fn realised_axis(&self, p: DVec3, n: DVec3) -> DVec3 {
        let a = num::rad(self.target(p, n).unwrap_or(0.0));
        DVec3::new(0.0, num::sin(a), num::cos(a))
    }
    fn branch_freedom(&self, p: DVec3, n: DVec3) -> f64 {
        if self.target(p, n).is_none() {
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
        Workspace {
            min: DVec3::new(-100.0, self.c.y - 40.0, self.c.z - 40.0),
            max: DVec3::new(100.0, self.c.y + 40.0, self.c.z + 40.0),
            max_tilt_deg: 180.0,
        }
    }
}
