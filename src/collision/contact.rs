//! Contact, not collision: where the nozzle's tip may touch the material it prints on.
//!
//! ## The physical picture
//! The nozzle's flat face (radius `r_f`, about the tool axis `n`, at the tip `p`) presses the
//! bead it lays onto the layer's surface. A layer that is not normal to the tool axis meets the
//! face at an angle β (the angle between `n` and the layer's normal): a 3-axis nozzle printing a
//! 30° cone has β = 30°, the RTN's fixed 45° on a 30° cone 15°, a 5-axis head following the
//! normal ≈ 0. The layer's surface through the tip then rises, within the face and beside it,
//! up to `ρ·tan β` above the face's plane at distance ρ from the axis; and the beads already
//! laid beside the tip (the same layer's neighbours, the bead being extended, the bead below)
//! have flat tops a line width `w` wide (the face flattens them, [`super::material`]), so a
//! bead whose centre line is at ρ + w/2 still covers ρ. The face rides on that material: it is
//! contact (the bead is ironed), not a collision.
//!
//! ## The rule
//! In the tool frame (axial coordinate `s = n·(q − p)`, radius `ρ = |q − p − s n|`), material
//! at a point `q` inside the tip part (the head part that starts at the tip: the nozzle) is
//! contact when it lies on or under the **contact surface**
//!
//! ```text
//!     s ≤ (ρ + w/2) · tan β_max          (β_max = MAX_FACE_TILT_DEG; w/2 = 0 for the bed)
//! ```
//!
//! and a collision above it. The depth of a finding on a vertical line (x, y) through the part
//! is the length of the line that is both in the material, inside the part and above the
//! contact surface: `top − max(z_in, t₀)`, `top = min(h, z_out)`, t₀ where the line crosses the
//! contact surface, less one layer height `h` when the material is the current layer's (the
//! face presses the beads beside the one it lays by up to their own height: the RTN turning in
//! place at the tip sweeps its tilted face through the end of the bead it has just laid, 0.17 mm
//! on the 20 mm box). Every other part (heater block, heat sink, …) has no contact surface: any
//! overlap is a collision.
//!
//! What the rule still finds: the tip pressed into material more than `(w/2)·tan β_max`
//! (0.13 mm for a 0.45 mm line) straight below the face; material above the face's plane at the
//! rim steeper than β_max (a layer the face cannot ride); the nozzle's cone flank reaching
//! material beyond where a β_max surface through the tip meets it (for the default V6 nozzle,
//! 40° half-angle, r_f = 0.5 mm, that is ρ > (r_f + (w/2) tan β tan ψ) / (1 − tan β tan ψ) =
//! 1.18 mm, s > 0.81 mm); and any material below the tip's own layer that the face reaches,
//! since the older layers lie at least a layer height under the current surface.
//!
//! ## Monotone along a vertical line
//! On the line `q(t) = (x, y, t)`, `v(t) = s(t) − (ρ(t) + w/2) tan β` has
//! `v'(t) = n_z − tan β · ρ'(t) ≥ cos θ − tan β sin θ` (θ the tool's tilt from vertical, since
//! `|ρ'| ≤ sin θ`), which is positive while θ < 90° − β_max (60°): the part above the contact
//! surface is one interval ending at the top, and t₀ is found in closed form (a quadratic,
//! `ContactSurface::crossing`), by bisection where no root checks out. For steeper tilts
//! the rule is not applied (the whole overlap counts: more findings, never fewer).

use glam::DVec3;

/// β_max: the largest angle between the tool axis and the layer's normal at which the nozzle's
/// flat face still rides on the layer, degrees. 30°: the acceptance warps' slope (conic 30°
/// printed by a vertical nozzle), seed 001's tilt limit of the triple-Z bed (≤ 30°) and the
/// usual limit of non-planar printing with a 40° nozzle cone; a steeper layer is ploughed by
/// the nozzle's flank, which the rule then reports.
pub const MAX_FACE_TILT_DEG: f64 = 30.0;

/// Bisection steps for t₀: the vertical lines the check meets are at most a few mm inside a
/// part, so 40 halvings leave < 1e-11 mm.
const BISECTION_STEPS: usize = 40;

