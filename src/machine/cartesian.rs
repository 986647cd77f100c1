//! `cartesian`: a plain 3-axis printer. X Y Z = tip; the nozzle is always vertical.
//!
//! `forward(X, Y, Z) = ((X, Y, Z), +Z)`, `realised_axis = +Z`. With `max_tilt_deg` set, a tool
//! axis tilted more than that from vertical is refused (`UnreachableOrientation`): a vertical
//! nozzle following a surface steeper than its cone gouges the part (seed 001 §4.7).

use glam::DVec3;

use super::{AxisSet, Capabilities, InverseResult, Machine, MachineError, Workspace};
use crate::num;

/// Parameters of [`Cartesian`] (JSON `"kind": "cartesian"`).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct CartesianParams {
    /// Refuse tool axes tilted more than this from vertical (degrees); `None` accepts all.
    pub max_tilt_deg: Option<f64>,
}

/// The 3-axis machine.
#[derive(Clone, Debug)]
pub struct Cartesian {
    axis_set: AxisSet,
    params: CartesianParams,
}

impl Cartesian {
    /// Build with axis letters `names` (3 of them).
    pub fn new(name: &str, names: &[String], params: CartesianParams) -> Cartesian {
        Cartesian {
            axis_set: AxisSet::linear(name, names),
            params,
        }
    }
}

impl super::spec::Kind for CartesianParams {
    fn default_axis_names(&self) -> &'static [&'static str] {
        &["X", "Y", "Z"]
    }
    fn build(&self, name: &str, axis_names: &[String]) -> Result<Box<dyn Machine>, MachineError> {
        Ok(Box::new(Cartesian::new(name, axis_names, self.clone())))
    }
}

impl Machine for Cartesian {
    fn axis_set(&self) -> &AxisSet {
        &self.axis_set
    }
    /// `forward` is the identity: with the letters X Y Z, the slicer's own words.
    fn axes_are_output_xyz(&self) -> bool {
        self.axis_set
            .limits()
            .iter()
            .map(|l| l.name.as_str())
            .eq(["X", "Y", "Z"])
    }
    /// The head never turns: the identity.
    fn head_frame(&self, _axes: &[f64]) -> Option<glam::DMat3> {
        Some(glam::DMat3::IDENTITY)
    }
    fn capabilities(&self) -> Capabilities {
        Capabilities {
            summary: "3 axes: the nozzle stays vertical".into(),
            max_tilt_deg: self.params.max_tilt_deg,
            fixed_tilt_deg: None,
            moving_bed: false,
            warps: super::all_warps(),
            notes: vec!["3 axes: the nozzle stays vertical; steep layers need a nozzle whose cone clears them".into()],
        }
    }
    /// The firmware's path is the intended one (tip = axes, axis +Z): only the rounding of
    /// the two interpolations differs ([`super::bound::ROUND_TRIP_SLACK_MM`]), and the tool
    /// axis not at all. With a `max_tilt_deg` of at most 90° every slerped axis is accepted too
    /// (geodesic convexity, [`super::bound::arc_in_cap`]); above it, sample.
    fn interpolation_bound(
        &self,
        from: super::PieceEnd,
        to: super::PieceEnd,
    ) -> Option<(f64, f64)> {
        use super::bound;
        let tilt_ok = self
            .params
            .max_tilt_deg
            .is_none_or(|max| bound::arc_in_cap(from.2, to.2, DVec3::Z, max));
        (tilt_ok && bound::usable(from, to, 3)).then_some((bound::ROUND_TRIP_SLACK_MM, 0.0))
    }
    fn inverse(&self, p: DVec3, n: DVec3, _previous: Option<&[f64]>) -> InverseResult {
        let n = self.axis_set.check_input(p, n)?;
        if let Some(max) = self.params.max_tilt_deg {
            let t = num::deg(super::angles::tilt(n));
            if t > max + super::LIMIT_SLACK_DEG {
                return Err(self.axis_set.unreachable(
                    p,
                    n,
                    format!(
                        "the slope {t:.3}° exceeds max_tilt_deg = {max}° of this 3-axis machine"
                    ),
                ));
            }
        }
        let axes = vec![p.x, p.y, p.z];
        self.axis_set.check_limits(axes, p)
    }
    fn forward(&self, axes: &[f64]) -> Result<(DVec3, DVec3), MachineError> {
        self.axis_set.check_count(3, axes)?;
        Ok((DVec3::new(axes[0], axes[1], axes[2]), DVec3::Z))
    }
    fn realised_axis(&self, _p: DVec3, _n: DVec3) -> DVec3 {
        DVec3::Z
    }
    /// No rotary axis: the nozzle points along +Z at every pose.
    fn fixed_tool_axis(&self) -> Option<DVec3> {
        Some(DVec3::Z)
    }
    /// Rotary axes fixed ⇒ the tip is affine in the linear axes (law 3).
    fn linear_at_fixed_pose(&self) -> bool {
        true
    }
    fn workspace(&self) -> Workspace {
        Workspace::desktop(self.params.max_tilt_deg.unwrap_or(180.0))
    }
}
