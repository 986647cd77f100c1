//! `ratrig-vcore3-3z`: the triple-Z tilting bed of seed 001 (Cocco et al., SCF '25). Axes
//! X Y Z U V = x, y, z₀, z₁, z₂. Closed form both ways (seed 001 §3, Eqs. 1–23), no iteration.
//!
//! ## Frames and parameters (seed 001 §3)
//! Bed space (^): the part/output frame; the nozzle touches its origin when all axes are 0.
//! World space: origin at ball 0 when homed, `e₃` up. Balls `b̂ᵢ` (bed space, all at the same
//! z = `ball_z`) slide on rails of direction `dᵢ = (cos σᵢ, sin σᵢ, 0)`; each ball stays in the
//! vertical plane `nᵢ·b + kᵢ = 0`, `nᵢ = e₃ × dᵢ`, `kᵢ = −nᵢ·b̄ᵢ`, `b̄ᵢ = b̂ᵢ − b̂₀` (Eq. 3),
//! at height `(bᵢ)_z = −zᵢ` (Eq. 1). Bed space → world is a rotation R and a translation.
//!
//! ## The tool axis: Rᵀe₃, not the mirrored bed normal (a correction to seed 001)
//! The nozzle is vertical in the world, so the tool axis n̂ (tip → nozzle, bed space) is
//! `n̂ = Rᵀe₃`. The paper realises n̂ by the bed normal `n' = R e₃ = (n̂)_{−x,−y,z}` (§3,
//! "reflecting it about the z-axis") and Eq. 23 reads `n̂ = (n')_{−x,−y,z}` back. The two agree
//! only when R is a rotation about a horizontal axis; the paper's R = Mᵀ R_θ (Eq. 14) also
//! turns the bed about its normal by the θ the rails impose, and then the real nozzle
//! direction in bed space is off the requested n̂ by up to 0.14° at a 30° tilt on the RatRig
//! preset (more than the 0.1° the output promises). So warpslice keeps Rᵀe₃ = n̂ exactly: the
//! rotations with that property are `R = R_z(ψ)·T`, T the least rotation taking n̂ to e₃ (about
//! a horizontal axis), ψ a turn about the vertical. The heights of the balls do not depend on
//! ψ (`(R l̂ᵢ)_z = n̂·l̂ᵢ`), so the tilt is exactly the requested one, and the rails fix ψ.
//! `tests/machine_threez.rs` checks the nozzle direction with a generic solve of the physical
//! constraints.
//!
//! ## Inverse (§3.1, with R = R_z(ψ)·T)
//! Ball offsets in the world `R l̂ᵢ = R_z(ψ) T l̂ᵢ`, `l̂ᵢ = b̂ᵢ − b̂₀`. Ball 0 slides along its
//! rail, `b₀ = t d₀` (k₀ = 0, Eq. 7); balls 1 and 2 stay in their rail planes
//! `nᵢ·(t d₀ + R_z(ψ)(T l̂ᵢ)_{xy}) + kᵢ = 0` (Eq. 3). Eliminating t (Eq. 8) gives
//! `α cos ψ + β sin ψ + γ = 0` (Eq. 9 in the world frame), solved for the smallest |ψ| by
//! Eq. 11 (half-angle tangent, cancellation-free root). Then (Eqs. 14–15)
//!
//! ```text
//! q = R (p̂ − b̂₀) + b̂₀ + (t d₀, 0)
//! x = q_x, y = q_y, z₀ = q_z, zᵢ = z₀ − (R l̂ᵢ)_z   (i = 1, 2)
//! ```
//!
//! ## Forward (§3.2)
//! R₁ about `a₁ = e₃ × b̄₁/|·|` so that `(R₁ b̄₁)_z = z₀ − z₁` (Eq. 16), R₂ about
//! `a₂ = R₁b̄₁/|·|` so that `(R₂R₁ b̄₂)_z = z₀ − z₂` (Eq. 17), each by Rodrigues (Eqs. 18–19)
//! and Eq. 11; then the 2-D problem of Eqs. 20–22 in world xy for (t', θ'); finally (Eq. 23)
//!
//! ```text
//! R = R_{θ'} R₂ R₁,  p̂ = Rᵀ((x − t'd₀ₓ, y − t'd₀ᵧ, z₀) − b̂₀) + b̂₀,  n̂ = Rᵀe₃ = R₁ᵀR₂ᵀe₃
//! ```
//!
//! The paper's preset (§4.1): b̂₀ = (−4.07, −12.16), b̂₁ = (304.93, −12.16),
//! b̂₂ = (150.43, 296.84), ball z = −45.7 mm, slots 29.89°, 150.11°, −90°, tilt ≤ 30°.
//! The Z motors go below zero when the bed tilts: their travel is `[−D, ∞)` (D in
//! [`ThreeZ::z_motor_depth`]: every tip on the plate at a tilt within the limit keeps each
//! raw height above −D); the flavour headers give the firmware that minimum (RepRapFirmware
//! `M208 Z−D S1`: its default minimum is 0, and it clamps a homed axis there).