/// The contact surface of one pose of the tip part (see the module documentation).
#[derive(Clone, Copy, Debug)]
pub struct ContactSurface {
    p: DVec3,
    n: DVec3,
    half_width: f64,
    tan_beta: f64,
    /// `sin θ = √(1 − n_z²)`, the tool's tilt from vertical (computed once per pose: the block
    /// and row bounds ask for it at every block and row of a search).
    sin_t: f64,
    monotone: bool,
}

impl ContactSurface {
    /// The surface for the tip at `p`, tool axis `n` (unit), beads of width `width` (mm; 0 for
    /// the bed).
    pub fn new(p: DVec3, n: DVec3, width: f64) -> ContactSurface {
        static TAN_BETA: std::sync::OnceLock<f64> = std::sync::OnceLock::new();
        let tan_beta =
            *TAN_BETA.get_or_init(|| crate::num::tan(crate::num::rad(MAX_FACE_TILT_DEG)));
        // cos θ − tan β sin θ > 0 (module documentation)
        let sin_t = (1.0 - n.z * n.z).max(0.0).sqrt();
        ContactSurface {
            p,
            n,
            half_width: 0.5 * width,
            tan_beta,
            sin_t,
            monotone: n.z - tan_beta * sin_t > 0.0,
        }
    }

    /// A lower bound of the height of the points above the contact surface on the vertical
    /// line through (x, y) (−∞: none known), cheap enough to skip a line before the exact test.
    ///
    /// A point `q` above the surface has `s > (ρ + c) T` (`c = w/2`, `T = tan β_max`), lies within
    /// `s sin θ + ρ` of the tip horizontally (θ the tool's tilt) and has
    /// `q_z − p_z ≥ s n_z − ρ sin θ`. For θ ≤ β_max (`T n_z ≥ sin θ`) that is smallest on the
    /// surface at the least ρ that reaches the line's horizontal distance D:
    /// `ρ_min = max(0, (D − c T sin θ)/(1 + T sin θ))`, giving
    /// `p_z + ρ_min (T n_z − sin θ) + c T n_z`.
    pub fn floor_at(&self, x: f64, y: f64) -> f64 {
        let (dx, dy) = (x - self.p.x, y - self.p.y);
        self.floor_at_distance((dx * dx + dy * dy).sqrt())
    }

    /// A lower bound of [`ContactSurface::floor_at`] over the square of centre `c` and half
    /// side `half` seen from above: the bound at the square's least distance from the tip (it
    /// grows with the distance).
    pub fn floor_over_square(&self, c: glam::DVec2, half: f64) -> f64 {
        self.floor_at_distance(super::solid::square_distance(self.p.truncate(), c, half))
    }

    /// A lower bound of [`ContactSurface::floor_at`] on every vertical line, as computed: its
    /// value at distance 0 (`p_z + c T n_z`, or −∞ where `T n_z < sin θ`), known before any
    /// distance is measured.
    ///
    /// It holds for the computed doubles, not only for the real numbers: at distance `d ≥ 0`,
    /// `ρ_min = max(0, ·) ≥ 0` where at 0 it is 0 (`−c T sin θ / (1 + T sin θ) ≤ 0`); with
    /// the gain `g = T n_z − sin θ ≥ 0` (else both are −∞) the product `ρ_min·g` rounds to
    /// at least 0, and `p_z + ρ_min g`, then `+ c T n_z`, are roundings of sums that do not
    /// decrease with it (IEEE rounding is monotone). The check's per-pose search for the
    /// deepest cell turns a cell away on its top against this one value before it pays for the
    /// distances (`crate::collision::sweep`, `penetrations`).
    pub fn floor_anywhere(&self) -> f64 {
        self.floor_at_distance(0.0)
    }

    /// [`ContactSurface::floor_at`] of a vertical line at horizontal distance `d` from the tip
    /// (the bound depends on that distance only, and does not decrease with it).
    pub fn floor_at_distance(&self, d: f64) -> f64 {
        let sin_t = self.sin_t;
        let t = self.tan_beta;
        let gain = t * self.n.z - sin_t;
        if gain < 0.0 {
            return f64::NEG_INFINITY;
        }
        let rho = ((d - self.half_width * t * sin_t) / (1.0 + t * sin_t)).max(0.0);
        self.p.z + rho * gain + self.half_width * t * self.n.z
    }

