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

//! ## Two halves
//! Everything above is a bound over s ∈ [0, 1] from the start pose, with variation terms that
//! grow with the rotation over the piece. The bound is taken twice, over each half of the piece
//! from the firmware's pose at its middle (the firmware's axes at s = ½ are the mean of the
//! ends', the intended tip the mean of theirs; the half towards s = 0 runs backwards), so one
//! pose, one J̃₀⁻¹ and one rail position serve both halves and the middle's error below. On a
//! half, parametrised by s' = 2s − 1 (or 1 − 2s), each second derivative is ¼ of the one in s,
//! so `sup |H''|` and `sup |ω̇| + Ω²` over the piece are at most 4× the larger of the halves'
//! (each with half the rotation in its variation terms): about half the slack of a single bound
//! from s = 0 (bench ball, 3Z: pieces sampled 546 k → 313 k). The rails are checked along each
//! half.
//! Also `|ω − ω₀| ≤ min(δ|Δu|/Λ, (|Ã₀|_F + δ) Ω²)`: the second from `|ω̇| ≤ |Ã| Ω²` over s ≤ 1.
//!
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
//! or, tighter on short pieces, H''(0) computed exactly (ω₀, ẗ₀, ω̇₀ from J̃₀) plus how far each
//! of its four terms can move: `|ẗ − ẗ₀|, Λ|ω̇ − ω̇₀| ≤ σ` (below), `|Rv − R₀v₀| ≤ ΩV + |Δp|`
//! (ρ), `|ω − ω₀| ≤ δ|Δu|/Λ`; the smaller of the two is taken.
//!
//! **Accelerations at the start.** `x' = (Λω̇, ẗ) = J̃⁻¹ c`, `c = −(e₃·q₁, e₃·q₂, N₁·q₁, N₂·q₂)`:
//! exactly `x'₀ = J̃₀⁻¹ c₀` at the start, and along the piece
//! `|x' − x'₀| ≤ σ = δ Ω²Λ + K₀ ((Ω + |ω₀|) δ|Δu|/Λ + |ω₀|² Ω) Λ`
//! (`‖J̃⁻¹ − J̃₀⁻¹‖ |c|` and `K₀ |c − c₀|`, qᵢ's change from ω's and rᵢ's).
//!
//! **The rails.** Ball i slides along its rail at `dᵢ·(ṫ D + ω × rᵢ)`: exactly at the start,
//! and along the piece within `δ|Δu| √(1 + |l̂ᵢ|²/Λ²) + |ω₀| Ω |l̂ᵢ|` of it; the ball stays
//! within that (s ≤ 1) of its start slide.
//!
//! ## The tool axis (Lemmas 1, 3)
//! The tool axis is the world's vertical seen from the bed, `Rᵀe₃` ([`super::threez`]):
//! `(Rᵀe₃)' = −Rᵀ(ω × e₃)`, `(Rᵀe₃)'' = Rᵀ(ω × (ω × e₃)) − Rᵀ(ω̇ × e₃)`, so `|(Rᵀe₃)''| ≤ |ω̇| + Ω²`:
//! within `(|ω̇| + Ω²)/8` of its chord, and the slerp of the ends within `w²/8` of it
//! (w = ∠(n₀, n₁)); the angle is `2 asin(chord/2)` ([`bound::angle_of_chord`]).
//!
//! ## The middle (Lemma 1 with an end known)
//! The firmware's pose at s = ½ gives (Eq. 23) the tip error there, `e_m = |F(½) − p(½)|`, and
//! the tool axis' chord to the slerp there, `d_m`. On each half, parametrised by s' ∈ [0, 1]
//! from the piece's exact end, the error vanishes at s' = 0, is e_m at s' = 1 and has
//! `|e''| ≤ T` (T = the half's `sup |H''|` in s', above), so
//! `|e| ≤ s' e_m + s'(1 − s')T/2` ([`bound::deviation_with_end`]); the same for the tool axis
//! with `T = sup(|ω̇| + Ω²) + (w/2)²` (the firmware's axis and the half's slerp). The smaller of
//! this and the bound above is taken: near a piece's middle the error is known, not bounded.
//!
//! ## The tool axis in closed form (the lifted chord)
//! `(R l̂ᵢ)_z = uᵢ` (Eqs. 16–17) and `(R l̂ᵢ)_z = (Rᵀe₃)·l̂ᵢ`, so the firmware's tool axis
//! `F = Rᵀe₃` has `F·l̂ᵢ = uᵢ(s)`, linear in s (the firmware moves the motors linearly); the
//! l̂ᵢ are horizontal and span the plane (the balls are not collinear), so F's horizontal part
//! `x(s)` is linear in s, and `F_z = √(1 − |x|²)` (F_z > 0 at the ends, and |x(s)| is at most
//! the larger end's (convexity), so F_z never reaches 0 on a continuous pose). The ends realise
//! their requests (law 1), so `x(s) = (1 − s) n₀,xy + s n₁,xy` within the round trip: the
//! firmware's axis is the lifted chord `g(s) = (x, √(1 − |x|²))`, a function of n₀, n₁ alone.
//! Against the slerp S: `d = g − S` vanishes at both ends, `S'' = −w² S`, and
//! `g'' = (0, 0, z'')` with `z'' = −(|x'|² z² + (x·x')²)/z³`, `|z''| ≤ |x'|²/z³`
//! (`(x·x')² ≤ |x|²|x'|²`, `z² + |x|² = 1`), z ≥ z_min = √(1 − max |nᵢ,xy|²). So with
//! `M = |x'|²/z_min³ + w²`, d sampled at s = k/K ([`AXIS_SAMPLES`]) is within `M/(8K²)` of the
//! chord of its two nearest samples (Lemma 1 on an interval of 1/K), whose length is at most
//! the larger sample's: `|d| ≤ max_k |d(k/K)| + M/(8K²)`. On a conic layer at 30° this is about
//! 1.3 times the true deviation where the Lemma 1 sum above is about 5 times.
//!
//! ## Where the bound is not given (the piece is sampled)
//! The piece is not given a bound when an end is within [`LIMIT_MARGIN_MM`] of an axis limit,
//! when a ball comes within that margin of its rail's end (the intended path, within the bound
//! of the firmware's, must solve: `inverse` checks both),
//! when the tool axes leave the tilt cap ([`bound::arc_in_cap`]), or when `K₀ e ≥ ½`. The
//! branch of Eq. 11 the forward map takes is assumed to be the smooth one along the piece (the
//! other root is a pose about half a turn away); law 6 checks the bound against dense sampling.