use glam::{DVec2, DVec3};

use super::angles::{tilt, Turn};
use super::{require, AxisSet, Capabilities, InverseResult, Machine, MachineError, Workspace};
use crate::num;

/// Below this |cross product| of two ball-to-ball vectors (mm²) the three balls are taken to be
/// collinear: they span no bed plane.
pub const COLLINEAR_AREA: f64 = 1e-6;

/// Parameters of [`ThreeZ`] (JSON `"kind": "three-z"`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct ThreeZParams {
    /// Ball positions b̂₀, b̂₁, b̂₂ in bed space (x, y), mm.
    pub balls_xy: [[f64; 2]; 3],
    /// The balls' z in bed space (negative: below the bed surface), mm.
    pub ball_z_mm: f64,
    /// Rail (slot) directions σ₀, σ₁, σ₂ from the X axis, degrees.
    pub slot_angles_deg: [f64; 3],
    /// Largest bed tilt, degrees.
    pub max_tilt_deg: f64,
    /// Planar build volume (x, y, z), mm — where the law tests sample.
    pub build_volume_mm: [f64; 3],
    /// Rail travel of each ball from its planar position (inward towards the balls' centroid,
    /// outward), mm; `None` does not check. Seed 001 §4.1: 69 mm inward, 19 mm outward.
    pub rail_travel_mm: Option<[f64; 2]>,
}

impl Default for ThreeZParams {
    fn default() -> Self {
        ThreeZParams {
            balls_xy: [[-4.07, -12.16], [304.93, -12.16], [150.43, 296.84]],
            ball_z_mm: -45.7,
            slot_angles_deg: [29.89, 150.11, -90.0],
            max_tilt_deg: 30.0,
            build_volume_mm: [300.0, 293.0, 205.0],
            rail_travel_mm: None,
        }
    }
}

/// The tangent of half the θ of [`solve_trig`] (`θ = 2 atan τ`), or ±∞ for θ = π; the same
/// root, without the arc tangent.
fn half_tangent(alpha: f64, beta: f64, gamma: f64) -> Option<f64> {
    let s = alpha + gamma;
    if s == 0.0 {
        return Some(0.0);
    }
    let scale = alpha * alpha + beta * beta;
    let mut d = scale - gamma * gamma;
    if d < 0.0 {
        if d > -super::DISCRIMINANT_SLACK * scale {
            d = 0.0;
        } else {
            return None;
        }
    }
    let sign = if beta >= 0.0 { 1.0 } else { -1.0 };
    let den = -beta - sign * d.sqrt();
    if den == 0.0 {
        return Some(f64::INFINITY);
    }
    Some(s / den)
}

/// Solve `α cos θ + β sin θ + γ = 0` for the θ of smallest |θ| (seed 001 Eq. 11).
/// `None` when there is no real solution (`α² + β² < γ²`).
pub fn solve_trig(alpha: f64, beta: f64, gamma: f64) -> Option<f64> {
    let tau = half_tangent(alpha, beta, gamma)?;
    Some(if tau.is_infinite() {
        core::f64::consts::PI
    } else {
        2.0 * num::atan(tau)
    })
}