    /// An upper bound of [`ContactSurface::excess`] over the horizontal square of centre `c`
    /// and half side `half` (seen from above) at height `z`, mm: where it is ≤ 0 no point of
    /// the square at that height, nor (where the rule applies: `v` grows with z, module
    /// documentation "Monotone") below it, lies above the contact surface.
    ///
    /// `v(q) = n·d − T·|P d| − cT` (`d = q − p`, `P = I − n nᵀ`, c = w/2, T = tan β_max) is
    /// **concave**: `n·d` is linear and `|P d|`, a norm of a linear map, is convex. A concave
    /// function lies under each of its tangent planes: with `q₀ = (c, z)` and the supergradient
    /// `g = n − T·P d₀/|P d₀|` (`g = n` on the axis, where `|P d|` has the subgradient 0),
    /// `v(q) ≤ v(q₀) + g·(q − q₀)` for every q, and over the square (`q − q₀` horizontal,
    /// `|Δx|, |Δy| ≤ half`) the right side is at most `v(q₀) + (|g_x| + |g_y|)·half`. Unlike
    /// [`ContactSurface::floor_over_square`] (a bound of heights, flat for a tool tilted by
    /// β_max) it follows the surface in the tool frame: the layer rising beside a tilted
    /// nozzle lies at `s ≈ 0`, far under the surface, and its blocks are skipped whole.
    pub fn excess_over_square(&self, c: glam::DVec2, half: f64, z: f64) -> f64 {
        let d = DVec3::new(c.x, c.y, z) - self.p;
        let s = self.n.dot(d);
        let perp = d - self.n * s;
        let rho = perp.length();
        let g = if rho > 0.0 {
            self.n - perp * (self.tan_beta / rho)
        } else {
            self.n
        };
        s - (rho + self.half_width) * self.tan_beta + (g.x.abs() + g.y.abs()) * half
    }

    /// A horizontal radius about the tip outside which no point above the contact surface is
    /// below height `m` (`None`: none known): where [`ContactSurface::floor_at`] reaches `m`,
    /// `D = ρ (1 + T sin θ) + c T sin θ` with `ρ = (m − p_z − c T n_z)/(T n_z − sin θ)`.
    pub fn radius_below(&self, m: f64) -> Option<f64> {
        let sin_t = self.sin_t;
        let t = self.tan_beta;
        let gain = t * self.n.z - sin_t;
        if gain <= 1e-12 {
            return None;
        }
        let rho = ((m - self.p.z - self.half_width * t * self.n.z) / gain).max(0.0);
        Some(rho * (1.0 + t * sin_t) + self.half_width * t * sin_t)
    }

    /// [`ContactSurface::radius_below`] with its centre: the disc (seen from above, about the
    /// tip) outside which no point above the contact surface is below height `m`.
    pub fn disc_below(&self, m: f64) -> Option<(glam::DVec2, f64)> {
        self.radius_below(m).map(|r| (self.p.truncate(), r))
    }

    /// Whether the rule applies at this pose (the tool's tilt below `90° − β_max`, where the
    /// part above the surface is one interval of a vertical line; steeper, every overlap counts:
    /// [`ContactSurface::depth_above`]).
    pub fn applies(&self) -> bool {
        self.monotone
    }

    /// The surface moved back along the tool axis so that the region above it contains every
    /// point within `delta` (mm) of the region above this one: `v = s − (ρ + c)·T` changes by at
    /// most `|∇v| = √(1 + T²)` per mm moved (its gradient is `n − T·ρ̂`), so the tip moves by
    /// `−delta·√(1 + T²)·n`. With [`super::solid::Posed::dilated`] it bounds the nozzle's depth
    /// over a stretch of poses whose points move at most `delta` (`crate::collision::sweep`).
    pub fn grown(&self, delta: f64) -> ContactSurface {
        ContactSurface {
            p: self.p - self.n * (delta * (1.0 + self.tan_beta * self.tan_beta).sqrt()),
            ..*self
        }
    }

    /// The same pose against a plane (the bed): no half bead (w = 0).
    pub fn for_plane(&self) -> ContactSurface {
        ContactSurface {
            half_width: 0.0,
            ..*self
        }
    }

