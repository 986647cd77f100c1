//! A head part placed in the output frame: a frustum of revolution about an axis, or an
//! oriented box. Two questions are asked of it: where a vertical line enters and leaves it
//! ([`Posed::column`]), and a lower bound of its distance from a point ([`Posed::distance`]).
//!
//! ## Frustum (cone, cylinder)
//! Origin `o` (the tip), unit axis `a` (the tool axis), axial coordinate `s = a·(q − o)` in
//! `[s0, s1]`, radius `r(s) = r0 + k (s − s0)` with `k = tan(half-angle)` (0: a cylinder). On the
//! vertical line `q(t) = (x, y, t)` with `w = (x − o_x, y − o_y, −o_z)`:
//! `f(t) = |w + t e_z|² − s(t)² − r(s(t))²`, a quadratic in t; the line is inside where
//! `f ≤ 0` and `s0 ≤ s(t) ≤ s1`, one interval since the frustum is convex.
//!
//! ## Box
//! Origin `o`, rotation `R` (columns: the box frame's axes in the output frame), corners `min`,
//! `max` of the box frame: the slab method on `Rᵀ(q(t) − o)`.

use glam::{DMat3, DVec3};

/// A placed solid (output frame, mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Posed {
    /// A frustum of revolution (see the module documentation).
    Frustum {
        /// The tip (origin of the axial coordinate).
        o: DVec3,
        /// Unit axis.
        a: DVec3,
        /// Axial range.
        s0: f64,
        /// Axial range.
        s1: f64,
        /// Radius at `s0`.
        r0: f64,
        /// dr/ds.
        k: f64,
    },
    /// An oriented box.
    Box {
        /// Origin of the box frame.
        o: DVec3,
        /// Box frame axes (columns) in the output frame.
        r: DMat3,
        /// Lowest corner in the box frame.
        min: DVec3,
        /// Highest corner in the box frame.
        max: DVec3,
    },
}

/// The distance seen from above from point `p` to the square of centre `c` and half side
/// `half` (0 inside), mm.
pub fn square_distance(p: glam::DVec2, c: glam::DVec2, half: f64) -> f64 {
    ((p - c).abs() - glam::DVec2::splat(half))
        .max(glam::DVec2::ZERO)
        .length()
}

/// Below this |coefficient| a quadratic is taken as linear and a direction component as zero.
const DEGENERATE: f64 = 1e-12;

/// Added to each side of a box's clipped rectangle ([`Posed::below_in_rect`]), mm: the
/// clip's intersection points carry the rounding of a division; far below a cell (0.2 mm).
const BELOW_RECT_SLACK_MM: f64 = 1e-6;

/// Most vertices of [`Posed::below_in_rect`]'s clipped polygon: the rectangle's 4, at most
/// doubled by each of the three slabs' cuts (a cut keeps some vertices and adds one per sign
/// change along the boundary, no more than the vertices it had).
const CLIP_VERTICES: usize = 32;

impl Posed {
    /// The axis-aligned bounding box (lowest, highest corner).
    pub fn aabb(&self) -> (DVec3, DVec3) {
        match *self {
            Posed::Frustum {
                o,
                a,
                s0,
                s1,
                r0,
                k,
            } => {
                // a disc of radius r about centre c with normal a spans ± r·sqrt(1 − a_i²)
                let disc = |s: f64, r: f64| {
                    let c = o + a * s;
                    let e = DVec3::new(
                        (1.0 - a.x * a.x).max(0.0).sqrt(),
                        (1.0 - a.y * a.y).max(0.0).sqrt(),
                        (1.0 - a.z * a.z).max(0.0).sqrt(),
                    ) * r;
                    (c - e, c + e)
                };
                let (l0, h0) = disc(s0, r0);
                let (l1, h1) = disc(s1, r0 + k * (s1 - s0));
                (l0.min(l1), h0.max(h1))
            }
            Posed::Box { o, r, min, max } => {
                let c = o + r * ((min + max) * 0.5);
                let h = (max - min) * 0.5;
                let e = r.x_axis.abs() * h.x + r.y_axis.abs() * h.y + r.z_axis.abs() * h.z;
                (c - e, c + e)
            }
        }
    }

