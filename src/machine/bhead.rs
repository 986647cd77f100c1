//! `fullcontrol-prusa-b`: a print head tilting about the machine Y axis (seed 000, FullControl's
//! Prusa MK3S+ B-axis modification). Axes X Y Z B.
//!
//! ## Convention (ours, proven by `forward`)
//! B is a right-hand rotation of the head about +Y, in degrees. The tool axis (tip → nozzle) is
//! `n(B) = R_y(B)·e_z = (sin B, 0, cos B)`: B > 0 leans the nozzle body towards +X. Only the
//! XZ-plane part of a requested axis can be realised: `B = atan2(n_x, n_z)`; the Y component is
//! dropped (the angle between `n` and the realised axis is what the pipeline reports).
//!
//! The pivot sits `r` (pivot-to-tip, 46 mm in FullControl's guide) up the nozzle from the tip:
//! `pivot = p + r·n(B)`. The machine position is that of the tip at B = 0, i.e. the pivot minus
//! `r·e_z`:
//!
//! ```text
//! X = p_x + r sin B,   Y = p_y,   Z = p_z + r cos B − r          (inverse)
//! p = (X − r sin B, Y, Z − r cos B + r),  n = (sin B, 0, cos B)   (forward)
//! ```
//! so B = 0 gives X Z = tip. (Seed 000's Eqs. 5–6 measure b from another reference direction.)
//!
//! ## Collision clip (seed 000 §4.3.1)
//! `|B| ≤ b₀ + (90° − b₀)·min(max(z, 0)/z_clip, 1)` with `z` the tip height, b₀ = 18°,
//! z_clip = 50 mm: near the bed the head may tilt little, from 50 mm up to ±90°.

use glam::DVec3;

use super::{
    require, AxisSet, Capabilities, InverseResult, Machine, MachineError, Workspace, POLE_EPSILON,
};
use crate::num;

/// Parameters of [`BHead`] (JSON `"kind": "b-head"`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct BHeadParams {
    /// Pivot-to-tip distance r, mm.
    pub pivot_to_tip_mm: f64,
    /// Apply the collision clip.
    pub clip: bool,
    /// Largest |B| at the bed (b₀), degrees.
    pub clip_b0_deg: f64,
    /// Height from which |B| may reach 90°, mm.
    pub clip_z_mm: f64,
    /// Travel of B: [−b_limit, b_limit], degrees.
    pub b_limit_deg: f64,
}

impl Default for BHeadParams {
    fn default() -> Self {
        BHeadParams {
            pivot_to_tip_mm: 46.0,
            clip: true,
            clip_b0_deg: 18.0,
            clip_z_mm: 50.0,
            b_limit_deg: 90.0,
        }
    }
}

/// The tilting-head machine.
#[derive(Clone, Debug)]
pub struct BHead {
    axis_set: AxisSet,
    params: BHeadParams,
}

impl BHead {
    /// Build with axis letters `names` (X Y Z B).
    pub fn new(name: &str, names: &[String], params: BHeadParams) -> Result<BHead, MachineError> {
        require(
            name,
            params.pivot_to_tip_mm.is_finite()
                && params.clip_z_mm > 0.0
                && params.b_limit_deg > 0.0,
            "pivot_to_tip_mm must be finite, clip_z_mm and b_limit_deg positive",
        )?;
        let b = params.b_limit_deg;
        let axis_set = AxisSet::linear_then_rotary(name, names, &[(-b, b)]);
        Ok(BHead { axis_set, params })
    }

    /// The largest |B| allowed at tip height `z` (degrees), seed 000 §4.3.1.
    pub fn clip_limit_deg(&self, z: f64) -> f64 {
        let b0 = self.params.clip_b0_deg;
        b0 + (90.0 - b0) * (z.max(0.0) / self.params.clip_z_mm).min(1.0)
    }