    /// `v(q) = s − (ρ + w/2)·tan β_max`: how far `q` stands above the contact surface along the
    /// tool axis (≤ 0: contact).
    pub fn excess(&self, q: DVec3) -> f64 {
        let d = q - self.p;
        let s = self.n.dot(d);
        let rho = (d.length_squared() - s * s).max(0.0).sqrt();
        s - (rho + self.half_width) * self.tan_beta
    }

    /// Whether the point (x, y, z) lies above the contact surface, where the rule applies
    /// ([`ContactSurface::applies`]; elsewhere every point counts: true). Above it along the
    /// line is one interval ending at the top (module documentation, "Monotone"), so a line
    /// whose material top `h` has `above_at(x, y, h − tol)` false has at most `tol` of its
    /// material above the surface: [`ContactSurface::depth_above`] ≤ tol for any `z_in`.
    pub fn above_at(&self, x: f64, y: f64, z: f64) -> bool {
        !self.monotone || self.excess(DVec3::new(x, y, z)) > 0.0
    }

    /// The x-interval of the row `y` at height `z` whose points lie above the contact surface
    /// (`None`: no point; unbounded ends where the rule does not bound it), widened by
    /// [`CROSSING_SLACK_MM`]. With `d = q − p = (Δx, Δy, Δz)`, `s = n_x Δx + s₁`
    /// (`s₁ = n_y Δy + n_z Δz`) and `ρ² = Δx² + e − s²` (`e = Δy² + Δz²`), "above" is
    /// `s − cT > Tρ`: `s > cT` and `(1 + T²)s² − 2cTs + c²T² − T²(Δx² + e) > 0`, a quadratic
    /// `A Δx² + B Δx + C > 0` with `A = (1 + T²)n_x² − T²`, `B = 2n_x((1 + T²)s₁ − cT)`,
    /// `C = (1 + T²)s₁² − 2cTs₁ + c²T² − T²e`. For `A < 0` (the tool leaning less than β_max in
    /// x) it holds between the roots (the two nappes of `|s − cT| > Tρ` meet only at the apex,
    /// so `s > cT` keeps the upper one's interval); otherwise no bound is taken.
    pub fn above_on_row(&self, y: f64, z: f64) -> Option<(f64, f64)> {
        const ALL: Option<(f64, f64)> = Some((f64::NEG_INFINITY, f64::INFINITY));
        if !self.monotone {
            return ALL;
        }
        let (n, t, c) = (self.n, self.tan_beta, self.half_width);
        let (dy, dz) = (y - self.p.y, z - self.p.z);
        let s1 = n.y * dy + n.z * dz;
        let k = 1.0 + t * t;
        let a = k * n.x * n.x - t * t;
        if a > -ROW_BOUND_MIN_CURVATURE {
            return ALL;
        }
        let b = 2.0 * n.x * (k * s1 - c * t);
        let cc = k * s1 * s1 - 2.0 * c * t * s1 + c * c * t * t - t * t * (dy * dy + dz * dz);
        let disc = b * b - 4.0 * a * cc;
        if disc < 0.0 {
            return None;
        }
        let root = disc.sqrt();
        // a < 0: the quadratic is positive between (−b ± √disc)/(2a)
        let (r1, r2) = ((-b + root) / (2.0 * a), (-b - root) / (2.0 * a));
        let (mut lo, mut hi) = (r1.min(r2), r1.max(r2));
        // and s = n_x Δx + s₁ > cT
        if n.x.abs() > 1e-12 {
            let edge = (c * t - s1) / n.x;
            if n.x > 0.0 {
                lo = lo.max(edge);
            } else {
                hi = hi.min(edge);
            }
        } else if s1 <= c * t {
            return None;
        }
        let slack = CROSSING_SLACK_MM * (1.0 + self.p.abs().max_element());
        (lo <= hi).then_some((self.p.x + lo - slack, self.p.x + hi + slack))
    }