/// [`solve_trig`]'s θ as the turn about the unit `axis`, its cosine and sine from the half-angle
/// tangent τ (`cos θ = (1 − τ²)/(1 + τ²)`, `sin θ = 2τ/(1 + τ²)`, in 1/τ for |τ| > 1 so nothing
/// overflows): no trigonometry. Within a few ulps of `Turn::new(axis, solve_trig(..))`; the
/// forward kinematics use it (they feed the interpolation check, not the written axes).
fn solve_turn(axis: DVec3, alpha: f64, beta: f64, gamma: f64) -> Option<Turn> {
    let tau = half_tangent(alpha, beta, gamma)?;
    let (cos, sin) = if tau.abs() <= 1.0 {
        let q = tau * tau;
        ((1.0 - q) / (1.0 + q), 2.0 * tau / (1.0 + q))
    } else {
        let u = 1.0 / tau;
        let q = u * u;
        ((q - 1.0) / (q + 1.0), 2.0 * u / (q + 1.0))
    };
    Some(Turn::from_cos_sin(axis, cos, sin))
}

fn perp(v: DVec2) -> DVec2 {
    DVec2::new(-v.y, v.x)
}

/// The triple-Z bed machine.
#[derive(Clone, Debug)]
pub struct ThreeZ {
    axis_set: AxisSet,
    params: ThreeZParams,
    /// b̂ᵢ (bed space, 3-D).
    b_hat: [DVec3; 3],
    /// l̂ᵢ = b̂ᵢ − b̂₀ = b̄ᵢ (3-D, z = 0).
    l: [DVec3; 3],
    /// Rail directions dᵢ (xy).
    d: [DVec2; 3],
    /// Rail-plane normals nᵢ = e₃ × dᵢ (xy).
    nrm: [DVec2; 3],
    /// kᵢ = −nᵢ·b̄ᵢ.
    k: [f64; 3],
    /// R₁'s axis `a₁ = e₃ × b̄₁/|·|` (Eq. 16), a constant of the machine.
    a1: DVec3,
}

impl ThreeZ {
    /// D of the Z motors' travel `[−D, ∞)`, mm: how far below the tip's height a motor can be
    /// for a tip on the build plate (x ∈ [0, w], y ∈ [0, d], z ≥ 0, bed frame) and a tilt up to
    /// θ = `max_tilt_deg`. A motor's height follows its ball (Eq. 1, `(bᵢ)_z = −zᵢ`), which is
    /// the vector v from the contact point to the ball rotated with the bed: the ball moves
    /// vertically by at most `|Rv − v| ≤ 2 sin(θ/2) |v|`, with |v|² ≤ (largest distance from a
    /// plate corner to a ball)² + ball_z². So `D = ⌈2 sin(θ/2) · √(spread² + ball_z²)⌉`
    /// (225 mm for the RatRig preset).
    pub fn z_motor_depth(p: &ThreeZParams) -> f64 {
        let [w, d, _] = p.build_volume_mm;
        let mut spread = 0.0f64;
        for c in [[0.0, 0.0], [w, 0.0], [0.0, d], [w, d]] {
            for b in &p.balls_xy {
                spread = spread.max(((c[0] - b[0]).powi(2) + (c[1] - b[1]).powi(2)).sqrt());
            }
        }
        let v = (spread * spread + p.ball_z_mm * p.ball_z_mm).sqrt();
        let depth = 2.0 * num::sin(num::rad(p.max_tilt_deg) / 2.0) * v;
        if depth.is_finite() {
            depth.max(0.0).ceil()
        } else {
            f64::INFINITY
        }
    }