    /// B (degrees) for `n` at tip height `z`, holding `held` when n has no XZ component.
    fn b_of(&self, n: DVec3, z: f64, held: f64) -> f64 {
        let len = (n.x * n.x + n.z * n.z).sqrt();
        let mut b = if len < POLE_EPSILON {
            held
        } else {
            num::deg(num::atan2(n.x, n.z))
        };
        if self.params.clip {
            let lim = self.clip_limit_deg(z);
            b = b.clamp(-lim, lim);
        }
        b
    }
}

impl super::spec::Kind for BHeadParams {
    fn default_axis_names(&self) -> &'static [&'static str] {
        &["X", "Y", "Z", "B"]
    }
    fn build(&self, name: &str, axis_names: &[String]) -> Result<Box<dyn Machine>, MachineError> {
        Ok(Box::new(BHead::new(name, axis_names, self.clone())?))
    }
}

impl Machine for BHead {
    fn axis_set(&self) -> &AxisSet {
        &self.axis_set
    }
    /// The head turns about +Y by B: R_y(B).
    fn head_frame(&self, axes: &[f64]) -> Option<glam::DMat3> {
        Some(super::head::turned_frame(0.0, num::rad(*axes.get(3)?)))
    }
    fn capabilities(&self) -> Capabilities {
        {
            let mut notes = vec![format!(
                "head tilts about Y only (B ±{}°), pivot {} mm above the tip",
                self.params.b_limit_deg, self.params.pivot_to_tip_mm
            )];
            if self.params.clip {
                notes.push(format!(
                    "below z = {} mm the tilt is clipped to {}° (bed clearance)",
                    self.params.clip_z_mm, self.params.clip_b0_deg
                ));
            }
            Capabilities {
                summary: "head tilting about Y (B axis)".into(),
                max_tilt_deg: Some(self.params.b_limit_deg),
                fixed_tilt_deg: None,
                moving_bed: false,
                // tilts in XZ only: the warps whose tool axis stays in XZ (belt toward ±X)
                warps: vec!["curved", "tilted", "belt"],
                notes,
            }
        }
    }
    fn inverse(&self, p: DVec3, n: DVec3, previous: Option<&[f64]>) -> InverseResult {
        let n = self.axis_set.check_input(p, n)?;
        let held = previous.and_then(|a| a.get(3).copied()).unwrap_or(0.0);
        let b = self.b_of(n, p.z, held);
        let r = self.params.pivot_to_tip_mm;
        let br = num::rad(b);
        let axes = vec![p.x + r * num::sin(br), p.y, p.z + r * num::cos(br) - r, b];
        self.axis_set.check_limits(axes, p)
    }
    fn forward(&self, axes: &[f64]) -> Result<(DVec3, DVec3), MachineError> {
        self.axis_set.check_count(4, axes)?;
        let r = self.params.pivot_to_tip_mm;
        let br = num::rad(axes[3]);
        let (s, c) = (num::sin(br), num::cos(br));
        Ok((
            DVec3::new(axes[0] - r * s, axes[1], axes[2] - r * c + r),
            DVec3::new(s, 0.0, c),
        ))
    }
    fn realised_axis(&self, p: DVec3, n: DVec3) -> DVec3 {
        let br = num::rad(self.b_of(n, p.z, 0.0));
        DVec3::new(num::sin(br), 0.0, num::cos(br))
    }
    fn branch_freedom(&self, _p: DVec3, n: DVec3) -> f64 {
        if (n.x * n.x + n.z * n.z).sqrt() < POLE_EPSILON * n.length() {
            core::f64::consts::FRAC_PI_2
        } else {
            0.0
        }
    }
    /// Rotary axes fixed ⇒ the tip is affine in the linear axes (law 3).
    fn linear_at_fixed_pose(&self) -> bool {
        true
    }
    /// Tip = (X − r sin B, Y, Z − r cos B + r), axis (sin B, 0, cos B), r = `pivot_to_tip_mm`.
    /// With B interpolated linearly (ΔB radians) the pivot offset leaves its chord by
    /// `r ΔB²/8` ([`super::bound`] Lemmas 1–2); the intended B is the XZ azimuth ψ(s) of the
    /// slerp, within G of the linear B (Lemma 4), and both axes lie on the XZ great circle, so
    /// they are G apart. Only when both ends realise their asked B and the whole piece stays
    /// inside the B limit and the clip (whose limit grows with z, so its least is at the lower
    /// end): else sample.
    fn interpolation_bound(
        &self,
        from: super::PieceEnd,
        to: super::PieceEnd,
    ) -> Option<(f64, f64)> {
        use super::bound;
        let (a0, a1, n0, n1) = (from.0, to.0, from.2, to.2);
        if !bound::usable(from, to, 4) {
            return None;
        }
        let g = bound::slerp_azimuth_deviation(n0, n1, DVec3::Y, |n| glam::DVec2::new(n.z, n.x))?;
        let (b0, b1) = (a0[3], a1[3]);
        let matches = (b0 - num::deg(num::atan2(n0.x, n0.z))).abs() <= bound::AZIMUTH_MATCH_DEG
            && (b1 - num::deg(num::atan2(n1.x, n1.z))).abs() <= bound::AZIMUTH_MATCH_DEG
            && (b1 - b0).abs() <= 90.0;
        if !matches {
            return None;
        }
        let g_deg = num::deg(g) + 2.0 * bound::AZIMUTH_MATCH_DEG;
        let mut limit = self.params.b_limit_deg;
        if self.params.clip {
            limit = limit.min(self.clip_limit_deg(from.1.z.min(to.1.z)));
        }
        if b0.abs().max(b1.abs()) + g_deg + bound::BRANCH_MARGIN_DEG > limit {
            return None;
        }
        let db = num::rad(b1 - b0);
        Some((
            self.params.pivot_to_tip_mm.abs() * bound::chord_deviation(db * db)
                + bound::ROUND_TRIP_SLACK_MM,
            g_deg + bound::ROUND_TRIP_SLACK_DEG,
        ))
    }
    /// B is the clamp of the azimuth ψ = atan2(n_x, n_z) about Y to ±`clip_limit_deg(z)`
    /// (with the clip) and is held only where `|n_xz| < POLE_EPSILON`. A turn of the request by
    /// at most `turn` moves ψ by at most `turn/(ρ − turn)` ([`super::drift`], ρ = |n_xz|),
    /// clear of the pole; the clip's limit moves by at most `|90° − b₀|/z_clip` per mm of tip;
    /// a clamp is 1-Lipschitz; and the realised axes `(sin B, 0, cos B)` are |ΔB| apart. So the
    /// bound is the sum, where the drift cannot reach atan2's cut at ψ = ±180° (the clamp
    /// would send B from one clip end to the other) and B stays within its travel.
    fn start_drift_deg(
        &self,
        p: DVec3,
        n: DVec3,
        axes: &[f64],
        turn: f64,
        tip_mm: f64,
    ) -> Option<f64> {
        use super::drift;
        let xz = glam::DVec2::new(n.z, n.x);
        let d = drift::azimuth_drift(xz, n.length(), turn)?;
        if !drift::clear_of(xz, glam::DVec2::new(-1.0, 0.0), d) || !p.is_finite() {
            return None;
        }
        let mut d_deg = num::deg(d);
        if self.params.clip {
            d_deg += (90.0 - self.params.clip_b0_deg).abs() / self.params.clip_z_mm * tip_mm;
        }
        let b = *axes.get(3)?;
        // false for a NaN: no bound
        let within = b.abs() + d_deg <= self.params.b_limit_deg;
        if !within {
            return None;
        }
        Some(d_deg + drift::DRIFT_SLACK_DEG)
    }
    fn workspace(&self) -> Workspace {
        Workspace::desktop(if self.params.clip {
            180.0
        } else {
            self.params.b_limit_deg.min(180.0)
        })
    }
}