    /// The length of the vertical line (x, y) between `z_in` and `top` (the material inside the
    /// part) that lies above the contact surface, mm.
    pub fn depth_above(&self, x: f64, y: f64, z_in: f64, top: f64) -> f64 {
        if top <= z_in {
            return 0.0;
        }
        if !self.monotone {
            return top - z_in;
        }
        let v = |t: f64| self.excess(DVec3::new(x, y, t));
        if v(top) <= 0.0 {
            return 0.0;
        }
        if v(z_in) > 0.0 {
            return top - z_in;
        }
        // v(z_in) ≤ 0 < v(top): one crossing (monotone), in closed form when it checks out
        if let Some(t0) = self.crossing(x, y, z_in, top) {
            return top - t0;
        }
        let (mut lo, mut hi) = (z_in, top);
        for _ in 0..BISECTION_STEPS {
            let mid = 0.5 * (lo + hi);
            if v(mid) > 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        top - hi
    }

    /// Where the vertical line (x, y) crosses the contact surface between `lo` and `hi`, in
    /// closed form (None: no root checks out, bisect instead). With `u = t − p_z`,
    /// `s(u) = s₀ + n_z u` (`s₀ = n_x Δx + n_y Δy`), `|q − p|² = D² + u²` and `ρ² = |q − p|² − s²`,
    /// `v = 0` is `s − cT = T ρ` (c = w/2, T = tan β_max) with `s − cT ≥ 0`; squared,
    /// `(s − cT)² + T² s² − T² (D² + u²) = 0`, the quadratic `A u² + B u + C = 0` with
    /// `A = (1 + T²) n_z² − T²`, `B = 2 n_z ((1 + T²) s₀ − cT)`,
    /// `C = (1 + T²) s₀² − 2cT s₀ + c²T² − T² D²`. A root counts when it lies in `[lo, hi]`
    /// (within [`CROSSING_SLACK_MM`]) and `|v|` there is below that slack too.
    fn crossing(&self, x: f64, y: f64, lo: f64, hi: f64) -> Option<f64> {
        let (dx, dy) = (x - self.p.x, y - self.p.y);
        let (n, t, c) = (self.n, self.tan_beta, self.half_width);
        let s0 = n.x * dx + n.y * dy;
        let k = 1.0 + t * t;
        let a = k * n.z * n.z - t * t;
        let b = 2.0 * n.z * (k * s0 - c * t);
        let cc = k * s0 * s0 - 2.0 * c * t * s0 + c * c * t * t - t * t * (dx * dx + dy * dy);
        let roots: [Option<f64>; 2] = if a.abs() < 1e-12 {
            [(b.abs() > 1e-300).then(|| -cc / b), None]
        } else {
            let disc = b * b - 4.0 * a * cc;
            if disc < 0.0 {
                return None;
            }
            // the stable pair: q = −(b + sign(b)·√disc)/2, roots q/a and c/q
            let q = -0.5 * (b + b.signum() * disc.sqrt());
            [Some(q / a), (q.abs() > 1e-300).then(|| cc / q)]
        };
        roots
            .into_iter()
            .flatten()
            .map(|u| u + self.p.z)
            .find(|&t0| {
                t0 >= lo - CROSSING_SLACK_MM
                    && t0 <= hi + CROSSING_SLACK_MM
                    && self.excess(DVec3::new(x, y, t0)).abs() <= CROSSING_SLACK_MM
            })
            .map(|t0| t0.clamp(lo, hi))
    }
}

/// `|A|` below which [`ContactSurface::above_on_row`] takes no bound: a tool leaning nearly
/// β_max in x makes the row's interval long and its roots ill-conditioned (dimensionless; the
/// per-cell test still decides).
const ROW_BOUND_MIN_CURVATURE: f64 = 1e-6;

/// How far a closed-form crossing of the contact surface may lie outside the line's interval,
/// and how far from the surface (along the tool axis) it may be, mm: rounding of the quadratic's
/// coefficients (a few 1e-15 relative on mm-sized values), far below the check's
/// [`super::sweep::CONTACT_TOLERANCE_MM`] (0.05 mm).
const CROSSING_SLACK_MM: f64 = 1e-9;

#[cfg(test)]
mod tests {
    use super::*;

    /// The contact rule's `s − (ρ + c)·T` for tip `p`, axis `n`, half width `c`, `T = tb`,
    /// written here from the module documentation (the tests' oracle, not
    /// [`ContactSurface::excess`]).
    fn rule_excess(p: DVec3, n: DVec3, q: DVec3, c: f64, tb: f64) -> f64 {
        let d = q - p;
        let s = n.dot(d);
        let rho = (d.length_squared() - s * s).max(0.0).sqrt();
        s - (rho + c) * tb
    }