    /// Build with axis letters `names` (X Y Z U V).
    pub fn new(name: &str, names: &[String], params: ThreeZParams) -> Result<ThreeZ, MachineError> {
        let ok = params.balls_xy.iter().flatten().all(|v| v.is_finite())
            && params.ball_z_mm.is_finite()
            && params.slot_angles_deg.iter().all(|v| v.is_finite())
            && params.max_tilt_deg > 0.0
            && params.max_tilt_deg < 90.0;
        require(
            name,
            ok,
            "balls_xy, ball_z_mm, slot_angles_deg must be finite and max_tilt_deg in (0, 90)",
        )?;
        let b_hat = params
            .balls_xy
            .map(|[x, y]| DVec3::new(x, y, params.ball_z_mm));
        let l = b_hat.map(|b| b - b_hat[0]);
        let d = params
            .slot_angles_deg
            .map(|s| DVec2::new(num::cos(num::rad(s)), num::sin(num::rad(s))));
        let nrm = d.map(perp);
        let k = [0, 1, 2].map(|i| -nrm[i].dot(l[i].truncate()));
        let tri = l[1].truncate().perp_dot(l[2].truncate());
        // the balls span no triangle (area² below 1e-6 mm²), or a slot direction is not
        // perpendicular to its normal (cannot happen but for NaN)
        let collinear = tri.abs() < COLLINEAR_AREA || nrm[0].dot(d[0]).abs() > super::UNIT_EPSILON;
        require(name, !collinear, "the three balls are collinear")?;
        Ok(ThreeZ {
            axis_set: {
                let floor = -ThreeZ::z_motor_depth(&params);
                let mut limits = AxisSet::linear(name, names).limits().to_vec();
                for l in limits.iter_mut().skip(2) {
                    l.min = floor;
                }
                AxisSet::new(name, limits)
            },
            params,
            b_hat,
            l,
            d,
            nrm,
            k,
            a1: DVec3::new(-l[1].y, l[1].x, 0.0).normalize(),
        })
    }

    /// The bed's pose for axes (x, y, z₀, z₁, z₂) (seed 001 §3.2, Eqs. 16–22): the rotations
    /// R₁, R₂, R_θ' and the slide t' of ball 0 along its rail; [`Machine::forward`] applies
    /// it (Eq. 23). Depends on z₀ − z₁ and z₀ − z₂ only.
    pub(super) fn bed_pose(&self, axes: &[f64]) -> Result<BedPose, MachineError> {
        self.axis_set.check_count(5, axes)?;
        let (x, y, z0, z1, z2) = (axes[0], axes[1], axes[2], axes[3], axes[4]);
        let fail = |what: &str| {
            self.axis_set.unreachable(
                DVec3::new(x, y, z0),
                DVec3::Z,
                format!("the Z axes (z0, z1, z2) = ({z0}, {z1}, {z2}) admit no bed pose: {what}"),
            )
        };
        // Eqs. 16–19: the rotation of v about a so that its z becomes zt, its cosine and sine
        // from Eq. 11's half-angle tangent (no trigonometry: `solve_turn`)
        let solve_rot = |v: DVec3, a: DVec3, zt: f64| -> Option<Turn> {
            let va = v.dot(a);
            solve_turn(a, v.z - a.z * va, a.cross(v).z, a.z * va - zt)
        };
        let (l1, l2) = (self.l[1], self.l[2]);
        let t1 = solve_rot(l1, self.a1, z0 - z1).ok_or_else(|| fail("R1"))?;
        let r1l1 = t1.apply(l1);
        let a2 = r1l1.normalize();
        let r1l2 = t1.apply(l2);
        let t2 = solve_rot(r1l2, a2, z0 - z2).ok_or_else(|| fail("R2"))?;
        // Eqs. 20–22.
        let (tp, spin) = self
            .solve_triangle(t2.apply(r1l1).truncate(), t2.apply(r1l2).truncate(), true)
            .ok_or_else(|| fail("the balls cannot reach their rails"))?;
        Ok(BedPose { t1, t2, spin, tp })
    }

