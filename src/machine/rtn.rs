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
//! - `single` (1): R ∈ `rotation_range_deg` = [lo, hi] (the cables allow one turn; default
//!   [−170°, 170°], seed 002's prototype: "rotation 170°..180° and −170°..−180° were not
//!   reliable …: limiting A to −170°..170°: `M208 A-170 S1` and `M208 A170 S0`"). The target
//!   `R₀ = φ + c + rot_offset` is taken modulo 360° into [lo, hi]; inside the rotation shadow
//!   (hi, lo + 360°) the machine stops at the nearer end, as the firmware clamps a move to its
//!   `M208` limits (the nozzle then leans up to half the shadow, 10°, off the requested
//!   azimuth: reported as the dropped tool-axis angle); at equal distance, or when both ends
//!   are the same direction (a 360° range), the end nearer the previous value (`lo` without
//!   one, as Slicer4RTN's wrap into [−180°, 180°) followed by the firmware's clamp). When consecutive values jump by more than 180° the head must turn around the other
//!   way: [`Rtn::must_rotate_around`] tells the emitter to insert Slicer4RTN's lifted
//!   rotate-around move.
//! - `unlimited` (0, RotBot's slip ring): R is unwrapped continuously next to the previous value
//!   (the emitter may `G92` it back modulo 360° at a layer change).
//!
//! ## Nozzle misalignment (RotBot)
//! The tip sits off the rotation axis by `e_parallel` along the azimuth direction and
//! `e_perpendicular` 90° counter-clockwise from it; the offset turns with R:
//! `tip = (X, Y, Z) + R_z(φ)·(e_par, e_perp, 0)`, hence `(X, Y) = p_xy − R_z(φ)·(e_par, e_perp)`.

use glam::DVec3;

use super::angles::{unwrap_near, wrap180, Turn};
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
    /// `[lo, hi]` of the rotation with `revolution: single`, degrees: lo < hi,
    /// 180° < hi − lo ≤ 360° (seed 002's prototype: [−170, 170]; Slicer4RTN writes
    /// [−180, 180]). Ignored for `unlimited`.
    pub rotation_range_deg: [f64; 2],
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
            rotation_range_deg: [-170.0, 170.0],
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
    /// The unit XY direction of the tool axis whose rotation is the middle of the rotation
    /// shadow (single revolution; [`Machine::start_drift_deg`]).
    shadow_middle: glam::DVec2,
    /// `(sin α, cos α)` of the tilt, computed once (the same bits as each call's).
    tilt_sin_cos: (f64, f64),
}