    #[test]
    fn a_vertical_nozzle_on_a_30_degree_layer_is_contact_and_a_plunge_is_not() {
        let c = ContactSurface::new(DVec3::ZERO, DVec3::Z, 0.45);
        let t30 = 30f64.to_radians().tan();
        // the layer's surface through the tip, rising 30°, and the uphill bead's flat top
        // reaching w/2 further: contact at the face's rim (ρ = 0.5)
        assert!(c.depth_above(0.5, 0.0, 0.0, 0.5 * t30) == 0.0);
        assert!(c.depth_above(0.5, 0.0, 0.0, (0.5 + 0.225) * t30 - 1e-9) == 0.0);
        // 0.1 mm above that surface: 0.1 mm of the line is above it
        let d = c.depth_above(0.5, 0.0, 0.0, (0.5 + 0.225) * t30 + 0.1);
        assert!((d - 0.1).abs() < 1e-9, "{d}");
        // straight below the face, pressed 0.5 mm in: all but (w/2)·tan 30° is a collision
        let d = c.depth_above(0.0, 0.0, 0.0, 0.5);
        assert!((d - (0.5 - 0.225 * t30)).abs() < 1e-9, "{d}");
        // the bed (w = 0) under a tip 0.2 mm into it
        let bed = ContactSurface::new(DVec3::ZERO, DVec3::Z, 0.0);
        assert!((bed.depth_above(0.0, 0.0, 0.0, 0.2) - 0.2).abs() < 1e-9);
    }

    #[test]
    fn the_floor_bound_is_below_every_point_above_the_contact_surface() {
        // brute force over tilts, lines and heights: every point above the surface is above
        // the bound
        for tilt in [0.0f64, 10.0, 25.0, 30.0] {
            let n = DVec3::new(tilt.to_radians().sin(), 0.0, tilt.to_radians().cos());
            let c = ContactSurface::new(DVec3::new(1.0, 2.0, 3.0), n, 0.45);
            for (x, y) in [(1.0, 2.0), (1.3, 2.0), (0.2, 2.5), (3.0, 0.0), (1.0, 4.0)] {
                let floor = c.floor_at(x, y);
                let mut z = -5.0;
                while z < 10.0 {
                    if c.excess(DVec3::new(x, y, z)) > 0.0 {
                        assert!(z >= floor - 1e-9, "tilt {tilt} ({x}, {y}): {z} < {floor}");
                    }
                    z += 0.001;
                }
            }
        }
    }

    /// [`ContactSurface::floor_anywhere`] is at most [`ContactSurface::floor_at`] of every
    /// vertical line, compared as computed doubles (the per-pose search turns cells away on it
    /// in place of `floor_at`, so one ulp above would drop a cell the full test keeps), and the
    /// oracle written here from the rule (`rule_excess`, not the engine's) finds no point above
    /// the surface below it: random tips, tilts up to 70° (the gain negative beyond 30°), widths
    /// (0 for the bed), lines from on the axis out to 3 mm, the first 0.3 mm finely.
    #[test]
    fn the_floor_anywhere_is_under_the_floor_of_every_line_as_computed() {
        let tb = 30f64.to_radians().tan();
        let mut rng = crate::test_rng::Lcg(0x5eed_0018);
        let (mut lines, mut raised, mut finite) = (0, 0, 0);
        for case in 0..300 {
            let (tilt, az) = (
                rng.range(0.0, 70.0).to_radians(),
                rng.range(0.0, 360.0).to_radians(),
            );
            let n = DVec3::new(tilt.sin() * az.cos(), tilt.sin() * az.sin(), tilt.cos());
            let p = DVec3::new(
                rng.range(-50.0, 50.0),
                rng.range(-50.0, 50.0),
                rng.range(0.0, 40.0),
            );
            let w = if case % 5 == 0 {
                0.0
            } else {
                rng.range(0.3, 0.8)
            };
            let surf = ContactSurface::new(p, n, w).grown(rng.range(0.0, 0.3));
            let low = surf.floor_anywhere();
            finite += usize::from(low.is_finite());
            for k in 0..120 {
                let d = if k < 60 {
                    0.005 * k as f64
                } else {
                    rng.range(0.3, 3.0)
                };
                let a = rng.range(0.0, std::f64::consts::TAU);
                let (x, y) = (p.x + d * a.cos(), p.y + d * a.sin());
                let floor = surf.floor_at(x, y);
                assert!(
                    low <= floor,
                    "case {case}: tilt {:.1}°, width {w}, line at {d:.3} mm: floor_anywhere {low} above floor_at {floor}",
                    tilt.to_degrees()
                );
                lines += 1;
                raised += usize::from(floor > low);
                // the oracle: no point of the line above the surface lies under the bound
                let pg = surf.p;
                let mut z = low - 1.0;
                while z < low {
                    assert!(
                        !surf.applies() || rule_excess(pg, n, DVec3::new(x, y, z), 0.5 * w, tb) <= 1e-12,
                        "case {case}: ({x}, {y}, {z}) is above the surface under floor_anywhere {low}"
                    );
                    z += 0.01;
                }
            }
        }
        // the bound is finite where the gain allows (tilts under 30°), and many lines' floors
        // rise above it (it is not the floor itself: the others are tilts beyond 30°, both
        // −∞, and lines within `c T sin θ` of the axis, where ρ_min is 0 too)
        assert!(
            finite > 60 && raised > lines / 3,
            "{finite} finite bounds, {raised} of {lines} lines above"
        );
    }