    /// [`Machine::forward`] with the bed's pose of these axes already found
    /// ([`ThreeZ::bed_pose`]): the tip and tool axis of Eq. 23.
    pub(super) fn pose_at(&self, pose: &BedPose, axes: &[f64]) -> (DVec3, DVec3) {
        let (x, y, z0) = (axes[0], axes[1], axes[2]);
        let (t1_back, t2_back) = (pose.t1.reversed(), pose.t2.reversed());
        let r21t = |v: DVec3| t1_back.apply(t2_back.apply(v));
        // Eq. 23.
        let b0 = self.d[0] * pose.tp;
        let v = DVec3::new(x - b0.x, y - b0.y, z0) - self.b_hat[0];
        let p = r21t(pose.spin.reversed().about_z(v)) + self.b_hat[0];
        // The nozzle is vertical in the world: in bed space it points along Rᵀ e₃ = R₁ᵀ R₂ᵀ e₃
        // (R_θ' turns about e₃).
        (p, r21t(DVec3::Z))
    }

    /// How far ball `i`, at `now` (xy, relative to b̂₀'s planar position), has slid along its
    /// rail from its planar position, signed towards the centroid of the balls (inward), mm.
    pub(super) fn slide(&self, i: usize, now: DVec2) -> f64 {
        let centroid = (self.l[0] + self.l[1] + self.l[2]) / 3.0;
        let into = if self.d[i].dot((centroid - self.l[i]).truncate()) >= 0.0 {
            self.d[i]
        } else {
            -self.d[i]
        };
        into.dot(now - self.l[i].truncate())
    }

    /// Ball offsets l̂ᵢ = b̂ᵢ − b̂₀ (bed space, z = 0), mm.
    pub(super) fn ball_offsets(&self) -> [DVec3; 3] {
        self.l
    }
    /// Rail directions dᵢ (xy) and the rail-plane normals nᵢ = e₃ × dᵢ.
    pub(super) fn rails(&self) -> ([DVec2; 3], [DVec2; 3]) {
        (self.d, self.nrm)
    }
    /// b̂₀ (bed space), mm.
    pub(super) fn ball0(&self) -> DVec3 {
        self.b_hat[0]
    }
    /// The machine's parameters.
    pub(super) fn params(&self) -> &ThreeZParams {
        &self.params
    }

    /// Solve the 2-D rigid-triangle problem (Eqs. 8–11 / 21–22): ball offsets `l1, l2` (xy) on
    /// the machine's rails (ball 0's line direction d₀, rail normals n₁, n₂, offsets k₁, k₂) →
    /// (t, the turn by θ about +Z, its sine and cosine computed once). `trig_free`: the turn
    /// from [`solve_turn`] (the forward map), else from θ (the inverse, whose axes are written:
    /// kept bit for bit).
    fn solve_triangle(&self, l1: DVec2, l2: DVec2, trig_free: bool) -> Option<(f64, Turn)> {
        let (d0, n1, n2, k1, k2) = (self.d[0], self.nrm[1], self.nrm[2], self.k[1], self.k[2]);
        let (dn1, dn2) = (d0.dot(n1), d0.dot(n2));
        let (c1, s1) = (l1.dot(n1), perp(l1).dot(n1));
        let (c2, s2) = (l2.dot(n2), perp(l2).dot(n2));
        let alpha = dn1 * c2 - dn2 * c1;
        let beta = dn1 * s2 - dn2 * s1;
        let gamma = d0.dot(n1 * k2 - n2 * k1);
        let turn = if trig_free {
            solve_turn(DVec3::Z, alpha, beta, gamma)?
        } else {
            Turn::new(DVec3::Z, solve_trig(alpha, beta, gamma)?)
        };
        if dn1.abs() < f64::MIN_POSITIVE {
            return None;
        }
        let t = -(c1 * turn.cos() + s1 * turn.sin() + k1) / dn1;
        Some((t, turn))
    }
}

/// The bed's pose (seed 001 §3.2): bed space → world is `R = R_{θ'} R₂ R₁`, ball 0 at
/// `b̂₀ + t' d₀` ([`ThreeZ::bed_pose`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct BedPose {
    t1: Turn,
    t2: Turn,
    /// R_θ': the turn by θ' about +Z.
    spin: Turn,
    /// t' (mm).
    pub(super) tp: f64,
}

