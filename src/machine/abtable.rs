//! `open5x-ab`: a vertical nozzle over an A/B rotary table (seed 004, Open5x / UHH). Axes
//! X Y Z A B.
//!
//! ## Model (seed 004 §4.1)
//! A turns the table about the line (A_pos, A_dir) ≈ X; B turns the bed about the line
//! (B_pos, B_dir) ≈ Z, which is carried by A (B_pos, B_dir are given at A = 0). A part point `p`
//! (output frame = machine frame at A = B = 0, shifted by `part_offset`) is at
//!
//! ```text
//! q = T_A(A) T_B(B) (p + part_offset),   T_L(θ)(x) = L_pos + R(L_dir, θ)(x − L_pos)
//! ```
//! (right-hand rotations, degrees). The origin is moved to the machine origin of seed 004
//! §4.1.1/§5.4.2: the point of the B line closest to the A line. The nozzle stays vertical, so
//! (A, B) must satisfy `R(A_dir, A)·R(B_dir, B)·n = e_z`, and X Y Z = q.
//!
//! ## Closed form (any line directions, ideal or calibrated)
//! `R_A(A) R_B(B) n = e_z` ⇔ `R_B(B) n = R_A(−A) e_z =: v`. Rotations keep the component along
//! their axis, so v is a unit vector with `v·b_dir = n·b_dir` and `v·a_dir = e_z·a_dir`: the
//! meeting of two circles on the sphere, `v = x a + y b ± z (a × b)` with
//! `x = (c_a − (a·b) c_b)/(1 − (a·b)²)`, `y = (c_b − (a·b) c_a)/(1 − (a·b)²)`,
//! `z² = (1 − |x a + y b|²)/|a × b|²`. Then B is the rotation about b_dir taking n to v and A
//! the rotation about a_dir taking v to e_z, each `atan2(u·(w⊥ × v⊥), w⊥·v⊥)`. No iteration is
//! needed (this replaces the Newton steps suggested for calibrated axes: it is exact).
//! For ideal axes (a = X, b = Z) this is `(A, B) = (t, 90° − φ)` or `(−t, −90° − φ)` (tilt t,
//! azimuth φ of n). The branch whose B is nearer the previous B (unwrapped, B is continuous) is
//! taken; without a previous pose the larger A. A ∈ [−90°, 90°] (⇔ n_z ≥ 0 for ideal axes);
//! beyond it the orientation is unreachable.
//!
//! ## Pole
//! B is undefined when n ∥ b_dir. Near it (|n × b_dir| < sin 0.5°, `pole_hold_deg`) B is held at
//! its previous value instead of spinning, and A maximises `(R_A R_B n)_z` (closed form): the
//! realised axis then differs from n by at most 0.5° (`branch_freedom`).
//!
//! ## A-axis Z wobble (seed 004 §5.1.8, Eq. 5.1)
//! `z_wobble(A) = min(max(z_d, −z_d), max(min(z_d, −z_d), 2 z_d A / 180))` (linear in A,
//! ±z_d at ±90°). The commanded Z is the ideal Z plus z_wobble (as the a_wobble_correct
//! post-processor does); forward subtracts it.

use glam::DVec3;

use super::angles::{rotate, unwrap_near, wrap180, Turn};
use super::{
    require, AxisSet, Capabilities, InverseResult, Machine, MachineError, Workspace, UNLIMITED,
};
use crate::num;
use crate::tolerance::LENGTH_EPSILON;

/// Slack below zero on z² of the closest approach (mm², rounding of a difference of
/// products of unit-vector dot products): within it z² is taken to be 0.
pub const Z2_SLACK: f64 = 1e-15;

/// Parameters of [`AbTable`] (JSON `"kind": "ab-table"`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct AbTableParams {
    /// A point of the A line, mm.
    pub a_pos: DVec3,
    /// Direction of the A line (≈ +X).
    pub a_dir: DVec3,
    /// A point of the B line at A = 0, mm.
    pub b_pos: DVec3,
    /// Direction of the B line at A = 0 (≈ +Z).
    pub b_dir: DVec3,
    /// The output-frame origin in machine coordinates at A = B = 0 (e.g. the bed surface above
    /// the machine origin), mm.
    pub part_offset: DVec3,
    /// Wobble amplitude z_d at A = ±90°, mm (0 disables).
    pub z_wobble_mm: f64,
    /// Hold B when |n_xy| < sin(pole_hold_deg), degrees.
    pub pole_hold_deg: f64,
    /// Largest |A|, degrees.
    pub a_limit_deg: f64,
}