use glam::{DMat4, DVec3, DVec4};

use super::bound;
use super::tessellate::Slerp;
use super::threez::{BedPose, ThreeZ};
use super::{Machine, PieceEnd};

/// How far (mm) the firmware path's axes and balls must stay from an axis limit or a rail end
/// for a closed form, so that the intended path (which `inverse` must solve) stays inside too.
/// An estimate, not a proof: the intended pose differs from the firmware's by at most the bound
/// (≤ 0.02 mm of tip, ≤ 0.1° of tool axis); 0.1° moves an axis by at most 500 mm × 1.75e-3 rad
/// = 0.87 mm on a bed under 500 mm, and a ball along its rail by about |l̂| sin 30° × 1.75e-3 rad
/// ≈ 0.3 mm (RatRig, at the largest tilt). Law 6 checks `inverse` at every sample.
pub const LIMIT_MARGIN_MM: f64 = 1.0;

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
    // Both halves of the piece, each from its own exact end pose (the firmware's axes at s = ½,
    // the mean of the ends', are each half's other end): on a half, with its parameter
    // s' = 2s or 2(1 − s), every derivative in s' is ¼ of that in s and the variation terms
    // (Neumann δ, spread, Ω) cover half the rotation, so sup |H''| over [0, 1] is at most four
    // times the larger half's sup, tighter than one bound from s = 0 over the whole piece.
    let am: Vec<f64> = a0.iter().zip(a1).map(|(x, y)| (x + y) / 2.0).collect();
    let pm = (p0 + p1) / 2.0;
    let middle = Start::new(m, &am)?;
    let (tip0, turn0) = second_derivatives(m, &middle, (&am, pm), (a0, p0))?;
    let (tip_half, turn_half) = {
        let (tip1, turn1) = second_derivatives(m, &middle, (&am, pm), (a1, p1))?;
        (tip0.max(tip1), turn0.max(turn1))
    };
    let (tip, turn) = (4.0 * tip_half, 4.0 * turn_half);
    let w = bound::angle(n0, n1);
    // the firmware's pose at s = ½ (module documentation, "The middle")
    let (fm, rm) = m.pose_at(&middle.pose, &am);
    let tip_bound =
        bound::chord_deviation(tip).min(bound::deviation_with_end((fm - pm).length(), tip_half));
    let nm = Slerp::new(n0, n1).at(0.5);
    let mut axis = (bound::chord_deviation(turn) + bound::chord_deviation(w * w)).min(
        bound::deviation_with_end((rm - nm).length(), turn_half + (w / 2.0) * (w / 2.0)),
    );
    if let Some(lifted) = lifted_axis_deviation(n0, n1, w) {
        axis = axis.min(lifted);
    }
    let (bp, ba) = (
        tip_bound + bound::ROUND_TRIP_SLACK_MM,
        bound::angle_of_chord(axis) + bound::ROUND_TRIP_SLACK_DEG,
    );
    (bp.is_finite() && ba.is_finite()).then_some((bp, ba))
}

