//! `lathe-a`: a vertical nozzle over a mandrel turning about a horizontal axis parallel to X
//! (the cylindrical warp of seed 002 "printed on a horizontal rotating rod (like a lathe)").
//! Axes X Y Z A.
//!
//! ## Convention
//! The mandrel axis is the line through `c = (0, axis_y, axis_z)` along +X (output frame = part
//! frame at A = 0). A turns the part by a right-hand rotation about +X, in degrees:
//! `q = c + R_x(A)·(p − c)` is the tip in the machine frame, and the nozzle is vertical, so
//! `R_x(A)·n = e_z` ⇒ `A = atan2(n_y, n_z)` (the X component of n cannot be realised and is
//! dropped: realised n = R_x(−A)·e_z = (0, sin A, cos A)). A is unwrapped continuously next to
//! the previous value (unlimited); with n ∥ X, A is held.
//!
//! ```text
//! inverse: A = atan2(n_y, n_z),  (X, Y, Z) = c + R_x(A)(p − c)
//! forward: p = c + R_x(−A)((X, Y, Z) − c),  n = (0, sin A, cos A)
//! ```

use glam::DVec3;

use super::angles::{rot_x, unwrap_near, wrap180};
use super::{
    check_count, check_input, check_limits, AxisLimit, Machine, MachineError, Workspace,
    POLE_EPSILON,
};
use crate::num;

/// Parameters of [`Lathe`] (JSON `"kind": "lathe-a"`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct LatheParams {
    /// Y of the mandrel axis, mm.
    pub axis_y_mm: f64,
    /// Z of the mandrel axis, mm.
    pub axis_z_mm: f64,
}

impl Default for LatheParams {
    fn default() -> Self {
        LatheParams {
            axis_y_mm: 0.0,
            axis_z_mm: 0.0,
        }
    }
}

/// The rotating-mandrel machine.
#[derive(Clone, Debug)]
pub struct Lathe {
    name: String,
    limits: Vec<AxisLimit>,
    c: DVec3,
}

impl Lathe {
    /// Build with axis letters `names` (X Y Z A).
    pub fn new(name: &str, names: &[String], params: LatheParams) -> Result<Lathe, MachineError> {
        let c = DVec3::new(0.0, params.axis_y_mm, params.axis_z_mm);
        if !c.is_finite() {
            return Err(MachineError::BadSpec {
                machine: name.to_string(),
                message: "axis_y_mm/axis_z_mm must be finite".into(),
            });
        }
        let mut limits: Vec<AxisLimit> = names[..3].iter().map(|n| AxisLimit::linear(n)).collect();
        limits.push(AxisLimit::rotary(
            &names[3],
            f64::NEG_INFINITY,
            f64::INFINITY,
        ));
        Ok(Lathe {
            name: name.to_string(),
            limits,
            c,
        })
    }
}

impl Machine for Lathe {
    fn name(&self) -> &str {
        &self.name
    }
    fn limits(&self) -> &[AxisLimit] {
        &self.limits
    }
    fn inverse(
        &self,
        p: DVec3,
        n: DVec3,
        previous: Option<&[f64]>,
    ) -> Result<Vec<f64>, MachineError> {
        let n = check_input(&self.name, p, n)?;
        let prev = previous.and_then(|a| a.get(3).copied());
        let a = if (n.y * n.y + n.z * n.z).sqrt() < POLE_EPSILON {
            prev.unwrap_or(0.0)
        } else {
            let t = num::deg(num::atan2(n.y, n.z));
            match prev {
                Some(pr) => unwrap_near(t, pr),
                None => wrap180(t),
            }
        };
        let q = self.c + rot_x(p - self.c, num::rad(a));
        let axes = vec![q.x, q.y, q.z, a];
        check_limits(&self.name, &self.limits, &axes, p)?;
        Ok(axes)
    }
    fn forward(&self, axes: &[f64]) -> Result<(DVec3, DVec3), MachineError> {
        check_count(&self.name, 4, axes)?;
        let a = num::rad(axes[3]);
        let p = self.c + rot_x(DVec3::new(axes[0], axes[1], axes[2]) - self.c, -a);
        Ok((p, DVec3::new(0.0, num::sin(a), num::cos(a))))
    }
    fn realised_axis(&self, _p: DVec3, n: DVec3) -> DVec3 {
        let len = (n.y * n.y + n.z * n.z).sqrt();
        if len < POLE_EPSILON * n.length() {
            DVec3::Z
        } else {
            DVec3::new(0.0, n.y / len, n.z / len)
        }
    }
    fn branch_freedom(&self, _p: DVec3, n: DVec3) -> f64 {
        if (n.y * n.y + n.z * n.z).sqrt() < POLE_EPSILON * n.length() {
            core::f64::consts::PI
        } else {
            0.0
        }
    }
    fn workspace(&self) -> Workspace {
        Workspace {
            min: DVec3::new(-100.0, self.c.y - 40.0, self.c.z - 40.0),
            max: DVec3::new(100.0, self.c.y + 40.0, self.c.z + 40.0),
            max_tilt_deg: 180.0,
        }
    }
}
