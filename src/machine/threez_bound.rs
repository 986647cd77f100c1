//! The closed-form interpolation bound of the triple-Z bed ([`super::threez::ThreeZ`],
//! issue 13): the firmware moves X, Y, Z₀, Z₁, Z₂ linearly while the bed's pose is a nonlinear
//! function of the three motor heights (seed 001 §3.2). The bound is the second derivative of
//! the forward map along the piece (Lemma 1 of [`super::bound`]), from the rigid-body equations
//! of the bed on its rails.
//!
//! ## The bed as a rigid body (seed 001 §3, Eqs. 1–3, 16–23)
//! Bed space → world is the rotation `R` (R = R_{θ'} R₂ R₁); ball 0 is at `b̂₀ + t D` (D = (d₀, 0),
//! its rail direction, t the paper's t'), ball i at `b̂₀ + t D + rᵢ`, `rᵢ = R l̂ᵢ`,
//! `l̂ᵢ = b̂ᵢ − b̂₀` (horizontal in bed space). The pose (R, t) depends on the motor differences
//! `uᵢ = z₀ − zᵢ` (i = 1, 2) alone: `(rᵢ)_z = uᵢ` (Eqs. 16–17) and ball i stays in its vertical
//! rail plane, `Nᵢ·(t D + rᵢ) + kᵢ = 0`, `Nᵢ = (nᵢ, 0)` (Eq. 3; ball 0 moves along D, inside
//! its plane). The machine coordinates of a bed point p̂ are
//! `q = R (p̂ − b̂₀) + b̂₀ + t D` (Eq. 23 solved for (x, y, z₀)).
//!
//! ## Velocities and accelerations (s is the piece's parameter, u linear in s)
//! With ω the angular velocity (`rᵢ' = ω × rᵢ`), differentiating the four constraints:
//!
//! ```text
//! ω·(rᵢ × e₃) = uᵢ',   ω·(rᵢ × Nᵢ) + ṫ (Nᵢ·D) = 0            (i = 1, 2)
//! J̃ (Λω, ṫ) = (u₁', u₂', 0, 0),   J̃ = [ (rᵢ × e₃)ᵀ/Λ  0 ; (rᵢ × Nᵢ)ᵀ/Λ  Nᵢ·D ],   Λ = √(|l̂₁|² + |l̂₂|²)
//! J̃ (Λω̇, ẗ) = −(e₃·q₁, e₃·q₂, N₁·q₁, N₂·q₂),   qᵢ = ω × (ω × rᵢ)   (u'' = 0)
//! ```
//!
//! (Λ scales the rotation so every entry of J̃ is of order 1; Δu = u(1) − u(0).) So with `Ã`,
//! `b̃` the first three rows and the last row of J̃⁻¹: `|ω̇| ≤ |Ã| Ω²` and `|ẗ| ≤ |b̃| Ω² Λ`
//! (`|(e₃·qᵢ, Nᵢ·qᵢ)| ≤ |qᵢ| ≤ Ω²|l̂ᵢ|`, Ω = sup |ω|).
//!
//! ## J̃⁻¹ along the piece (Neumann series)
//! J̃₀ is J̃ at the piece's start pose (K₀ = ‖J̃₀⁻¹‖_F), `x₀ = J̃₀⁻¹ (Δu, 0)` the exact start
//! velocity (ω₀, ṫ₀). After a rotation by φ from the start pose, `|Δrᵢ| ≤ φ|l̂ᵢ|`, so
//! `‖J̃ − J̃₀‖_F ≤ √2 φ` (e₃ ⊥ Nᵢ, unit). Suppose `‖J̃⁻¹ − J̃₀⁻¹‖ ≤ δ` on [0, s]: then
//! `|x − x₀| ≤ δ|Δu|`, `φ ≤ Ω ≤ (|Λω₀| + δ|Δu|)/Λ`, `e = √2 Ω`, and when `K₀ e < ½` the
//! Neumann series gives `‖J̃⁻¹ − J̃₀⁻¹‖ ≤ g(δ) = K₀² e/(1 − K₀ e)`. From δ = K₀ (g(K₀) < K₀),
//! each step δ ← g(δ) is established on the whole piece by continuity (g increases with δ), and
//! J̃ stays invertible there (the pose is a smooth function of s). Then `|Ã| ≤ |Ã₀|_F + δ`,
//! `|b̃| ≤ |b̃₀| + δ` for the accelerations, and `|ṫ| ≤ |ṫ₀| + δ|Δu|` (the rails).