/// Points `s = k/AXIS_SAMPLES` at which [`lifted_axis_deviation`] compares the firmware's tool
/// axis with the slerp; between them Lemma 1 on intervals of `1/AXIS_SAMPLES` adds
/// `M/(8·AXIS_SAMPLES²)`.
pub const AXIS_SAMPLES: usize = 4;

/// The firmware's tool axis at `s` on a piece whose ends realise `n0`, `n1` (above the
/// horizon): the lifted chord `g(s) = (x, √(1 − |x|²))`, `x = (1 − s) n₀,xy + s n₁,xy` (module
/// documentation).
pub fn lifted_axis(n0: DVec3, n1: DVec3, s: f64) -> DVec3 {
    let x = n0.truncate().lerp(n1.truncate(), s);
    x.extend((1.0 - x.length_squared()).sqrt())
}

/// The largest chord between the firmware's tool axis and the slerp of `n0`, `n1` (unit,
/// `w` apart) over the piece, from the lifted chord (module documentation, "The tool axis in
/// closed form"); `None` when an end is not above the horizon.
pub fn lifted_axis_deviation(n0: DVec3, n1: DVec3, w: f64) -> Option<f64> {
    let (x0, x1) = (n0.truncate(), n1.truncate());
    let r2 = x0.length_squared().max(x1.length_squared());
    if !(n0.z > 0.0 && n1.z > 0.0 && r2 < 1.0) {
        return None;
    }
    let z_min = (1.0 - r2).sqrt();
    // |d''| ≤ |g''| + |S''| ≤ |x'|²/z³ + w²
    let m = (x1 - x0).length_squared() / (z_min * z_min * z_min) + w * w;
    let slerp = Slerp::new(n0, n1);
    let mut worst = 0.0f64;
    for k in 1..AXIS_SAMPLES {
        let s = k as f64 / AXIS_SAMPLES as f64;
        worst = worst.max((lifted_axis(n0, n1, s) - slerp.at(s)).length());
    }
    let h = 1.0 / AXIS_SAMPLES as f64;
    let d = worst + bound::chord_deviation(m * h * h);
    d.is_finite().then_some(d)
}

/// What a bound from a start pose needs of that pose alone ([`second_derivatives`]): the bed's
/// pose, the balls' offsets `rᵢ = R l̂ᵢ` in the world, J̃₀⁻¹ with `|Ã₀|_F`, `|b̃₀|` and
/// `K₀ = ‖J̃₀⁻¹‖_F`, and each ball's slide along its rail.
struct Start {
    pose: BedPose,
    /// Λ (module documentation), mm.
    lambda: f64,
    /// r₁, r₂.
    r: [DVec3; 2],
    inv: DMat4,
    a_norm: f64,
    b_norm: f64,
    k0: f64,
    /// R l̂ᵢ and ball i's slide along its rail (i = 0, 1, 2), when the rails are limited.
    rails: Option<[(DVec3, f64); 3]>,
}

