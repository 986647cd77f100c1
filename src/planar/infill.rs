//! Rectilinear infill: parallel lines at an angle and a spacing, clipped to a region.
//!
//! The region is turned by −θ (x' = x·cos θ + y·sin θ, y' = −x·sin θ + y·cos θ), cut by the
//! scanlines y' = (k + ½)·p for every integer k (a grid fixed in the bed's frame, so the lines
//! of layers with the same angle lie on top of each other), and every scanline's crossings with
//! the region's contours, sorted by x', are paired inside–outside. An edge counts for the
//! scanlines with `min(y'₀, y'₁) ≤ y' < max(y'₀, y'₁)` (half-open: a scanline through a vertex
//! crosses exactly one of its two edges, or both of a spike, so the pairing stays right).
//! The lines are turned back by +θ.
//!
//! Spacing: `p = s / (density / 100)` with s the line spacing ([`super::Settings::spacing`]);
//! 100 % gives p = s, lines touching each other: solid.

use super::region::Region;

/// A line shorter than this is not printed, mm: the region's slivers between two scanline
/// crossings a few µm apart (a scanline grazing a vertex) would be a single-point extrusion.
pub const MIN_INFILL_LINE: f64 = 0.01;

/// Lines `[from, to]` filling `region` at `angle_deg` with centre-to-centre distance `pitch`.
pub fn rectilinear(region: &Region, angle_deg: f64, pitch: f64) -> Vec<[[f64; 2]; 2]> {
    if region.is_empty() || pitch.is_nan() || pitch <= 0.0 {
        return Vec::new();
    }
    let (sin, cos) = angle_deg.to_radians().sin_cos();
    let turn = |p: [f64; 2]| [p[0] * cos + p[1] * sin, -p[0] * sin + p[1] * cos];
    let back = |p: [f64; 2]| [p[0] * cos - p[1] * sin, p[0] * sin + p[1] * cos];
    let contours: Vec<Vec<[f64; 2]>> = region
        .iter()
        .flatten()
        .map(|c| c.iter().map(|&p| turn(p)).collect())
        .collect();
    let (lo, hi) = contours
        .iter()
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p[1]), hi.max(p[1]))
        });
    if !(lo.is_finite() && hi.is_finite()) {
        return Vec::new();
    }
    // scanline k at y' = (k + ½)·pitch
    let k_of = |y: f64| ((y / pitch) - 0.5).ceil() as i64;
    let (k0, k1) = (k_of(lo), k_of(hi));
    let rows = (k1 - k0).max(0) as usize + 1;
    let mut crossings: Vec<Vec<f64>> = vec![Vec::new(); rows];
    for c in &contours {
        for i in 0..c.len() {
            let (p, q) = (c[i], c[(i + 1) % c.len()]);
            if p[1] == q[1] {
                continue;
            }
            let (a, b) = if p[1] < q[1] { (p, q) } else { (q, p) };
            let mut k = k_of(a[1]);
            loop {
                let y = (k as f64 + 0.5) * pitch;
                if y >= b[1] {
                    break;
                }
                if y >= a[1] {
                    let t = (y - a[1]) / (b[1] - a[1]);
                    if let Some(row) = crossings.get_mut((k - k0) as usize) {
                        row.push(a[0] + t * (b[0] - a[0]));
                    }
                }
                k += 1;
            }
        }
    }
    let mut lines = Vec::new();
    for (r, xs) in crossings.iter_mut().enumerate() {
        xs.sort_by(f64::total_cmp);
        let y = ((k0 + r as i64) as f64 + 0.5) * pitch;
        for pair in xs.chunks_exact(2) {
            if pair[1] - pair[0] >= MIN_INFILL_LINE {
                lines.push([back([pair[0], y]), back([pair[1], y])]);
            }
        }
    }
    lines
}