    #[test]
    fn the_square_bound_is_above_the_excess_at_every_point_of_the_square() {
        // brute force on a 0.02 mm grid of each square (excess written from the rule here, not
        // the engine's): the bound is at least the largest excess over the square, so a square
        // it puts under the surface has no point above it; and it skips squares beside a
        // tilted tool that the height bound (floor_over_square) keeps, or it cuts nothing
        let (tb, c) = (30f64.to_radians().tan(), 0.225);
        let excess = |p: DVec3, n: DVec3, q: DVec3| rule_excess(p, n, q, c, tb);
        let (mut skipped, mut skipped_only_here) = (0, 0);
        for tilt in [0.0f64, 15.0, 30.0, 45.0] {
            for az in [0.0f64, 100.0, 225.0] {
                let (t, a) = (tilt.to_radians(), az.to_radians());
                let n = DVec3::new(t.sin() * a.cos(), t.sin() * a.sin(), t.cos());
                let p = DVec3::new(1.0, 2.0, 3.0);
                let surf = ContactSurface::new(p, n, 2.0 * c).grown(0.3);
                let pg = p - n * (0.3 * (1.0 + tb * tb).sqrt());
                for (cx, cy) in [(1.0, 2.0), (1.9, 2.3), (-0.5, 1.0), (3.5, 2.0), (1.0, 5.0)] {
                    for half in [0.1, 0.8, 3.2] {
                        for dz in [-1.0, -0.3, 0.0, 0.2, 1.0] {
                            let z = p.z + dz;
                            let ctr = glam::DVec2::new(cx, cy);
                            let bound = surf.excess_over_square(ctr, half, z);
                            let mut worst = f64::NEG_INFINITY;
                            for i in 0..=40 {
                                for j in 0..=40 {
                                    let x = cx - half + 2.0 * half * i as f64 / 40.0;
                                    let y = cy - half + 2.0 * half * j as f64 / 40.0;
                                    worst = worst.max(excess(pg, n, DVec3::new(x, y, z)));
                                }
                            }
                            assert!(
                                bound >= worst - 1e-12,
                                "tilt {tilt} az {az} square ({cx}, {cy}) ±{half} at z {z}: bound {bound} < {worst}"
                            );
                            if bound <= 0.0 {
                                skipped += 1;
                                if surf.floor_over_square(ctr, half) < z {
                                    skipped_only_here += 1;
                                }
                            }
                        }
                    }
                }
            }
        }
        assert!(
            skipped > 100 && skipped_only_here > 30,
            "{skipped} squares under the surface, {skipped_only_here} of them above the height bound"
        );
    }