    /// A lower bound of where the vertical line through (x, y) enters the solid (+∞: it
    /// cannot; −∞: no bound known), cheap enough to try before [`Posed::column`].
    ///
    /// Frustum (s0 ≥ 0): a point `q = o + s a + v` of it (`v ⟂ a`, `|v| ≤ r(s)`, θ the axis'
    /// tilt from vertical) lies within `s sin θ + r(s)` of the tip horizontally, so the line at
    /// horizontal distance D meets only `s ≥ s_min = (D − r0 + k s0)/(sin θ + k)`; and
    /// `q_z ≥ o_z + s a_z − r(s) sin θ`, linear in s, so the bound is the smaller of its values
    /// at `max(s0, s_min)` and `s1`.
    ///
    /// Box: −∞ (its exact entry, [`Posed::column`]'s slab method, costs about as much as a
    /// bound would; [`Posed::floor_over_square`] bounds a whole block).
    pub fn floor_at(&self, x: f64, y: f64) -> f64 {
        match *self {
            Posed::Frustum { o, .. } => {
                let (dx, dy) = (x - o.x, y - o.y);
                self.floor_at_distance((dx * dx + dy * dy).sqrt())
            }
            Posed::Box { .. } => f64::NEG_INFINITY,
        }
    }

    /// A lower bound of [`Posed::floor_at`] over the square of centre `c` and half side `half`
    /// seen from above: the frustum's bound at the square's least distance from the tip (it
    /// grows with the distance); for a box, a vertical line enters it where it enters the last
    /// of the three slabs (the slab method of [`Posed::column`]), `z_in = max_k t_k(x, y)` over
    /// the slabs not parallel to it; each `t_k` is linear in (x, y), least over the square at a
    /// corner: `t_k(c) − (|∂t_k/∂x| + |∂t_k/∂y|)·half`, and the largest of those bounds `z_in`
    /// from below.
    pub fn floor_over_square(&self, c: glam::DVec2, half: f64) -> f64 {
        match *self {
            Posed::Frustum { o, .. } => {
                self.floor_at_distance(square_distance(o.truncate(), c, half))
            }
            Posed::Box { o, r, min, max } => {
                let mut floor = f64::NEG_INFINITY;
                let w = DVec3::new(c.x - o.x, c.y - o.y, -o.z);
                for (k, axis) in [r.x_axis, r.y_axis, r.z_axis].into_iter().enumerate() {
                    // u_k(t) = axis·(w + t e_z) = axis·w + axis.z t: enters [min, max] at
                    let vz = axis.z;
                    if vz.abs() < DEGENERATE {
                        continue;
                    }
                    let entry = if vz > 0.0 { min[k] } else { max[k] };
                    let t = (entry - axis.dot(w)) / vz;
                    let slope = (axis.x.abs() + axis.y.abs()) / vz.abs();
                    floor = floor.max(t - slope * half);
                }
                floor
            }
        }
    }

    /// [`Posed::floor_at`] of a vertical line at horizontal distance `d` from the tip `o` (the
    /// frustum's bound depends on that distance only, and does not decrease with it).
    pub fn floor_at_distance(&self, d: f64) -> f64 {
        match *self {
            Posed::Frustum {
                o,
                a,
                s0,
                s1,
                r0,
                k,
            } => {
                if s0 < 0.0 {
                    return f64::NEG_INFINITY;
                }
                let sin_t = (1.0 - a.z * a.z).max(0.0).sqrt();
                let denom = sin_t + k;
                let s_min = if denom > DEGENERATE {
                    ((d - r0 + k * s0) / denom).max(s0)
                } else if d <= r0 {
                    s0
                } else {
                    return f64::INFINITY;
                };
                if s_min > s1 {
                    return f64::INFINITY;
                }
                let f = |s: f64| o.z + s * a.z - (r0 + k * (s - s0)) * sin_t;
                f(s_min).min(f(s1))
            }
            Posed::Box { .. } => f64::NEG_INFINITY,
        }
    }