//! ## The tip (Lemma 1)
//! The firmware puts the machine coordinates on the chord `c(s)` of the ends'; the tip is then
//! `F(s) = Rᵀ(c(s) − t D − b̂₀) + b̂₀`. The intended tip p(s) would be at
//! `H(s) = R (p(s) − b̂₀) + b̂₀ + t D` (the same pose), so `|F(s) − p(s)| = |c(s) − H(s)|`, and
//! `H(0) = c(0)`, `H(1) = c(1)` (the ends are exact): the error is H's deviation from its chord,
//! at most `max|H''|/8` with
//!
//! ```text
//! H'' = ẗ D + ω̇ × R v + ω × (ω × R v) + 2 ω × R Δp,   v = p(s) − b̂₀,  Δp = p₁ − p₀
//! |H''| ≤ |ẗ| + (|ω̇| + Ω²) V + 2 Ω |Δp|,   V = max(|p₀ − b̂₀|, |p₁ − b̂₀|)
//! ```
//!
//! ## The tool axis (Lemmas 1, 3)
//! The tool axis is the bed normal R e₃ mirrored in x and y (an isometry), `|(R e₃)''| ≤ |ω̇| + Ω²`:
//! within `(|ω̇| + Ω²)/8` of its chord, and the slerp of the ends within `w²/8` of it
//! (w = ∠(n₀, n₁)); the angle is `2 asin(chord/2)` ([`bound::angle_of_chord`]).
//!
//! ## Where the bound is not given (the piece is sampled)
//! The piece is not given a bound when an end is within [`LIMIT_MARGIN_MM`] of an axis limit,
//! when an end's ball is within that margin, plus its travel along the piece, of its rail's
//! end (the intended path, within the bound of the firmware's, must solve: `inverse` checks both),
//! when the tool axes leave the tilt cap ([`bound::arc_in_cap`]), or when `K₀ e ≥ ½`. The
//! branch of Eq. 11 the forward map takes is assumed to be the smooth one along the piece (the
//! other root is a pose about half a turn away); law 6 checks the bound against dense sampling.

use glam::{DMat4, DVec3, DVec4};

use super::bound;
use super::threez::ThreeZ;
use super::{Machine, PieceEnd};

/// How far (mm) both ends' axes and balls must stay from an axis limit or a rail end for a
/// closed form: the intended path deviates from the firmware's by at most the bound
/// (0.02 mm, 0.1°), which moves an axis or a ball by about 1 mm at most on a bed under
/// 500 mm (0.1° = 1.75e-3 rad × 500 mm = 0.87 mm); five times that.
pub const LIMIT_MARGIN_MM: f64 = 5.0;

/// The Neumann series' limit: `K₀ e` must stay below this for J̃⁻¹ to be bounded by 2K₀.
pub const NEUMANN_LIMIT: f64 = 0.5;

/// Steps of the Neumann bound's fixed-point iteration (module documentation).
pub const NEUMANN_STEPS: usize = 4;

/// Smallest |det J̃₀| for which J̃₀ is inverted (a bed pose near a singular one: sample).
pub const MIN_DETERMINANT: f64 = 1e-9;