    #[test]
    fn the_closed_form_crossing_equals_bisection() {
        // bisection on v written here (not the engine's): every tilt, azimuth and line where the
        // surface is crossed
        for tilt in [0.0f64, 10.0, 30.0, 45.0, 55.0] {
            for az in [0.0f64, 70.0, 200.0] {
                let (t, a) = (tilt.to_radians(), az.to_radians());
                let n = DVec3::new(t.sin() * a.cos(), t.sin() * a.sin(), t.cos());
                let c = ContactSurface::new(DVec3::new(1.0, 2.0, 3.0), n, 0.45);
                for (x, y) in [(1.0, 2.0), (1.3, 2.1), (0.4, 2.5), (2.5, 1.0)] {
                    let (lo, hi) = (1.0, 6.0);
                    let v = |z: f64| c.excess(DVec3::new(x, y, z));
                    if v(lo) > 0.0 || v(hi) <= 0.0 {
                        continue;
                    }
                    let (mut a, mut b) = (lo, hi);
                    for _ in 0..60 {
                        let m = 0.5 * (a + b);
                        if v(m) > 0.0 {
                            b = m
                        } else {
                            a = m
                        }
                    }
                    let got = c.depth_above(x, y, lo, hi);
                    assert!(
                        (got - (hi - b)).abs() < 1e-8,
                        "tilt {tilt} az {az} ({x}, {y}): {got} vs {}",
                        hi - b
                    );
                }
            }
        }
    }

    #[test]
    fn a_rows_interval_holds_every_point_above_the_surface_and_little_else() {
        // brute force on a 0.001 mm grid of each row (excess written from the rule here, not
        // the engine's): every point above the surface is inside the interval, and the interval
        // is no wider than the points above it (plus the grid and the slack)
        let (tb, c) = (30f64.to_radians().tan(), 0.225);
        let above = |p: DVec3, n: DVec3, q: DVec3| rule_excess(p, n, q, c, tb) > 0.0;
        let mut bounded = 0;
        for tilt in [0.0f64, 10.0, 25.0, 29.0, 45.0, 55.0] {
            for az in [0.0f64, 70.0, 180.0, 250.0] {
                let (t, a) = (tilt.to_radians(), az.to_radians());
                let n = DVec3::new(t.sin() * a.cos(), t.sin() * a.sin(), t.cos());
                let p = DVec3::new(1.0, 2.0, 3.0);
                let surf = ContactSurface::new(p, n, 2.0 * c);
                if !surf.applies() {
                    continue;
                }
                for (y, z) in [(2.0, 3.1), (2.3, 3.0), (1.6, 3.4), (2.0, 2.9), (3.5, 4.5)] {
                    let got = surf.above_on_row(y, z);
                    let xs: Vec<f64> = (-4000..=6000)
                        .map(|i| i as f64 * 0.001)
                        .filter(|&x| above(p, n, DVec3::new(x, y, z)))
                        .collect();
                    match got {
                        None => assert!(
                            xs.is_empty(),
                            "tilt {tilt} az {az} row ({y}, {z}): None but {} points above",
                            xs.len()
                        ),
                        Some((lo, hi)) => {
                            for &x in &xs {
                                assert!(
                                    x >= lo && x <= hi,
                                    "tilt {tilt} az {az} row ({y}, {z}): {x} outside [{lo}, {hi}]"
                                );
                            }
                            if lo.is_finite() && hi.is_finite() {
                                bounded += 1;
                                // ends inside the grid's span are within a grid step of the points
                                let (a, b) = (
                                    xs.first().copied().unwrap_or(lo),
                                    xs.last().copied().unwrap_or(hi),
                                );
                                let inside = |x: f64| (-3.99..5.99).contains(&x);
                                assert!(!inside(lo) || a - lo <= 0.0011, "tilt {tilt} az {az} row ({y}, {z}): [{lo}, {hi}] vs points [{a}, {b}]");
                                assert!(!inside(hi) || hi - b <= 0.0011, "tilt {tilt} az {az} row ({y}, {z}): [{lo}, {hi}] vs points [{a}, {b}]");
                            }
                        }
                    }
                }
            }
        }
        assert!(bounded > 30, "only {bounded} rows bounded");
    }

    #[test]
    fn beyond_sixty_degrees_of_tilt_the_whole_overlap_counts() {
        let n = DVec3::new(70f64.to_radians().sin(), 0.0, 70f64.to_radians().cos());
        let c = ContactSurface::new(DVec3::ZERO, n, 0.45);
        assert!((c.depth_above(0.1, 0.0, -0.1, 0.05) - 0.15).abs() < 1e-12);
    }
}