    /// A horizontal radius about the tip `o` outside which the solid lies above height `m`
    /// (`None`: no such bound known): where [`Posed::floor_at`] exceeds `m`. With
    /// `f(s) = o_z + s a_z − r(s) sin θ` increasing (`a_z ≥ k sin θ`), `f(s*) = m` gives
    /// `s* = (m − o_z + (r0 − k s0) sin θ)/(a_z − k sin θ)` and the radius
    /// `D* = s* (sin θ + k) + r0 − k s0`.
    pub fn radius_below(&self, m: f64) -> Option<f64> {
        match *self {
            Posed::Frustum {
                o, a, s0, r0, k, ..
            } => {
                let sin_t = (1.0 - a.z * a.z).max(0.0).sqrt();
                let slope = a.z - k * sin_t;
                if s0 < 0.0 || slope <= DEGENERATE {
                    return None;
                }
                let s = ((m - o.z + (r0 - k * s0) * sin_t) / slope).max(s0);
                Some(s * (sin_t + k) + r0 - k * s0)
            }
            Posed::Box { .. } => None,
        }
    }

    /// [`Posed::radius_below`] with its centre: the disc (seen from above, about the tip `o`)
    /// outside which the solid lies above height `m`.
    pub fn disc_below(&self, m: f64) -> Option<(glam::DVec2, f64)> {
        match *self {
            Posed::Frustum { o, .. } => self.radius_below(m).map(|r| (o.truncate(), r)),
            Posed::Box { .. } => None,
        }
    }

    /// Whether [`Posed::floor_over_square`] is the solid's lowest height everywhere: a box
    /// whose every face is horizontal or vertical (only its bottom bounds a vertical line).
    pub fn floor_is_flat(&self) -> bool {
        match *self {
            Posed::Frustum { .. } => false,
            Posed::Box { r, .. } => [r.x_axis, r.y_axis, r.z_axis]
                .iter()
                .all(|a| a.z.abs() < DEGENERATE || a.x.abs() + a.y.abs() < DEGENERATE),
        }
    }

    /// The bounding rectangle of the part of `rect` (x0, y0, x1, y1) where the solid may come
    /// below height `m` (`None`: nowhere): for a frustum `rect` cut to the square about
    /// [`Posed::disc_below`]; for a box `rect` clipped (a convex polygon) by the half-planes
    /// `t_k(x, y) ≤ m` of [`Posed::floor_over_square`]'s slab entries, whose largest is the
    /// line's entry height.
    pub fn below_in_rect(
        &self,
        (x0, y0, x1, y1): (f64, f64, f64, f64),
        m: f64,
    ) -> Option<(f64, f64, f64, f64)> {
        let cut = match *self {
            Posed::Frustum { .. } => match self.disc_below(m) {
                Some((o, r)) => (
                    x0.max(o.x - r),
                    y0.max(o.y - r),
                    x1.min(o.x + r),
                    y1.min(o.y + r),
                ),
                None => (x0, y0, x1, y1),
            },
            Posed::Box { o, r, min, max } => {
                // the polygon on the stack, in two buffers used in turn: each cut keeps some of
                // the `len` vertices and adds one per sign change along the boundary, at most
                // 2·len in all (a convex polygon gains one, but rounding near the cut line may
                // change signs more often), so 4·2³ after the three cuts
                let mut buf = [[glam::DVec2::ZERO; CLIP_VERTICES]; 2];
                buf[0][..4].copy_from_slice(&[
                    glam::DVec2::new(x0, y0),
                    glam::DVec2::new(x1, y0),
                    glam::DVec2::new(x1, y1),
                    glam::DVec2::new(x0, y1),
                ]);
                let (mut cur, mut len) = (0, 4);
                for (k, axis) in [r.x_axis, r.y_axis, r.z_axis].into_iter().enumerate() {
                    let vz = axis.z;
                    if vz.abs() < DEGENERATE {
                        continue;
                    }
                    let entry = if vz > 0.0 { min[k] } else { max[k] };
                    // f(q) = t_k(q) − m ≤ 0 kept (t_k linear in q)
                    let f = |q: glam::DVec2| {
                        (entry - axis.dot(DVec3::new(q.x - o.x, q.y - o.y, -o.z))) / vz - m
                    };
                    let [b0, b1] = &mut buf;
                    let (poly, next) = if cur == 0 { (b0, b1) } else { (b1, b0) };
                    let mut n = 0;
                    for i in 0..len {
                        let (p, q) = (poly[i], poly[(i + 1) % len]);
                        let (fp, fq) = (f(p), f(q));
                        if fp <= 0.0 {
                            next[n] = p;
                            n += 1;
                        }
                        if (fp <= 0.0) != (fq <= 0.0) {
                            next[n] = p + (q - p) * (fp / (fp - fq));
                            n += 1;
                        }
                    }
                    (cur, len) = (1 - cur, n);
                    if len == 0 {
                        return None;
                    }
                }
                let poly = &buf[cur];
                let (mut lo, mut hi) = (poly[0], poly[0]);
                for p in &poly[..len] {
                    lo = lo.min(*p);
                    hi = hi.max(*p);
                }
                // the clip's intersections are computed in f64: keep their rounding in
                let e = BELOW_RECT_SLACK_MM;
                (lo.x - e, lo.y - e, hi.x + e, hi.y + e)
            }
        };
        (cut.0 <= cut.2 && cut.1 <= cut.3).then_some(cut)
    }

