//! `pax-5axis`: a 5-axis head (seed 002 `--axis=5`, Penta Axis): rotation A about the vertical
//! plus tilt B of the nozzle. Axes X Y Z A B.
//!
//! ## Convention
//! The tool axis (tip → nozzle body) is
//! `n(A, B) = (sin B cos φ, sin B sin φ, cos B)` with `A = φ + c + rot_offset`, the rotation
//! convention of the rotating tilted nozzle ([`super::rtn::RotConvention`]): with the default
//! `"slicer4rtn"` (c = 180°) and Slicer4RTN's default `rot_offset = −90°` this is Slicer4RTN
//! 0.6.0's `--axis=5` output (A = azimuth of the point about the cone centre + 90°, B = the cone
//! angle, on an outside cone): A = 0° with B > 0 leans the nozzle body to the front (−Y).
//! B is signed: `(A, B)` and `(A + 180°, −B)` give the same
//! axis; the branch nearest the previous A is taken so A stays continuous through the vertical
//! (A is unwrapped, unlimited). Without a previous pose B ≥ 0 and A ∈ (−180°, 180°].
//! Vertical n: B = 0, A held.
//!
//! The pivot sits `L` (pivot-to-tip) up the nozzle: `pivot = p + L·n`; the machine position is
//! the tip at B = 0: `(X, Y, Z) = p + L·n − L·e_z`; forward `p = (X, Y, Z) + L·e_z − L·n`.

use glam::DVec3;

use super::angles::{nearer_half_turn, tilt, wrap180};
use super::rtn::RotConvention;
use super::{
    require, AxisSet, Capabilities, InverseResult, Machine, MachineError, Workspace, POLE_EPSILON,
    UNLIMITED,
};
use crate::num;

/// Parameters of [`Pax`] (JSON `"kind": "pax"`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct PaxParams {
    /// Pivot-to-tip distance L, mm (0 when the tip lies on both rotation axes).
    pub pivot_to_tip_mm: f64,
    /// Which formula gives A (see [`RotConvention`]).
    pub rot_convention: RotConvention,
    /// Slicer4RTN's `--rot-offset`: `A = φ + c + rot_offset`, degrees.
    pub rot_offset_deg: f64,
    /// Largest |B|, degrees.
    pub max_tilt_deg: f64,
}

impl Default for PaxParams {
    fn default() -> Self {
        PaxParams {
            pivot_to_tip_mm: 0.0,
            rot_convention: RotConvention::Slicer4rtn,
            rot_offset_deg: -90.0,
            max_tilt_deg: 90.0,
        }
    }
}

/// The 5-axis head.
#[derive(Clone, Debug)]
pub struct Pax {
    axis_set: AxisSet,
    params: PaxParams,
}

impl Pax {
    /// Build with axis letters `names` (X Y Z A B).
    pub fn new(name: &str, names: &[String], params: PaxParams) -> Result<Pax, MachineError> {
        let t = params.max_tilt_deg;
        require(
            name,
            params.pivot_to_tip_mm.is_finite() && t > 0.0 && t <= 180.0,
            "pivot_to_tip_mm must be finite and max_tilt_deg in (0, 180]",
        )?;
        let axis_set = AxisSet::linear_then_rotary(name, names, &[UNLIMITED, (-t, t)]);
        Ok(Pax { axis_set, params })
    }

    /// `c + rot_offset`: A = φ + this, degrees.
    fn a_offset(&self) -> f64 {
        self.params.rot_convention.base_deg() + self.params.rot_offset_deg
    }

    fn axis_of(&self, a: f64, b: f64) -> DVec3 {
        let phi = num::rad(a - self.a_offset());
        let b = num::rad(b);
        DVec3::new(
            num::sin(b) * num::cos(phi),
            num::sin(b) * num::sin(phi),
            num::cos(b),
        )
    }
}

impl super::spec::Kind for PaxParams {
    fn default_axis_names(&self) -> &'static [&'static str] {
        &["X", "Y", "Z", "A", "B"]
    }
    fn build(&self, name: &str, axis_names: &[String]) -> Result<Box<dyn Machine>, MachineError> {
        Ok(Box::new(Pax::new(name, axis_names, self.clone())?))
    }
}