impl BedPose {
    /// `R v`: a bed-space vector in the world.
    pub(super) fn rotate(&self, v: DVec3) -> DVec3 {
        self.spin.about_z(self.t2.apply(self.t1.apply(v)))
    }
}

impl super::spec::Kind for ThreeZParams {
    fn default_axis_names(&self) -> &'static [&'static str] {
        &["X", "Y", "Z", "U", "V"]
    }
    fn build(&self, name: &str, axis_names: &[String]) -> Result<Box<dyn Machine>, MachineError> {
        Ok(Box::new(ThreeZ::new(name, axis_names, self.clone())?))
    }
}

impl Machine for ThreeZ {
    fn axis_set(&self) -> &AxisSet {
        &self.axis_set
    }
    /// X, Y and the mean of the Z motors (the bed's height under its centroid: the tilt a
    /// drawing shows is that of the motor plane, an approximation of the bed's).
    fn head_position(&self, axes: &[f64]) -> DVec3 {
        let a = |i: usize| axes.get(i).copied().unwrap_or(0.0);
        let zs = axes.len().saturating_sub(2).max(1);
        let z: f64 = axes.iter().skip(2).sum();
        DVec3::new(a(0), a(1), z / zs as f64)
    }

    /// The bed's three Z motors are three axes (Z U V), each driven alone.
    fn axis_drive(&self) -> super::config::AxisDrive {
        super::config::AxisDrive::SeparateZ
    }

    fn capabilities(&self) -> Capabilities {
        {
            let v = self.params.build_volume_mm;
            Capabilities {
                summary: "tilting bed on three Z motors".into(),
                max_tilt_deg: Some(self.params.max_tilt_deg),
                fixed_tilt_deg: None,
                moving_bed: true,
                warps: super::all_warps(),
                notes: vec![format!(
                    "tilting bed on three Z motors, tilt up to {}°, build volume {} × {} × {} mm",
                    self.params.max_tilt_deg, v[0], v[1], v[2]
                )],
            }
        }
    }
    fn inverse(&self, p: DVec3, n: DVec3, _previous: Option<&[f64]>) -> InverseResult {
        let n_hat = self.axis_set.check_input(p, n)?;
        let tilt_deg = num::deg(tilt(n_hat));
        if tilt_deg > self.params.max_tilt_deg + super::LIMIT_SLACK_DEG {
            return Err(self.axis_set.unreachable(
                p,
                n_hat,
                format!(
                    "the bed would tilt {tilt_deg:.3}°, beyond max_tilt_deg = {}°",
                    self.params.max_tilt_deg
                ),
            ));
        }
        // The bed's rotation R (bed → world) must turn the tool axis n̂ onto the vertical nozzle,
        // Rᵀ e₃ = n̂: every such R is `R_z(ψ)·T`, T the least rotation n̂ → e₃ (about a
        // horizontal axis) and ψ a turn about the vertical (see the module doc: this is where
        // the paper's `n' = (n̂)_{−x,−y,z}` with `R = Mᵀ R_θ` is off by up to 0.14°).
        let tilt_turn = Turn::onto_z(n_hat);
        let a = |i: usize| tilt_turn.apply(self.l[i]);
        // Eqs. 7–11 in the world: ball 0 at t d₀ on its rail, ball i at t d₀ + R_z(ψ) (T l̂ᵢ)_{xy}
        // in its rail plane nᵢ·b + kᵢ = 0 (i = 1, 2): α cos ψ + β sin ψ + γ = 0, least |ψ|.
        let (tt, spin) = self
            .solve_triangle(a(1).truncate(), a(2).truncate(), false)
            .ok_or_else(|| {
                self.axis_set.unreachable(
                    p,
                    n_hat,
                    "no bed pose puts the three balls on their rails (Eq. 11 has no real root)"
                        .into(),
                )
            })?;
        // Eq. 14 with R = R_z(ψ)·T: q = R (p̂ − b̂₀) + b̂₀ + (t d₀, 0).
        let b0w = (self.d[0] * tt).extend(0.0);
        let rot = |v: DVec3| spin.about_z(tilt_turn.apply(v));
        let pp = rot(p - self.b_hat[0]) + self.b_hat[0] + b0w;
        let z0 = pp.z;
        // Eq. 15.
        if let Some([inward, outward]) = self.params.rail_travel_mm {
            // Ball i is at b₀ʷ + Mᵀ R_θ l̂ᵢ (xy); planar it is at l̂ᵢ. Its slide along the rail,
            // signed towards the centroid of the balls, must stay within the rail.
            for i in 0..3 {
                let now = DVec2::new(b0w.x, b0w.y) + rot(self.l[i]).truncate();
                let slide = self.slide(i, now);
                if slide > inward + crate::tolerance::LENGTH_EPSILON
                    || -slide > outward + crate::tolerance::LENGTH_EPSILON
                {
                    return Err(self.axis_set.unreachable(
                        p,
                        n_hat,
                        format!("ball {i} would slide {slide:.3} mm inward along its rail, beyond the rail travel [-{outward}, {inward}] mm"),
                    ));
                }
            }
        }
        let axes = vec![pp.x, pp.y, z0, z0 - rot(self.l[1]).z, z0 - rot(self.l[2]).z];
        self.axis_set.check_limits(axes, p)
    }
    fn forward(&self, axes: &[f64]) -> Result<(DVec3, DVec3), MachineError> {
        Ok(self.pose_at(&self.bed_pose(axes)?, axes))
    }