    /// The solid's lowest point (one of them): for a frustum the lower of its end discs' lowest
    /// points `c − r·h`, `h` the unit of `e_z − a_z a` (steepest ascent in the disc's plane);
    /// for a box its lowest corner.
    pub fn lowest(&self) -> DVec3 {
        match *self {
            Posed::Frustum {
                o,
                a,
                s0,
                s1,
                r0,
                k,
            } => {
                let up = DVec3::Z - a * a.z;
                let h = if up.length() > DEGENERATE {
                    up.normalize()
                } else {
                    DVec3::ZERO
                };
                let low0 = o + a * s0 - h * r0;
                let low1 = o + a * s1 - h * (r0 + k * (s1 - s0));
                if low0.z <= low1.z {
                    low0
                } else {
                    low1
                }
            }
            Posed::Box { o, r, min, max } => {
                let mut best = DVec3::splat(f64::INFINITY);
                for c in 0..8 {
                    let l = DVec3::new(
                        if c & 1 == 0 { min.x } else { max.x },
                        if c & 2 == 0 { min.y } else { max.y },
                        if c & 4 == 0 { min.z } else { max.z },
                    );
                    let w = o + r * l;
                    if w.z < best.z {
                        best = w;
                    }
                }
                best
            }
        }
    }

    /// Where the vertical line through (x, y) is inside: `(z_in, z_out)`, or `None`.
    pub fn column(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        match *self {
            Posed::Frustum {
                o,
                a,
                s0,
                s1,
                r0,
                k,
            } => {
                let w = DVec3::new(x - o.x, y - o.y, -o.z);
                let sw = a.dot(w);
                let az = a.z;
                // t range of the slab s0 ≤ sw + az t ≤ s1
                let (ta, tb) = if az.abs() < DEGENERATE {
                    if sw < s0 || sw > s1 {
                        return None;
                    }
                    // bounded by the solid's enclosing sphere about the tip
                    let rmax = r0.max(r0 + k * (s1 - s0));
                    let rb2 = s0.abs().max(s1.abs()).powi(2) + rmax * rmax;
                    let d2 = w.x * w.x + w.y * w.y;
                    if d2 > rb2 {
                        return None;
                    }
                    let h = (rb2 - d2).sqrt();
                    (-w.z - h, -w.z + h)
                } else {
                    let t0 = (s0 - sw) / az;
                    let t1 = (s1 - sw) / az;
                    (t0.min(t1), t0.max(t1))
                };
                let c0 = r0 + k * (sw - s0);
                let c1 = k * az;
                let a2 = 1.0 - az * az - c1 * c1;
                let a1 = 2.0 * (w.z - sw * az - c0 * c1);
                let a0 = w.length_squared() - sw * sw - c0 * c0;
                let f = |t: f64| (a2 * t + a1) * t + a0;
                let mut pts = [ta, tb, f64::NAN, f64::NAN];
                if a2.abs() < DEGENERATE {
                    if a1.abs() > DEGENERATE {
                        pts[2] = -a0 / a1;
                    }
                } else {
                    let disc = a1 * a1 - 4.0 * a2 * a0;
                    if disc >= 0.0 {
                        let sq = disc.sqrt();
                        // the numerically stable pair of roots
                        let q = -0.5 * (a1 + a1.signum() * sq);
                        pts[2] = q / a2;
                        if q != 0.0 {
                            pts[3] = a0 / q;
                        }
                    }
                }
                // the candidate ends in order (no allocation: at most four)
                let mut ts = [0.0; 4];
                let mut m = 0;
                for t in pts {
                    if t.is_finite() && t >= ta && t <= tb {
                        let mut k = m;
                        while k > 0 && ts[k - 1] > t {
                            ts[k] = ts[k - 1];
                            k -= 1;
                        }
                        ts[k] = t;
                        m += 1;
                    }
                }
                let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
                for p in ts[..m].windows(2) {
                    if f(0.5 * (p[0] + p[1])) <= 0.0 {
                        lo = lo.min(p[0]);
                        hi = hi.max(p[1]);
                    }
                }
                (lo <= hi).then_some((lo, hi))
            }
            Posed::Box { o, r, min, max } => {
                let u = r.transpose() * DVec3::new(x - o.x, y - o.y, -o.z);
                let v = r.transpose() * DVec3::Z;
                let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
                for i in 0..3 {
                    let (ui, vi, mn, mx) = (u[i], v[i], min[i], max[i]);
                    if vi.abs() < DEGENERATE {
                        if ui < mn || ui > mx {
                            return None;
                        }
                    } else {
                        let t0 = (mn - ui) / vi;
                        let t1 = (mx - ui) / vi;
                        lo = lo.max(t0.min(t1));
                        hi = hi.min(t0.max(t1));
                    }
                }
                (lo <= hi).then_some((lo, hi))
            }
        }
    }