impl Machine for Pax {
    fn axis_set(&self) -> &AxisSet {
        &self.axis_set
    }
    /// The head turns by A about +Z, then tilts by B: R_z(φ)·R_y(B) with φ = A − offset
    /// (the azimuth of [`Pax::axis_of`]).
    fn head_frame(&self, axes: &[f64]) -> Option<glam::DMat3> {
        let (a, b) = (*axes.get(3)?, *axes.get(4)?);
        Some(super::head::turned_frame(
            num::rad(a - self.a_offset()),
            num::rad(b),
        ))
    }
    fn capabilities(&self) -> Capabilities {
        Capabilities {
            summary: "5-axis head".into(),
            max_tilt_deg: Some(self.params.max_tilt_deg),
            fixed_tilt_deg: None,
            moving_bed: false,
            warps: super::all_warps(),
            notes: vec![format!(
                "5-axis head, tilt up to {}°",
                self.params.max_tilt_deg
            )],
        }
    }
    fn inverse(&self, p: DVec3, n: DVec3, previous: Option<&[f64]>) -> InverseResult {
        let n = self.axis_set.check_input(p, n)?;
        let prev_a = previous.and_then(|a| a.get(3).copied());
        let t = num::deg(tilt(n));
        let (a, b) = if (n.x * n.x + n.y * n.y).sqrt() < POLE_EPSILON {
            // Straight up (B = 0) or straight down (B = 180°, refused by the limit).
            (prev_a.unwrap_or(0.0), t)
        } else {
            let a1 = num::deg(num::atan2(n.y, n.x)) + self.a_offset();
            match prev_a {
                None => (wrap180(a1), t),
                Some(pa) => {
                    let (a, s) = nearer_half_turn(a1, pa);
                    (a, s * t)
                }
            }
        };
        let l = self.params.pivot_to_tip_mm;
        let q = p + self.axis_of(a, b) * l - DVec3::Z * l;
        let axes = vec![q.x, q.y, q.z, a, b];
        self.axis_set.check_limits(axes, p)
    }
    fn forward(&self, axes: &[f64]) -> Result<(DVec3, DVec3), MachineError> {
        self.axis_set.check_count(5, axes)?;
        let n = self.axis_of(axes[3], axes[4]);
        let l = self.params.pivot_to_tip_mm;
        Ok((
            DVec3::new(axes[0], axes[1], axes[2]) + DVec3::Z * l - n * l,
            n,
        ))
    }
    /// Rotary axes fixed ⇒ the tip is affine in the linear axes (law 3).
    fn linear_at_fixed_pose(&self) -> bool {
        true
    }
    /// Every axis within the tilt limit is realised exactly (A and signed B are its azimuth and
    /// tilt; a vertical axis whatever A), and a bound is given only inside that cap.
    fn realises_requests(&self) -> bool {
        true
    }
    /// Tip = X Y Z + l·(e_z − u(A, B)) with u the unit axis of azimuth A − offset and tilt B,
    /// l = `pivot_to_tip_mm`. With A and B interpolated linearly (totals ΔA, ΔB, radians) u is
    /// a vector in spherical coordinates turned linearly ([`super::bound`] Lemma 5): the
    /// firmware's tip leaves the intended straight line by `l·|u(s) − chord| ≤ l A/8` (Lemma 1,
    /// A = Lemma 5's bound of |u''|) and its axis the slerp by Lemma 5's chord D, an angle of
    /// `2 asin(D/2)`; the realised axis is the asked one ([`Machine::realises_requests`]). Only
    /// when the slerp stays within `max_tilt_deg` ≤ 90° (geodesic convexity): else sample.
    fn interpolation_bound(
        &self,
        from: super::PieceEnd,
        to: super::PieceEnd,
    ) -> Option<(f64, f64)> {
        use super::bound;
        let (a0, a1) = (from.0, to.0);
        if !bound::usable(from, to, 5)
            || !bound::arc_in_cap(from.2, to.2, DVec3::Z, self.params.max_tilt_deg)
        {
            return None;
        }
        let (chord, acc) = bound::spherical_deviation(
            num::rad(a0[4]),
            num::rad(a1[4]),
            num::rad(a1[3] - a0[3]),
            bound::angle(from.2, to.2),
        )?;
        let l = self.params.pivot_to_tip_mm.abs();
        Some((
            l * bound::chord_deviation(acc) + bound::ROUND_TRIP_SLACK_MM,
            bound::angle_of_chord(chord) + bound::ROUND_TRIP_SLACK_DEG,
        ))
    }
    fn workspace(&self) -> Workspace {
        Workspace::desktop(self.params.max_tilt_deg)
    }
}