impl Rtn {
    /// Build with axis letters `names` (X Y Z R).
    pub fn new(name: &str, names: &[String], params: RtnParams) -> Result<Rtn, MachineError> {
        require(
            name,
            params.tilt_deg > 0.0 && params.tilt_deg < 90.0,
            format!("tilt_deg = {} must be in (0, 90)", params.tilt_deg),
        )?;
        let [lo, hi] = params.rotation_range_deg;
        require(
            name,
            params.revolution == Revolution::Unlimited
                || (lo.is_finite() && hi.is_finite() && hi - lo > 180.0 && hi - lo <= 360.0),
            format!(
                "rotation_range_deg = [{lo}, {hi}] must be finite with 180 < max − min ≤ 360 (degrees; seed 002's RTN: [-170, 170])"
            ),
        )?;
        let r = match params.revolution {
            Revolution::Single => (lo, hi),
            Revolution::Unlimited => UNLIMITED,
        };
        let axis_set = AxisSet::linear_then_rotary(name, names, &[r]);
        // the tool axis' azimuth whose rotation is the shadow's middle m (range_window)
        let psi_m = num::rad((hi + lo + 360.0) / 2.0)
            - (num::rad(params.rot_convention.base_deg()) + num::rad(params.rot_offset_deg));
        let shadow_middle = glam::DVec2::new(num::cos(psi_m), num::sin(psi_m));
        let tilt = num::rad(params.tilt_deg);
        Ok(Rtn {
            axis_set,
            tilt_sin_cos: (num::sin(tilt), num::cos(tilt)),
            params,
            shadow_middle,
        })
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

    /// `single` revolution: the value of rotation `target` (degrees, any turn) within
    /// `rotation_range_deg` (see the module documentation: modulo 360°, the nearer end in the
    /// shadow, ties to the end nearer `previous`).
    pub fn in_range(&self, target: f64, previous: Option<f64>) -> f64 {
        let [lo, hi] = self.params.rotation_range_deg;
        let slack = super::LIMIT_SLACK_DEG;
        let base = lo + (target - lo).rem_euclid(360.0);
        let nearer = |a: f64, b: f64, da: f64, db: f64| {
            if (da - db).abs() > slack {
                if da < db {
                    a
                } else {
                    b
                }
            } else {
                match previous {
                    Some(pr) if (pr - a).abs() < (pr - b).abs() => a,
                    Some(_) => b,
                    None => a.min(b),
                }
            }
        };
        if base <= hi + slack {
            // a 360° range has both ends for the same direction
            if base - lo <= slack && lo + 360.0 <= hi + slack {
                return nearer(lo, hi, 0.0, 0.0);
            }
            return base.min(hi);
        }
        // the shadow (hi, lo + 360°)
        nearer(hi, lo, base - hi, lo + 360.0 - base)
    }

    /// `single` revolution: the target rotation `target` (degrees, any turn) written in the
    /// window `(m − 360°, m]`, m the middle of the rotation shadow `(hi, lo + 360°)`, which
    /// holds the range `[lo, hi]` with the shadow's upper half below it and its lower half
    /// above; and the range's clamp C(t) = `t.clamp(lo, hi)` in that window, which is
    /// [`Rtn::in_range`] away from the shadow's middle (the stop at the nearer end).
    fn range_window(&self, target: f64) -> (f64, f64) {
        let [lo, hi] = self.params.rotation_range_deg;
        let m = (hi + lo + 360.0) / 2.0;
        (m - (m - target).rem_euclid(360.0), m)
    }

    /// The bound on the rotation error (degrees) of [`Machine::interpolation_bound`] for a
    /// `single` revolution (its documentation): the ends' rotations `r0`, `r1`, the start's
    /// asked azimuth `psi0` and the slerp's turn (degrees), G = `g_deg`. `None` when an end does
    /// not realise the clamp of its target or the piece comes near the shadow's middle.
    fn clamped_error(&self, r0: f64, r1: f64, psi0: f64, turn: f64, g_deg: f64) -> Option<f64> {
        use super::bound;
        let [lo, hi] = self.params.rotation_range_deg;
        let (t0, m) = self.range_window(self.rotation_of(psi0));
        let t1 = t0 + turn;
        let (tmin, tmax) = (t0.min(t1) - g_deg, t0.max(t1) + g_deg);
        if !(tmin - bound::BRANCH_MARGIN_DEG > m - 360.0 && tmax + bound::BRANCH_MARGIN_DEG < m) {
            return None;
        }
        let (c0, c1) = (t0.clamp(lo, hi), t1.clamp(lo, hi));
        let matches = (r0 - c0).abs() <= bound::AZIMUTH_MATCH_DEG
            && (r1 - c1).abs() <= bound::AZIMUTH_MATCH_DEG;
        if !matches {
            return None;
        }
        // beyond one end all along: the nozzle stays stopped there, as the firmware's
        if tmin >= hi + bound::BRANCH_MARGIN_DEG || tmax <= lo - bound::BRANCH_MARGIN_DEG {
            return Some(0.0);
        }
        let kink = [lo, hi]
            .iter()
            .filter(|&&c| (t0 - c) * (t1 - c) < 0.0)
            .map(|&c| (c - t0).abs() * (t1 - c).abs() / (t1 - t0).abs())
            .fold(0.0, f64::max);
        Some(kink + g_deg)
    }

    /// The rotation value (degrees, not wrapped) for the tool-axis azimuth `phi_deg`.
    pub fn rotation_of(&self, phi_deg: f64) -> f64 {
        phi_deg + self.params.rot_convention.base_deg() + self.params.rot_offset_deg
    }

    /// The tool-axis azimuth (radians) of the rotation value `r` (degrees).
    fn azimuth_of(&self, r: f64) -> f64 {
        num::rad(r - self.params.rot_convention.base_deg() - self.params.rot_offset_deg)
    }

    /// The tool axis at azimuth `phi` (radians): `(sin α cos φ, sin α sin φ, cos α)`.
    fn axis_of(&self, phi: f64) -> DVec3 {
        self.axis_turned(&Turn::new(DVec3::Z, phi))
    }

    /// [`Rtn::axis_of`] with the azimuth's sine and cosine given (the tilt's computed once).
    fn axis_turned(&self, phi: &Turn) -> DVec3 {
        let (s, c) = self.tilt_sin_cos;
        DVec3::new(s * phi.cos(), s * phi.sin(), c)
    }

    /// The tip's offset from the rotation axis at azimuth `phi`: `R_z(φ)·(e_par, e_perp, 0)`.
    fn offset(&self, phi: &Turn) -> DVec3 {
        phi.about_z(DVec3::new(
            self.params.e_parallel_mm,
            self.params.e_perpendicular_mm,
            0.0,
        ))
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
            notes: vec![match self.params.revolution {
                Revolution::Single => format!(
                    "nozzle fixed at {}° and rotating about Z (single revolution, {}° to {}°; in the shadow between the ends the nozzle stops at the nearer end): conic layers at that angle",
                    self.params.tilt_deg,
                    self.params.rotation_range_deg[0],
                    self.params.rotation_range_deg[1]
                ),
                Revolution::Unlimited => format!(
                    "nozzle fixed at {}° and rotating about Z (unlimited revolution): conic layers at that angle",
                    self.params.tilt_deg
                ),
            }],
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
            (Revolution::Unlimited, None) => wrap180(target),
            (Revolution::Single, _) => self.in_range(target, prev),
        };
        let o = self.offset(&Turn::new(DVec3::Z, self.azimuth_of(r)));
        let axes = vec![p.x - o.x, p.y - o.y, p.z, r];
        self.axis_set.check_limits(axes, p)
    }
    fn forward(&self, axes: &[f64]) -> Result<(DVec3, DVec3), MachineError> {
        self.axis_set.check_count(4, axes)?;
        // one sine and cosine of the azimuth for the offset and the axis
        let phi = Turn::new(DVec3::Z, self.azimuth_of(axes[3]));
        Ok((
            DVec3::new(axes[0], axes[1], axes[2]) + self.offset(&phi),
            self.axis_turned(&phi),
        ))
    }
    fn realised_axis(&self, _p: DVec3, n: DVec3) -> DVec3 {
        let phi = if (n.x * n.x + n.y * n.y).sqrt() < POLE_EPSILON * n.length() {
            0.0
        } else {
            num::atan2(n.y, n.x)
        };
        match self.params.revolution {
            // within the range, or stopped at its nearer end
            Revolution::Single => {
                self.axis_of(self.azimuth_of(self.in_range(self.rotation_of(num::deg(phi)), None)))
            }
            Revolution::Unlimited => self.axis_of(phi),
        }
    }
    fn branch_freedom(&self, _p: DVec3, n: DVec3) -> f64 {
        if (n.x * n.x + n.y * n.y).sqrt() < POLE_EPSILON * n.length() {
            core::f64::consts::PI
        } else if self.params.revolution == Revolution::Single {
            // midway in the shadow (or a 360° range's seam) the previous value picks the end
            let t = self.rotation_of(num::deg(num::atan2(n.y, n.x)));
            let [lo, hi] = self.params.rotation_range_deg;
            let ends =
                [Some(lo), Some(hi)].map(|pr| self.axis_of(self.azimuth_of(self.in_range(t, pr))));
            num::angle_between(ends[0], ends[1])
        } else {
            0.0
        }
    }
    /// Rotary axes fixed ⇒ the tip is affine in the linear axes (law 3).
    fn linear_at_fixed_pose(&self) -> bool {
        true
    }
    /// Tip = X Y Z + R_z(φ)(e_par, e_perp, 0), axis on the cone of half-angle `tilt_deg` at
    /// azimuth φ. With the rotation interpolated linearly (Δφ radians) the offset leaves its
    /// chord by the sagitta bound `|e| Δφ²/8` ([`super::bound`] Lemmas 1–2); the intended tip is
    /// on the chord whatever the intended rotation (the linear axes make up the offset at each
    /// end). The intended axis is the cone's at the rotation `C(T(s))`: T(s) the target
    /// `rotation_of(ψ(s))`, ψ(s) the azimuth of the slerp (within G of its linear
    /// interpolation, Lemma 4), and C the range's clamp ([`Rtn::range_clamp`]; the identity for
    /// unlimited revolutions). C is 1-Lipschitz, so the intended rotation is within G of
    /// `C(T_lin(s))`, and the firmware's, linear between `C(T₀)` and `C(T₁)`, leaves
    /// `C(T_lin(s))` by at most the kink `|c − T₀||T₁ − c|/|T₁ − T₀|` where T_lin crosses a range
    /// end c (0 elsewhere). Where the whole piece, widened by G, lies beyond one end (the nozzle
    /// stopped there in the shadow) the intended rotation is that end, as the firmware's: no G.
    /// Two axes of the cone whose rotations differ by E are at most `sin(tilt)·E` apart (the
    /// small circle's arc is longer than the great circle's). Only when both ends realise
    /// `C(T)` of their asked azimuth, the firmware turns the short way, and the piece stays
    /// clear of the shadow's middle (where the nozzle's stop switches end): else sample.
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
        let g = bound::slerp_azimuth_deviation(n0, n1, DVec3::Z, DVec3::truncate)?;
        let g_deg = num::deg(g) + 2.0 * bound::AZIMUTH_MATCH_DEG;
        let (psi0, psi1) = (
            num::deg(num::atan2(n0.y, n0.x)),
            num::deg(num::atan2(n1.y, n1.x)),
        );
        let turn = wrap180(psi1 - psi0);
        let az_error = match self.params.revolution {
            Revolution::Unlimited => {
                let matches = wrap180(a0[3] - self.rotation_of(psi0)).abs()
                    <= bound::AZIMUTH_MATCH_DEG
                    && wrap180(a1[3] - self.rotation_of(psi1)).abs() <= bound::AZIMUTH_MATCH_DEG
                    && ((a1[3] - a0[3]) - turn).abs() <= 2.0 * bound::AZIMUTH_MATCH_DEG;
                if !matches {
                    return None;
                }
                g_deg
            }
            Revolution::Single => self.clamped_error(a0[3], a1[3], psi0, turn, g_deg)?,
        };
        let e = self
            .params
            .e_parallel_mm
            .hypot(self.params.e_perpendicular_mm);
        let dphi = num::rad(a1[3] - a0[3]);
        // the same bits as sin(rad(tilt)), computed once
        let sin_t = self.tilt_sin_cos.0.abs();
        Some((
            e * bound::chord_deviation(dphi * dphi) + bound::ROUND_TRIP_SLACK_MM,
            sin_t * az_error + bound::ROUND_TRIP_SLACK_DEG,
        ))
    }
    /// The rotation is the target `rotation_of(ψ)`, ψ = atan2(n_y, n_x), unwrapped next to
    /// the previous value (unlimited) or taken into the range (single: [`Rtn::in_range`],
    /// 1-Lipschitz in the target modulo 360° except at the shadow's middle, where the nozzle's
    /// stop switches end); it is held only where `|n_xy| < POLE_EPSILON`. A turn of the request
    /// by at most `turn` moves ψ by at most `d = turn/(ρ − turn)` ([`super::drift`], ρ =
    /// |n_xy|), clear of the pole; two axes of the cone whose rotations differ by `d` are at
    /// most `sin(tilt)·d ≤ d` apart. For a single revolution only where the drift (plus the
    /// range's tie slack) cannot reach the shadow's middle.
    fn start_drift_deg(
        &self,
        _p: DVec3,
        n: DVec3,
        _axes: &[f64],
        turn: f64,
        _tip_mm: f64,
    ) -> Option<f64> {
        use super::drift;
        let xy = n.truncate();
        let d = drift::azimuth_drift(xy, n.length(), turn)?;
        if self.params.revolution == Revolution::Single {
            let reach = d + num::rad(2.0 * super::LIMIT_SLACK_DEG);
            if !drift::clear_of(xy, self.shadow_middle, reach) {
                return None;
            }
        }
        Some(num::deg(d) + drift::DRIFT_SLACK_DEG)
    }
    fn workspace(&self) -> Workspace {
        Workspace::desktop(180.0)
    }
}