    /// A solid that contains every point within `delta` (mm, ≥ 0) of this one (the solid
    /// grown by a ball of radius `delta`, enclosed):
    /// - frustum: the axial range grows by `delta` at both ends and the radius by
    ///   `delta·√(1 + k²)` at every s (the side line `ρ = r0 + k (s − s0)` moved outward by
    ///   `delta` along its normal moves by `delta / cos α = delta·√(1 + k²)` in ρ, α the
    ///   half-angle); written with its origin at the new lower end (`s0 = 0`), so that
    ///   [`Posed::floor_at`] and [`Posed::radius_below`] apply to it;
    /// - box: every face moved outward by `delta` (the box grown by a cube ⊇ the ball).
    ///
    /// A part at every pose of a stretch of a move whose points move at most `delta` from a
    /// reference pose lies inside the reference pose's solid grown by `delta`
    /// (`crate::collision::sweep`, the cells a stretch of poses may reach).
    pub fn dilated(&self, delta: f64) -> Posed {
        match *self {
            Posed::Frustum {
                o,
                a,
                s0,
                s1,
                r0,
                k,
            } => Posed::Frustum {
                o: o + a * (s0 - delta),
                a,
                s0: 0.0,
                s1: s1 - s0 + 2.0 * delta,
                r0: r0 - k * delta + delta * (1.0 + k * k).sqrt(),
                k,
            },
            Posed::Box { o, r, min, max } => Posed::Box {
                o,
                r,
                min: min - DVec3::splat(delta),
                max: max + DVec3::splat(delta),
            },
        }
    }

