//! `pax-5axis`: a 5-axis head (seed 002 `--axis=5`, Penta Axis): rotation A about the vertical
//! plus tilt B of the nozzle. Axes X Y Z A B.
//!
//! ## Convention
//! The tool axis (tip → nozzle) is
//! `n(A, B) = (sin B cos φ, sin B sin φ, cos B)` with `φ = A − rot_offset` (Slicer4RTN's
//! `--rot-offset`, 0° here unless set). B is signed: `(A, B)` and `(A + 180°, −B)` give the same
//! axis; the branch nearest the previous A is taken so A stays continuous through the vertical
//! (A is unwrapped, unlimited). Without a previous pose B ≥ 0 and A ∈ (−180°, 180°].
//! Vertical n: B = 0, A held.
//!
//! The pivot sits `L` (pivot-to-tip) up the nozzle: `pivot = p + L·n`; the machine position is
//! the tip at B = 0: `(X, Y, Z) = p + L·n − L·e_z`; forward `p = (X, Y, Z) + L·e_z − L·n`.

use glam::DVec3;

use super::angles::{tilt, unwrap_near, wrap180};
use super::{
    check_count, check_input, check_limits, AxisLimit, Machine, MachineError, Workspace,
    POLE_EPSILON,
};
use crate::num;

/// Parameters of [`Pax`] (JSON `"kind": "pax"`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct PaxParams {
    /// Pivot-to-tip distance L, mm (0 when the tip lies on both rotation axes).
    pub pivot_to_tip_mm: f64,
    /// Added to the azimuth to give A, degrees.
    pub rot_offset_deg: f64,
    /// Largest |B|, degrees.
    pub max_tilt_deg: f64,
}

impl Default for PaxParams {
    fn default() -> Self {
        PaxParams {
            pivot_to_tip_mm: 0.0,
            rot_offset_deg: 0.0,
            max_tilt_deg: 90.0,
        }
    }
}

/// The 5-axis head.
#[derive(Clone, Debug)]
pub struct Pax {
    name: String,
    limits: Vec<AxisLimit>,
    params: PaxParams,
}

impl Pax {
    /// Build with axis letters `names` (X Y Z A B).
    pub fn new(name: &str, names: &[String], params: PaxParams) -> Result<Pax, MachineError> {
        if !(params.pivot_to_tip_mm.is_finite()
            && params.max_tilt_deg > 0.0
            && params.max_tilt_deg <= 180.0)
        {
            return Err(MachineError::BadSpec {
                machine: name.to_string(),
                message: "pivot_to_tip_mm must be finite and max_tilt_deg in (0, 180]".into(),
            });
        }
        let mut limits: Vec<AxisLimit> = names[..3].iter().map(|n| AxisLimit::linear(n)).collect();
        limits.push(AxisLimit::rotary(
            &names[3],
            f64::NEG_INFINITY,
            f64::INFINITY,
        ));
        limits.push(AxisLimit::rotary(
            &names[4],
            -params.max_tilt_deg,
            params.max_tilt_deg,
        ));
        Ok(Pax {
            name: name.to_string(),
            limits,
            params,
        })
    }

    fn axis_of(&self, a: f64, b: f64) -> DVec3 {
        let phi = num::rad(a - self.params.rot_offset_deg);
        let b = num::rad(b);
        DVec3::new(
            num::sin(b) * num::cos(phi),
            num::sin(b) * num::sin(phi),
            num::cos(b),
        )
    }
}

impl Machine for Pax {
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
        let prev_a = previous.and_then(|a| a.get(3).copied());
        let t = num::deg(tilt(n));
        let (a, b) = if (n.x * n.x + n.y * n.y).sqrt() < POLE_EPSILON {
            // Straight up (B = 0) or straight down (B = 180°, refused by the limit).
            (prev_a.unwrap_or(0.0), t)
        } else {
            let a1 = num::deg(num::atan2(n.y, n.x)) + self.params.rot_offset_deg;
            match prev_a {
                None => (wrap180(a1), t),
                Some(pa) => {
                    let c1 = unwrap_near(a1, pa);
                    let c2 = unwrap_near(a1 + 180.0, pa);
                    if (c2 - pa).abs() < (c1 - pa).abs() - 1e-9 {
                        (c2, -t)
                    } else {
                        (c1, t)
                    }
                }
            }
        };
        let l = self.params.pivot_to_tip_mm;
        let q = p + self.axis_of(a, b) * l - DVec3::Z * l;
        let axes = vec![q.x, q.y, q.z, a, b];
        check_limits(&self.name, &self.limits, &axes, p)?;
        Ok(axes)
    }
    fn forward(&self, axes: &[f64]) -> Result<(DVec3, DVec3), MachineError> {
        check_count(&self.name, 5, axes)?;
        let n = self.axis_of(axes[3], axes[4]);
        let l = self.params.pivot_to_tip_mm;
        Ok((
            DVec3::new(axes[0], axes[1], axes[2]) + DVec3::Z * l - n * l,
            n,
        ))
    }
    fn workspace(&self) -> Workspace {
        Workspace {
            min: DVec3::new(-100.0, -100.0, 0.0),
            max: DVec3::new(100.0, 100.0, 200.0),
            max_tilt_deg: self.params.max_tilt_deg,
        }
    }
}