    /// The bed turns the tool axis exactly onto the nozzle (`Rᵀe₃ = n̂`, the module doc) and
    /// puts the tip exactly under it: nothing is dropped, clipped or held.
    fn realises_requests(&self) -> bool {
        true
    }
    /// The bed's pose for the Z motor heights, [`ThreeZ::bed_pose`]: its 3Z closed-form bound
    /// ([`super::threez_bound`]).
    fn interpolation_bound(
        &self,
        from: super::PieceEnd,
        to: super::PieceEnd,
    ) -> Option<(f64, f64)> {
        super::threez_bound::bound(self, from, to)
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
    fn workspace(&self) -> Workspace {
        let v = self.params.build_volume_mm;
        Workspace {
            min: DVec3::ZERO,
            max: DVec3::new(v[0], v[1], v[2]),
            max_tilt_deg: self.params.max_tilt_deg,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `solve_turn` (the forward map's cosine and sine from the half-angle tangent) against
    /// `solve_trig`'s θ through libm, over roots on every side of ±π/2 (|τ| above and below 1)
    /// and the half turn (τ = ∞): within 4 ulps of 1.
    #[test]
    fn the_half_angle_turn_is_the_solved_angles_turn() {
        let mut checked = 0;
        for i in 0..2000 {
            let theta = -3.1 + 6.2 * i as f64 / 1999.0;
            for (a, b) in [(1.0, 0.0), (0.3, -2.0), (-1.5, 0.7), (2.0, 2.0)] {
                // γ so that θ is a root of α cos θ + β sin θ + γ = 0
                let g = -(a * num::cos(theta) + b * num::sin(theta));
                let (Some(t), Some(turn)) = (solve_trig(a, b, g), solve_turn(DVec3::Z, a, b, g))
                else {
                    panic!("no root for θ = {theta} (α {a}, β {b})");
                };
                let (c, s) = (num::cos(t), num::sin(t));
                assert!(
                    (turn.cos() - c).abs() <= 4.0 * f64::EPSILON
                        && (turn.sin() - s).abs() <= 4.0 * f64::EPSILON,
                    "θ = {t}: half-angle ({}, {}) vs libm ({c}, {s})",
                    turn.cos(),
                    turn.sin()
                );
                checked += 1;
            }
        }
        // the half turn: den = 0 (α = −1, β = 0, γ = −1 has θ = π)
        let turn = solve_turn(DVec3::Z, -1.0, 0.0, -1.0).unwrap();
        assert_eq!((turn.cos(), turn.sin()), (-1.0, 0.0));
        assert_eq!(solve_trig(-1.0, 0.0, -1.0), Some(core::f64::consts::PI));
        assert_eq!(checked, 8000);
    }
}