impl Start {
    /// The start pose of the axes `a0`; `None` where J̃₀ is (nearly) singular or no pose
    /// exists.
    fn new(m: &ThreeZ, a0: &[f64]) -> Option<Start> {
        let pose = m.bed_pose(a0).ok()?;
        let l = m.ball_offsets();
        let (d, nrm) = m.rails();
        let lambda = (l[1].length_squared() + l[2].length_squared()).sqrt();
        let dd = d[0].extend(0.0);
        let r = [pose.rotate(l[1]), pose.rotate(l[2])];
        let nn = [nrm[1].extend(0.0), nrm[2].extend(0.0)];
        let rows = [
            (r[0].cross(DVec3::Z) / lambda).extend(0.0),
            (r[1].cross(DVec3::Z) / lambda).extend(0.0),
            (r[0].cross(nn[0]) / lambda).extend(nn[0].dot(dd)),
            (r[1].cross(nn[1]) / lambda).extend(nn[1].dot(dd)),
        ];
        let j0 = DMat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose();
        let det = j0.determinant();
        if det.is_nan() || det.abs() < MIN_DETERMINANT {
            return None;
        }
        let inv = j0.inverse();
        let row = |i: usize| -> DVec4 { inv.row(i) };
        let a_norm =
            (row(0).length_squared() + row(1).length_squared() + row(2).length_squared()).sqrt();
        let b_norm = row(3).length();
        let rails = m.params().rail_travel_mm.map(|_| {
            [0, 1, 2].map(|i| {
                let ri = pose.rotate(l[i]);
                (ri, m.slide(i, d[0] * pose.tp + ri.truncate()))
            })
        });
        Some(Start {
            pose,
            lambda,
            r,
            inv,
            a_norm,
            b_norm,
            k0: a_norm.hypot(b_norm),
            rails,
        })
    }
}