impl Default for AbTableParams {
    fn default() -> Self {
        AbTableParams {
            a_pos: DVec3::ZERO,
            a_dir: DVec3::X,
            b_pos: DVec3::ZERO,
            b_dir: DVec3::Z,
            part_offset: DVec3::ZERO,
            z_wobble_mm: 0.0,
            pole_hold_deg: 0.5,
            a_limit_deg: 90.0,
        }
    }
}

/// The A/B table machine.
#[derive(Clone, Debug)]
pub struct AbTable {
    axis_set: AxisSet,
    params: AbTableParams,
}

impl AbTable {
    /// Build with axis letters `names` (X Y Z A B). Moves the origin to the closest approach of
    /// the two lines (seed 004 §5.4.2).
    pub fn new(
        name: &str,
        names: &[String],
        mut params: AbTableParams,
    ) -> Result<AbTable, MachineError> {
        require(
            name,
            params.a_dir.is_finite()
                && params.b_dir.is_finite()
                && params.a_pos.is_finite()
                && params.b_pos.is_finite(),
            "a_pos, a_dir, b_pos, b_dir must be finite",
        )?;
        require(
            name,
            params.a_dir.length() >= LENGTH_EPSILON && params.b_dir.length() >= LENGTH_EPSILON,
            "a_dir and b_dir must be non-zero",
        )?;
        params.a_dir = params.a_dir.normalize();
        params.b_dir = params.b_dir.normalize();
        let w = params.a_dir.cross(params.b_dir);
        require(
            name,
            w.length() >= super::PARALLEL_SINE,
            "the A and B lines are parallel",
        )?;
        // Closest approach: B_pos + s·B_dir with (B_pos + s B_dir − A_pos − u A_dir) ⟂ both.
        let (a, b) = (params.a_dir, params.b_dir);
        let r = params.b_pos - params.a_pos;
        let (ab, ar, br) = (a.dot(b), a.dot(r), b.dot(r));
        let s = (ab * ar - br) / (1.0 - ab * ab);
        let origin = params.b_pos + b * s;
        params.a_pos -= origin;
        params.b_pos -= origin;
        require(
            name,
            params.pole_hold_deg >= 0.0 && params.a_limit_deg > 0.0,
            "pole_hold_deg must be ≥ 0 and a_limit_deg > 0",
        )?;
        let a = params.a_limit_deg;
        let axis_set = AxisSet::linear_then_rotary(name, names, &[(-a, a), UNLIMITED]);
        Ok(AbTable { axis_set, params })
    }

    /// Eq. 5.1: the Z correction at A (degrees), mm.
    pub fn z_wobble(&self, a: f64) -> f64 {
        let zd = self.params.z_wobble_mm;
        zd.max(-zd).min(zd.min(-zd).max(2.0 * zd * a / 180.0))
    }

    /// Angular radius (radians) of the zone about b_dir where B is held: `pole_hold_deg` plus,
    /// for calibrated axes, the radius of the small cone about b_dir that no (A, B) makes exactly
    /// vertical (`asin |e_z·a − (a·b)|`; 0 for ideal axes).
    fn hold_radius(&self) -> f64 {
        let (a, b) = (self.params.a_dir, self.params.b_dir);
        num::rad(self.params.pole_hold_deg) + num::asin((a.z - a.dot(b)).abs().min(1.0))
    }

    /// The rotation about unit `u` (radians) taking `w` to `v` (both with the same component
    /// along `u`): `atan2(u·(w⊥ × v⊥), w⊥·v⊥)`, ⊥ = perpendicular to `u`.
    fn angle_about(u: DVec3, w: DVec3, v: DVec3) -> f64 {
        let wp = w - u * u.dot(w);
        let vp = v - u * u.dot(v);
        num::atan2(u.dot(wp.cross(vp)), wp.dot(vp))
    }