/// The 3Z bound of the piece `from` → `to` (module documentation), or `None`.
pub fn bound(m: &ThreeZ, from: PieceEnd, to: PieceEnd) -> Option<(f64, f64)> {
    let ((a0, p0, n0), (a1, p1, n1)) = (from, to);
    if !bound::usable(from, to, 5)
        || !bound::arc_in_cap(
            n0,
            n1,
            DVec3::Z,
            m.params().max_tilt_deg + super::LIMIT_SLACK_DEG,
        )
    {
        return None;
    }
    let inside = m.limits().iter().zip(a0.iter().zip(a1)).all(|(l, (x, y))| {
        x.min(*y) - LIMIT_MARGIN_MM >= l.min && x.max(*y) + LIMIT_MARGIN_MM <= l.max
    });
    if !inside {
        return None;
    }
    let pose0 = m.bed_pose(a0).ok()?;
    let l = m.ball_offsets();
    let (d, nrm) = m.rails();
    let lambda = (l[1].length_squared() + l[2].length_squared()).sqrt();
    let dd = d[0].extend(0.0);
    let r = [pose0.rotate(l[1]), pose0.rotate(l[2])];
    let nn = [nrm[1].extend(0.0), nrm[2].extend(0.0)];
    let rows = [
        (r[0].cross(DVec3::Z) / lambda).extend(0.0),
        (r[1].cross(DVec3::Z) / lambda).extend(0.0),
        (r[0].cross(nn[0]) / lambda).extend(nn[0].dot(dd)),
        (r[1].cross(nn[1]) / lambda).extend(nn[1].dot(dd)),
    ];
    let j0 = DMat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose();
    let det = j0.determinant();
    if !(det.abs() >= MIN_DETERMINANT) {
        return None;
    }
    let inv = j0.inverse();
    let row = |i: usize| -> DVec4 { inv.row(i) };
    let a_norm =
        (row(0).length_squared() + row(1).length_squared() + row(2).length_squared()).sqrt();
    let b_norm = row(3).length();
    let k0 = a_norm.hypot(b_norm);
    let du_v = DVec4::new(
        (a1[2] - a1[3]) - (a0[2] - a0[3]),
        (a1[2] - a1[4]) - (a0[2] - a0[4]),
        0.0,
        0.0,
    );
    let du = du_v.length();
    // the velocity at the start, exactly: x₀ = J̃₀⁻¹ (Δu, 0); along the piece x is within δ|Δu|
    let x0 = inv * du_v;
    let (w0, tdot0) = (x0.truncate().length(), x0.w.abs());
    // Neumann: with ‖J̃⁻¹ − J̃₀⁻¹‖ ≤ δ along the piece, φ ≤ (|Λω₀| + δ|Δu|)/Λ, e = √2 φ, and then
    // ‖J̃⁻¹ − J̃₀⁻¹‖ ≤ g(δ) = K₀² e/(1 − K₀ e); starting from δ = K₀, each g(δ) < δ is
    // established by continuity and g is increasing, so a few steps tighten δ
    let g = |delta: f64| {
        let e = core::f64::consts::SQRT_2 * (w0 + delta * du) / lambda;
        (k0 * e < NEUMANN_LIMIT).then(|| k0 * k0 * e / (1.0 - k0 * e))
    };
    let mut delta = k0;
    for _ in 0..NEUMANN_STEPS {
        match g(delta) {
            Some(next) if next <= delta => delta = next,
            Some(_) => break,
            None => return None,
        }
    }
    let omega = (w0 + delta * du) / lambda;
    let omega_dot = (a_norm + delta) * omega * omega;
    let t_ddot = (b_norm + delta) * omega * omega * lambda;
    if let Some([inward, outward]) = m.params().rail_travel_mm {
        // each ball moves along its rail by at most |ṫ| + Ω|l̂ᵢ| over the piece
        let t_dot = tdot0 + delta * du;
        let pose1 = m.bed_pose(a1).ok()?;
        for (i, li) in l.iter().enumerate() {
            let travel = t_dot + omega * li.length() + LIMIT_MARGIN_MM;
            for pose in [pose0, pose1] {
                let now = d[0] * pose.tp + pose.rotate(*li).truncate();
                let slide = m.slide(i, now);
                if slide + travel > inward || -slide + travel > outward {
                    return None;
                }
            }
        }
    }
    let b0 = m.ball0();
    let v = (p0 - b0).length().max((p1 - b0).length());
    let tip = t_ddot + (omega_dot + omega * omega) * v + 2.0 * omega * (p1 - p0).length();
    let w = bound::angle(n0, n1);
    let axis = bound::chord_deviation(omega_dot + omega * omega) + bound::chord_deviation(w * w);
    let (bp, ba) = (
        bound::chord_deviation(tip) + bound::ROUND_TRIP_SLACK_MM,
        bound::angle_of_chord(axis) + bound::ROUND_TRIP_SLACK_DEG,
    );
    (bp.is_finite() && ba.is_finite()).then_some((bp, ba))
}