    /// The distance from `q` to the solid (0 inside): exact for both shapes, so a lower bound.
    /// The frustum's is the least distance in its (ρ, s) half-plane to the three sides of its
    /// profile, each `√(u² + v²)` (not `hypot`: the operands are a few hundred mm at most, far
    /// from overflow, and the one cull that reads it, [`super::cull::Reach::skips_block`],
    /// keeps a 10⁻⁹ mm slack over the rounding of either).
    pub fn distance(&self, q: DVec3) -> f64 {
        match *self {
            Posed::Frustum {
                o,
                a,
                s0,
                s1,
                r0,
                k,
            } => {
                let d = q - o;
                let s = a.dot(d);
                let rho = (d.length_squared() - s * s).max(0.0).sqrt();
                let r1 = r0 + k * (s1 - s0);
                if s >= s0 && s <= s1 && rho <= r0 + k * (s - s0) {
                    return 0.0;
                }
                // the profile: a trapezoid (0, s0) (r0, s0) (r1, s1) (0, s1) in (ρ, s)
                let seg = |p0: (f64, f64), p1: (f64, f64)| {
                    let (ex, ey) = (p1.0 - p0.0, p1.1 - p0.1);
                    let l2 = ex * ex + ey * ey;
                    let t = if l2 > 0.0 {
                        (((rho - p0.0) * ex + (s - p0.1) * ey) / l2).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    let (u, v) = (rho - p0.0 - t * ex, s - p0.1 - t * ey);
                    (u * u + v * v).sqrt()
                };
                seg((0.0, s0), (r0, s0))
                    .min(seg((r0, s0), (r1, s1)))
                    .min(seg((r1, s1), (0.0, s1)))
            }
            Posed::Box { o, r, min, max } => {
                let u = r.transpose() * (q - o);
                let c = (min + max) * 0.5;
                let h = (max - min) * 0.5;
                ((u - c).abs() - h).max(DVec3::ZERO).length()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Lcg;
    use glam::{DMat3, DQuat};

    /// [`Posed::distance`] of a frustum is a lower bound of the distance to each of its points
    /// (the block cull skips what lies farther), and a tight one: the oracle samples points of
    /// the solid here from its own parameters (axial s, radius up to `r0 + k (s − s0)`, angle
    /// about the axis), not from the profile's segments. Random frusta (cones and cylinders,
    /// tilted up to 60°), query points around them; a point the oracle finds inside gets 0.
    #[test]
    fn a_frustums_distance_is_at_most_that_of_each_of_its_points_and_close_to_the_nearest() {
        let mut rng = Lcg(0x0d15_7a9c);
        let (mut outside, mut tight) = (0, 0);
        for case in 0..60 {
            let (tilt, az) = (
                rng.range(0.0, 60.0).to_radians(),
                rng.range(0.0, 360.0).to_radians(),
            );
            let a = DVec3::new(tilt.sin() * az.cos(), tilt.sin() * az.sin(), tilt.cos());
            let o = rng.within(DVec3::splat(-20.0), DVec3::splat(20.0));
            let (s0, len) = (rng.range(0.0, 5.0), rng.range(0.5, 10.0));
            let (r0, k) = (
                rng.range(0.1, 6.0),
                if case % 3 == 0 {
                    0.0
                } else {
                    rng.range(0.0, 1.2)
                },
            );
            let f = Posed::Frustum {
                o,
                a,
                s0,
                s1: s0 + len,
                r0,
                k,
            };
            // an orthonormal frame about the axis
            let e1 = a.any_orthonormal_vector();
            let e2 = a.cross(e1);
            let pts: Vec<DVec3> = (0..4000)
                .map(|_| {
                    let s = rng.range(s0, s0 + len);
                    let rho = (r0 + k * (s - s0)) * rng.unit().sqrt();
                    let phi = rng.range(0.0, std::f64::consts::TAU);
                    o + a * s + (e1 * phi.cos() + e2 * phi.sin()) * rho
                })
                .collect();
            for _ in 0..40 {
                let q = o + rng.within(DVec3::splat(-25.0), DVec3::splat(25.0));
                let d = f.distance(q);
                let nearest = pts
                    .iter()
                    .map(|p| p.distance(q))
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    d <= nearest + 1e-12,
                    "case {case}: distance {d} from {q:?} beyond a point of the solid at {nearest}"
                );
                if nearest > 0.5 {
                    outside += 1;
                    // the samples are ~0.3 mm apart on a solid of this size: the nearest lies
                    // within that of the true distance
                    tight += usize::from(nearest - d < 1.0);
                }
            }
        }
        assert!(
            outside > 1000 && tight * 10 >= outside * 9,
            "{tight} of {outside} tight"
        );
    }

    /// [`Posed::below_in_rect`] of a turned box holds every vertical line of the rectangle that
    /// enters the box below the height `m`: the oracle is [`Posed::column`] (the slab method,
    /// not the clip) with a point between the entry and `min(exit, m)` confirmed inside the box
    /// by its own coordinates. Random boxes turned about random axes by up to 60°, rectangles
    /// about their footprint, heights across their span; a 61 × 61 grid of each rectangle.
    /// Many cases clip the rectangle, some to nothing.
    #[test]
    fn a_boxs_clipped_rectangle_holds_every_line_entering_it_below_the_height() {
        let mut rng = Lcg(17);
        let (mut clipped, mut none, mut below) = (0, 0, 0);
        for case in 0..400 {
            let axis = rng
                .within(DVec3::splat(-1.0), DVec3::splat(1.0))
                .normalize_or(DVec3::X);
            let r = DMat3::from_quat(DQuat::from_axis_angle(axis, rng.range(0.0, 1.05)));
            let min = rng.within(DVec3::new(-12.0, -12.0, -2.0), DVec3::new(-1.0, -1.0, 1.0));
            let max = min + rng.within(DVec3::splat(1.0), DVec3::splat(20.0));
            let o = rng.within(DVec3::new(-5.0, -5.0, 0.0), DVec3::new(5.0, 5.0, 10.0));
            let solid = Posed::Box { o, r, min, max };
            let (lo, hi) = solid.aabb();
            let rect = (
                lo.x + rng.range(-2.0, 4.0),
                lo.y + rng.range(-2.0, 4.0),
                hi.x - rng.range(-2.0, 4.0),
                hi.y - rng.range(-2.0, 4.0),
            );
            let m = rng.range(lo.z - 1.0, hi.z);
            let got = solid.below_in_rect(rect, m);
            match got {
                None => none += 1,
                Some((x0, y0, x1, y1)) => {
                    let cut = (x0 - rect.0)
                        .max(y0 - rect.1)
                        .max(rect.2 - x1)
                        .max(rect.3 - y1);
                    clipped += usize::from(cut > 0.5);
                }
            }
            for j in 0..=60 {
                for i in 0..=60 {
                    let x = rect.0 + (rect.2 - rect.0) * i as f64 / 60.0;
                    let y = rect.1 + (rect.3 - rect.1) * j as f64 / 60.0;
                    let Some((zi, zo)) = solid.column(x, y) else {
                        continue;
                    };
                    if zi >= m - 1e-6 {
                        continue;
                    }
                    // the line really is inside the box there
                    let z = 0.5 * (zi + zo.min(m));
                    let u = r.transpose() * (DVec3::new(x, y, z) - o);
                    assert!(
                        u.cmpge(min - 1e-9).all() && u.cmple(max + 1e-9).all(),
                        "case {case}: the oracle's point ({x}, {y}, {z}) is not in the box"
                    );
                    below += 1;
                    assert!(
                        got.is_some_and(|(x0, y0, x1, y1)| x0 <= x
                            && x <= x1
                            && y0 <= y
                            && y <= y1),
                        "case {case}: the line ({x}, {y}) enters the box at {zi} below {m}, \
                         outside the clipped rectangle {got:?} of {rect:?}"
                    );
                }
            }
        }
        assert!(
            clipped > 100 && none > 10 && below > 100_000,
            "{clipped} rectangles clipped, {none} to nothing, {below} lines below the height"
        );
    }
}