    /// The two vectors `v = R_B(B)·n = R_A(−A)·e_z` (unit, `v·b_dir = n·b_dir`,
    /// `v·a_dir = e_z·a_dir`): `v = x a + y b ± z (a × b)`. `None` when the two circles miss.
    fn meeting(&self, n: DVec3) -> Option<[DVec3; 2]> {
        let (a, b) = (self.params.a_dir, self.params.b_dir);
        let (ca, cb, ab) = (a.z, n.dot(b), a.dot(b));
        let det = 1.0 - ab * ab;
        let x = (ca - ab * cb) / det;
        let y = (cb - ab * ca) / det;
        let base = a * x + b * y;
        let w = a.cross(b);
        // z²|a×b|² = 1 − |x a + y b|² = (|n × b|²·det − (c_a − (a·b) c_b)²)/det, written without the
        // cancellation of 1 − c_b² near the pole.
        let s2 = n.cross(b).length_squared();
        let e = ca - ab * cb;
        let mut z2 = (s2 * det - e * e) / (det * det);
        if z2 < 0.0 {
            if z2 > -Z2_SLACK {
                z2 = 0.0;
            } else {
                return None;
            }
        }
        let z = z2.sqrt();
        Some([base + w * z, base - w * z])
    }

    /// When no (A, B) makes n exactly vertical (calibrated axes near the pole): B turns n onto
    /// the point of its cone about b_dir nearest the cone of A, in the plane of a_dir and b_dir,
    /// then A = [`AbTable::hold_a`]. Radians.
    fn nearest(&self, n: DVec3) -> (f64, f64) {
        let (a, b) = (self.params.a_dir, self.params.b_dir);
        let cb = n.dot(b);
        let sb = (1.0 - cb * cb).max(0.0).sqrt();
        let e = (a - b * a.dot(b)).normalize();
        let sgn = if a.z - cb * a.dot(b) >= 0.0 {
            1.0
        } else {
            -1.0
        };
        let v = b * cb + e * (sb * sgn);
        let bb = AbTable::angle_about(b, n, v);
        (self.hold_a(n, bb), bb)
    }

    /// With B held (radians), the A (radians) bringing n closest to vertical: maximise
    /// `(R_A m)_z`, `m = R_B n`: `A = atan2((a_dir × m⊥)_z, (m⊥)_z)`.
    fn hold_a(&self, n: DVec3, b: f64) -> f64 {
        let u = self.params.a_dir;
        let m = rotate(n, self.params.b_dir, b);
        let mp = m - u * u.dot(m);
        num::atan2(u.cross(mp).z, mp.z)
    }

    /// Of the two exact solutions, the one whose B is nearest `prev_b` (degrees, unwrapped), or
    /// without a previous pose the larger A.
    fn pick(&self, n: DVec3, vs: [DVec3; 2], prev_b: Option<f64>) -> (f64, f64) {
        let cand = vs.map(|v| {
            let b = num::deg(AbTable::angle_about(self.params.b_dir, n, v));
            let a = num::deg(AbTable::angle_about(self.params.a_dir, v, DVec3::Z));
            (a, b)
        });
        match prev_b {
            None => {
                let (a, b) = if cand[0].0 >= cand[1].0 {
                    cand[0]
                } else {
                    cand[1]
                };
                (a, wrap180(b))
            }
            Some(pb) => {
                let c0 = (cand[0].0, unwrap_near(cand[0].1, pb));
                let c1 = (cand[1].0, unwrap_near(cand[1].1, pb));
                let (d0, d1) = ((c0.1 - pb).abs(), (c1.1 - pb).abs());
                if d1 < d0 - super::LIMIT_SLACK_DEG
                    || ((d1 - d0).abs() <= super::LIMIT_SLACK_DEG && c1.0 > c0.0)
                {
                    c1
                } else {
                    c0
                }
            }
        }
    }

    fn transform(&self, x: DVec3, a: f64, b: f64) -> DVec3 {
        let p = &self.params;
        let y = p.b_pos + rotate(x - p.b_pos, p.b_dir, b);
        p.a_pos + rotate(y - p.a_pos, p.a_dir, a)
    }

    /// The part point at machine point `q` for (A, B) (radians), and the tool axis
    /// `R_B(−B) R_A(−A) e_z`: each rotation's sine and cosine once.
    fn untransform(&self, q: DVec3, a: f64, b: f64) -> (DVec3, DVec3) {
        let p = &self.params;
        let (ta, tb) = (Turn::new(p.a_dir, -a), Turn::new(p.b_dir, -b));
        let y = p.a_pos + ta.apply(q - p.a_pos);
        (
            p.b_pos + tb.apply(y - p.b_pos),
            tb.apply(ta.apply(DVec3::Z)),
        )
    }
}

impl super::spec::Kind for AbTableParams {
    fn default_axis_names(&self) -> &'static [&'static str] {
        &["X", "Y", "Z", "A", "B"]
    }
    fn build(&self, name: &str, axis_names: &[String]) -> Result<Box<dyn Machine>, MachineError> {
        Ok(Box::new(AbTable::new(name, axis_names, self.clone())?))
    }
}