/// The sup over the piece from the axes `a0` (tip `p0`, start pose `start`) to `a1` (`p1`) of
/// `|H''|` (the tip, mm per unit parameter²) and of `|ω̇| + Ω²` (the tool axis'
/// `|(Rᵀe₃)''|`), both from the start pose (module documentation), with the rails checked
/// along the way; `None` where no bound is given.
fn second_derivatives(
    m: &ThreeZ,
    start: &Start,
    (a0, p0): (&[f64], DVec3),
    (a1, p1): (&[f64], DVec3),
) -> Option<(f64, f64)> {
    let Start {
        pose: pose0,
        lambda,
        r,
        inv,
        a_norm,
        b_norm,
        k0,
        rails,
    } = *start;
    let l = m.ball_offsets();
    let (d, nrm) = m.rails();
    let dd = d[0].extend(0.0);
    let nn = [nrm[1].extend(0.0), nrm[2].extend(0.0)];
    let du_v = DVec4::new(
        (a1[2] - a1[3]) - (a0[2] - a0[3]),
        (a1[2] - a1[4]) - (a0[2] - a0[4]),
        0.0,
        0.0,
    );
    let du = du_v.length();
    // the velocity at the start, exactly: x₀ = J̃₀⁻¹ (Δu, 0); along the piece x is within δ|Δu|
    let x0 = inv * du_v;
    let w0 = x0.truncate().length();
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
    // the acceleration x' = (Λω̇, ẗ) = J̃⁻¹ c, c = −(e₃·q₁, e₃·q₂, N₁·q₁, N₂·q₂): at the start
    // exactly, and along the piece within ‖J̃⁻¹ − J̃₀⁻¹‖|c| + K₀|c − c₀| of it, where
    // |c| ≤ Ω²Λ and |c − c₀| ≤ ((Ω + |ω₀|) Δω + |ω₀|² Ω) Λ (|Δrᵢ| ≤ φ|l̂ᵢ| ≤ Ω|l̂ᵢ|), where
    // Δω bounds |ω − ω₀| along the piece: δ|Δu|/Λ (the Neumann bound of J̃⁻¹), or
    // sup |ω̇| ≤ (|Ã₀|_F + δ) Ω² (s ≤ 1), whichever is smaller
    let d_omega = (delta * du / lambda).min((a_norm + delta) * omega * omega);
    let omega0 = x0.truncate() / lambda;
    let c0 = |r: DVec3| omega0.cross(omega0.cross(r));
    let (q1, q2) = (c0(r[0]), c0(r[1]));
    let acc0 = inv * -DVec4::new(q1.z, q2.z, nn[0].dot(q1), nn[1].dot(q2));
    let w0l = w0 / lambda;
    let spread = delta * omega * omega * lambda
        + k0 * ((omega + w0l) * d_omega + w0l * w0l * omega) * lambda;
    let omega_dot =
        ((acc0.truncate().length() + spread) / lambda).min((a_norm + delta) * omega * omega);
    let t_ddot = (acc0.w.abs() + spread).min((b_norm + delta) * omega * omega * lambda);
    if let (Some([inward, outward]), Some(rails)) = (m.params().rail_travel_mm, rails) {
        // ball i slides along its rail at dᵢ·(ṫ D + ω × rᵢ): at the start exactly, and along the
        // piece within δ|Δu|·√(1 + |l̂ᵢ|²/Λ²) (|x − x₀| ≤ δ|Δu|) + |ω₀| Ω |l̂ᵢ| (|Δrᵢ| ≤ φ|l̂ᵢ|)
        // of it; over the piece (s ≤ 1) it slides at most that far from its start position
        for (i, (li, (ri, slide))) in l.iter().zip(rails).enumerate() {
            let v0 = d[i].dot((dd * x0.w + omega0.cross(ri)).truncate());
            let ratio = li.length() / lambda;
            let travel = v0.abs()
                + delta * du * (1.0 + ratio * ratio).sqrt()
                + w0 / lambda * omega * li.length();
            let room = travel + LIMIT_MARGIN_MM;
            if slide + room > inward || -slide + room > outward {
                return None;
            }
        }
    }
    let b0 = m.ball0();
    let v = (p0 - b0).length().max((p1 - b0).length());
    let dp = (p1 - p0).length();
    // H'' at the start exactly, and how far it can move along the piece: |Rv − R₀v₀| ≤ ΩV + |Δp|,
    // |ω − ω₀| ≤ δ|Δu|/Λ, |ω̇ − ω̇₀| and |ẗ − ẗ₀| within `spread` (/Λ)
    let rv0 = pose0.rotate(p0 - b0);
    let (omega_dot0, wdot0) = (acc0.truncate() / lambda, acc0.truncate().length() / lambda);
    let h0 = dd * acc0.w
        + omega_dot0.cross(rv0)
        + omega0.cross(omega0.cross(rv0))
        + 2.0 * omega0.cross(pose0.rotate(p1 - p0));
    let rho = omega * v + dp;
    let h_moves = spread
        + spread / lambda * v
        + wdot0 * rho
        + (omega + w0l) * d_omega * v
        + w0l * w0l * rho
        + 2.0 * (d_omega + w0l * omega) * dp;
    let tip =
        (h0.length() + h_moves).min(t_ddot + (omega_dot + omega * omega) * v + 2.0 * omega * dp);
    Some((tip, omega_dot + omega * omega))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::machine::spec::preset;
    use crate::num;
    use crate::test_rng::Lcg;

    fn ratrig() -> Box<dyn Machine> {
        preset("ratrig-vcore3-3z")
            .and_then(|s| s.build())
            .unwrap_or_else(|e| panic!("{e}"))
    }

    fn unit(tilt_deg: f64, azimuth_deg: f64) -> DVec3 {
        let (t, a) = (num::rad(tilt_deg), num::rad(azimuth_deg));
        DVec3::new(t.sin() * a.cos(), t.sin() * a.sin(), t.cos())
    }

    /// A piece's start axes and tool axis, end axes and tool axis, and whether it is conic.
    type TestPiece = (Vec<f64>, DVec3, Vec<f64>, DVec3, bool);

    /// Random pieces on the RatRig bed (tilts up to 30°, turns up to 8°, tips up to 3 mm
    /// apart) and conic ones (30° tilt, the azimuth turned): `(a₀, n₀, a₁, n₁, conic)`.
    fn pieces(m: &dyn Machine) -> Vec<TestPiece> {
        let mut rng = Lcg(0x3a2_5eed);
        let mut out = Vec::new();
        for i in 0..600 {
            let p0 = rng.within(DVec3::new(20.0, 20.0, 0.0), DVec3::new(280.0, 270.0, 150.0));
            let p1 = p0 + rng.within(DVec3::splat(-2.0), DVec3::splat(2.0));
            let (n0, n1) = if i % 2 == 0 {
                let a = rng.range(-180.0, 180.0);
                (unit(30.0, a), unit(30.0, a + rng.range(0.2, 8.0)))
            } else {
                let n0 = unit(rng.range(0.0, 29.0), rng.range(-180.0, 180.0));
                let about = n0
                    .cross(rng.within(DVec3::splat(-1.0), DVec3::ONE))
                    .normalize();
                let n1 = crate::machine::angles::rotate(n0, about, num::rad(rng.range(0.2, 8.0)));
                (n0, n1)
            };
            if num::deg(num::angle_between(n1, DVec3::Z)) > 30.0 {
                continue;
            }
            let (Ok(a0), Ok(a1)) = (m.inverse(p0, n0, None), m.inverse(p1, n1, None)) else {
                continue;
            };
            out.push((a0, n0, a1, n1, i % 2 == 0));
        }
        out
    }

    /// The great-circle interpolation from its definition (not the tessellation's `Slerp`).
    fn great_circle(n0: DVec3, n1: DVec3, s: f64) -> DVec3 {
        let w = n0.dot(n1).clamp(-1.0, 1.0).acos();
        (n0 * ((1.0 - s) * w).sin() + n1 * (s * w).sin()) / w.sin()
    }

    /// The fact the tool-axis closed form rests on: the firmware's axis, `forward` of the
    /// interpolated motor heights, is the lifted chord of the ends' axes.
    #[test]
    fn the_firmwares_tool_axis_is_the_lifted_chord() {
        let m = ratrig();
        let mut worst = 0.0f64;
        let all = pieces(m.as_ref());
        for (a0, n0, a1, n1, _) in &all {
            for k in 0..=50 {
                let s = k as f64 / 50.0;
                let axes: Vec<f64> = a0.iter().zip(a1).map(|(x, y)| x + (y - x) * s).collect();
                let f = m.forward(&axes).unwrap().1;
                let d = num::angle_between(f, lifted_axis(*n0, *n1, s));
                worst = worst.max(d);
                assert!(
                    d <= 1e-9,
                    "s {s}: forward {f} vs lifted {}, {d:e} rad",
                    lifted_axis(*n0, *n1, s)
                );
            }
        }
        eprintln!(
            "{} pieces, lifted chord within {worst:e} rad of forward",
            all.len()
        );
        assert!(all.len() > 400);
    }

    /// The closed form of the tool axis' deviation holds against the firmware's axis
    /// (`forward` of the interpolated axes) and the slerp, sampled at 1000 points, and is
    /// within 1.4 times it on the conic pieces (a conic layer's, the bench ball's) turning by
    /// 0.5° or more (elsewhere the true deviation can be far smaller than the `M/(8K²)` term).
    #[test]
    fn the_lifted_axis_bound_holds_and_is_tight() {
        let m = ratrig();
        let (mut count, mut loosest, mut tightest) = (0, 0.0f64, f64::INFINITY);
        for (a0, n0, a1, n1, conic) in pieces(m.as_ref()) {
            let w = num::angle_between(n0, n1);
            let bound = lifted_axis_deviation(n0, n1, w).expect("above the horizon");
            let mut sampled = 0.0f64;
            for k in 1..1000 {
                let s = k as f64 / 1000.0;
                let axes: Vec<f64> = a0.iter().zip(&a1).map(|(x, y)| x + (y - x) * s).collect();
                let f = m.forward(&axes).unwrap().1;
                sampled = sampled.max((f - great_circle(n0, n1, s)).length());
            }
            // the round trip of the ends (1e-9 rad each)
            assert!(
                sampled <= bound + 3e-9,
                "{n0} → {n1}: sampled chord {sampled:e} > bound {bound:e}"
            );
            tightest = tightest.min(bound / sampled.max(1e-300));
            if conic && num::deg(w) >= 0.5 {
                loosest = loosest.max(bound / sampled);
            }
            count += 1;
        }
        eprintln!("{count} pieces: bound / sampled from {tightest:.3} to {loosest:.3}");
        assert!(
            count > 400 && loosest <= 1.4,
            "the bound is {loosest}× the sampled deviation"
        );
    }

    /// Below the horizon (or on it) the lift is not the firmware's axis: no closed form.
    #[test]
    fn the_lifted_axis_bound_is_not_given_below_the_horizon() {
        let w = 0.1;
        assert!(lifted_axis_deviation(unit(30.0, 0.0), unit(95.0, 3.0), w).is_none());
        assert!(lifted_axis_deviation(unit(90.0, 0.0), unit(30.0, 3.0), w).is_none());
        assert!(lifted_axis_deviation(unit(30.0, 0.0), unit(29.0, 3.0), w).is_some());
    }
}