impl Machine for AbTable {
    fn axis_set(&self) -> &AxisSet {
        &self.axis_set
    }
    fn capabilities(&self) -> Capabilities {
        Capabilities {
            summary: "A/B rotary table (the part turns)".into(),
            max_tilt_deg: Some(self.params.a_limit_deg),
            fixed_tilt_deg: None,
            moving_bed: true,
            warps: super::all_warps(),
            notes: vec![format!(
                "A/B rotary table, A within ±{}°; place the part on the table's axes (--place 0,0)",
                self.params.a_limit_deg
            )],
        }
    }
    fn inverse(&self, p: DVec3, n: DVec3, previous: Option<&[f64]>) -> InverseResult {
        let n = self.axis_set.check_input(p, n)?;
        let prev_b = previous.and_then(|a| a.get(4).copied());
        let off_pole = n.cross(self.params.b_dir).length();
        let hold = prev_b.is_some() && off_pole < num::sin(self.hold_radius());
        let (a, b) = if hold {
            let b = prev_b.unwrap_or(0.0);
            (num::deg(self.hold_a(n, num::rad(b))), b)
        } else {
            match self.meeting(n) {
                None => {
                    let (a, b) = self.nearest(n);
                    (num::deg(a), num::deg(b))
                }
                Some(vs) => self.pick(n, vs, prev_b),
            }
        };
        if a.abs() > self.params.a_limit_deg + super::LIMIT_SLACK_DEG {
            return Err(self.axis_set.unreachable(
                p,
                n,
                format!("the table would have to tilt A = {a:.3}°, beyond ±{}° (the tool axis points below the horizon)", self.params.a_limit_deg),
            ));
        }
        let q = self.transform(p + self.params.part_offset, num::rad(a), num::rad(b));
        let axes = vec![q.x, q.y, q.z + self.z_wobble(a), a, b];
        self.axis_set.check_limits(axes, p)
    }
    fn forward(&self, axes: &[f64]) -> Result<(DVec3, DVec3), MachineError> {
        self.axis_set.check_count(5, axes)?;
        let (a, b) = (axes[3], axes[4]);
        let q = DVec3::new(axes[0], axes[1], axes[2] - self.z_wobble(a));
        let (ar, br) = (num::rad(a), num::rad(b));
        let (p, n) = self.untransform(q, ar, br);
        Ok((p - self.params.part_offset, n))
    }
    fn realised_axis(&self, _p: DVec3, n: DVec3) -> DVec3 {
        let n = n / n.length();
        match self.meeting(n) {
            Some(_) => n,
            None => {
                let (a, b) = self.nearest(n);
                rotate(
                    rotate(DVec3::Z, self.params.a_dir, -a),
                    self.params.b_dir,
                    -b,
                )
            }
        }
    }
    /// `(−A, B ± 180°)` (ideal axes; the calibrated closed form's other root): B turned half a
    /// revolution towards 0, then the branch nearest it. Near the pole B is held there and A
    /// re-solved, as on any path. `None` when that solution's A is beyond its limit or the
    /// solution is the same branch (B within 90° of `axes`' B).
    fn other_branch(&self, p: DVec3, n: DVec3, axes: &[f64]) -> Option<Vec<f64>> {
        let b = *axes.get(4)?;
        let mut seed = axes.to_vec();
        seed[4] = if b > 0.0 { b - 180.0 } else { b + 180.0 };
        let alt = self.inverse(p, n, Some(&seed)).ok()?;
        ((alt[4] - b).abs() > 90.0).then_some(alt)
    }
    fn branch_freedom(&self, _p: DVec3, n: DVec3) -> f64 {
        let n = n / n.length();
        if n.cross(self.params.b_dir).length() < num::sin(self.hold_radius()) {
            2.0 * self.hold_radius() + super::UNIT_EPSILON
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
    /// Where a bound is given (ideal axes, the piece in the tilt cap and out of the pole's hold
    /// zone) the closed form of `inverse` is exact: two circles' meeting, no hold, no nearest.
    fn realises_bounded_requests(&self) -> bool {
        true
    }
    /// The firmware's tip is `F(s) = b_pos + R_B(−B) G`, `G = a_pos − b_pos + R_A(−A) v`,
    /// `v = q − a_pos`, q = (X, Y, Z − wobble(A)) (linear in s: the wobble is linear for
    /// |A| ≤ 90°), A and B linear (totals K_A, K_B radians). By [`super::bound`] Lemma 2, in the
    /// frames turning with each rotation: `|G''| ≤ K_A² V + 2 K_A Δ` and `|G'| ≤ K_A V + Δ`, with
    /// V the largest distance of q from the A line (a segment's farthest point is an end) and
    /// Δ = |q₁ − q₀|; and `|F''| ≤ K_B² R + 2 K_B |G'| + |G''|`, R the largest distance of G from
    /// the B line: at the ends the part point's distance from the B axis
    /// (`|(p + part_offset − b_pos)⊥b|`, a rotation about b keeps it), along the piece at most
    /// `|G''|/8` more (Lemma 1). So
    ///
    /// ```text
    /// |F''| ≤ K_B² R + 2 K_B (K_A V + Δ) + K_A² V + 2 K_A Δ,   R ≤ max_ends |x⊥b| + (K_A² V + 2 K_A Δ)/8
    /// ```
    ///
    /// and the tip is within `|F''|/8` of the straight line (Lemma 1). The tool axis
    /// `R_B(−B) R_A(−A) e_z = u(A, 90° − B)` (tilt A, azimuth 90° − B) is within Lemma 5's chord
    /// of the slerp when the intended axis is realised all along: ideal axes (A about X, B
    /// about Z), `a_limit_deg` ≤ 90° (the reachable axes are a cap) and the piece out of the
    /// pole's hold zone (its least angle from +Z, at least `(θ₀ + θ₁ − w)/2`, beyond the hold
    /// radius). Else the tip bound alone is no use: sample.
    fn interpolation_bound(
        &self,
        from: super::PieceEnd,
        to: super::PieceEnd,
    ) -> Option<(f64, f64)> {
        use super::bound;
        let (a0, a1, n0, n1) = (from.0, to.0, from.2, to.2);
        let pr = &self.params;
        let ideal = pr.a_dir == DVec3::X && pr.b_dir == DVec3::Z && pr.a_limit_deg <= 90.0;
        if !ideal || !bound::usable(from, to, 5) {
            return None;
        }
        if !bound::arc_in_cap(n0, n1, DVec3::Z, pr.a_limit_deg) {
            return None;
        }
        let w = bound::angle(n0, n1);
        let least = (bound::angle(n0, DVec3::Z) + bound::angle(n1, DVec3::Z) - w) / 2.0;
        // NaN refuses too
        let out_of_hold = least > self.hold_radius() + num::rad(bound::BRANCH_MARGIN_DEG);
        if !out_of_hold {
            return None;
        }
        let q = |a: &[f64]| DVec3::new(a[0], a[1], a[2] - self.z_wobble(a[3]));
        let (q0, q1) = (q(a0), q(a1));
        // distances from the A line (a_dir = X) and, of the part points, from the B line (Z)
        let off_a = |q: DVec3| {
            let d = q - pr.a_pos;
            d.y.hypot(d.z)
        };
        let off_b = |p: DVec3| (p + pr.part_offset - pr.b_pos).truncate().length();
        let v = off_a(q0).max(off_a(q1));
        let dq = (q1 - q0).length();
        let (ka, kb) = (
            num::rad((a1[3] - a0[3]).abs()),
            num::rad((a1[4] - a0[4]).abs()),
        );
        let g2 = ka * ka * v + 2.0 * ka * dq;
        let r = off_b(from.1).max(off_b(to.1)) + bound::chord_deviation(g2);
        let acc = kb * kb * r + 2.0 * kb * (ka * v + dq) + g2;
        let (chord, _) = bound::spherical_deviation(
            num::rad(a0[3]),
            num::rad(a1[3]),
            num::rad(a1[4] - a0[4]),
            w,
        )?;
        Some((
            bound::chord_deviation(acc) + bound::ROUND_TRIP_SLACK_MM,
            bound::angle_of_chord(chord) + bound::ROUND_TRIP_SLACK_DEG,
        ))
    }
    fn workspace(&self) -> Workspace {
        // Calibrated axes reach a little less (or more) than A's limit in some directions.
        let misalign = num::deg(
            num::angle_between(self.params.a_dir, DVec3::X)
                + num::angle_between(self.params.b_dir, DVec3::Z),
        );
        Workspace {
            min: DVec3::new(-50.0, -50.0, 0.0),
            max: DVec3::new(50.0, 50.0, 80.0),
            max_tilt_deg: self.params.a_limit_deg.min(180.0) - misalign,
        }
    }
}
