//! Planar regions and the polygon operations the slicer needs, over `i_overlay`
//! (why that crate: [`super`]).
//!
//! A [`Region`] is a list of shapes; a shape is its outer contour (counter-clockwise) followed
//! by its holes (clockwise); a contour is a closed list of points, first not repeated. Every
//! result comes from `i_overlay`, so it is a valid region (no self-crossings, holes inside
//! their outer contour) whatever the input loops were.

use i_overlay::core::fill_rule::FillRule;
use i_overlay::core::overlay_rule::OverlayRule;
use i_overlay::float::simplify::SimplifyShape;
use i_overlay::float::single::SingleFloatOverlay;
use i_overlay::mesh::float::outline::offset::OutlineOffset;
use i_overlay::mesh::float::style::{LineJoin, OutlineStyle};

/// A closed polygon, mm.
pub type Contour = Vec<[f64; 2]>;
/// An outer contour and its holes.
pub type Shape = Vec<Contour>;
/// Any number of disjoint shapes.
pub type Region = Vec<Shape>;

/// Smallest interior angle an offset keeps as a sharp (mitred) corner, radians; sharper corners
/// are cut (beveled) so a spike does not shoot out of a needle-like tip. 15° keeps every corner
/// of ordinary parts sharp (a cube's 90°, a hexagon's 120°).
pub const MITER_MIN_ANGLE: f64 = 15.0 * std::f64::consts::PI / 180.0;

/// The union of `loops` with the nonzero rule: overlapping or touching shells become one
/// region, a loop inside another with the opposite direction is a hole.
pub fn union_loops(loops: &[Contour]) -> Region {
    if loops.is_empty() {
        return Region::new();
    }
    loops.to_vec().simplify_shape(FillRule::NonZero)
}

/// The region grown by `delta` (> 0) or shrunk by `−delta` (< 0), mm, corners mitred.
pub fn offset(region: &Region, delta: f64) -> Region {
    if region.is_empty() {
        return Region::new();
    }
    let style = OutlineStyle::new(delta).line_join(LineJoin::Miter(MITER_MIN_ANGLE));
    region.outline(&style)
}

/// `a − b`.
pub fn difference(a: &Region, b: &Region) -> Region {
    boolean(a, b, OverlayRule::Difference)
}

/// `a ∩ b`.
pub fn intersection(a: &Region, b: &Region) -> Region {
    boolean(a, b, OverlayRule::Intersect)
}

/// `a ∪ b`.
pub fn union(a: &Region, b: &Region) -> Region {
    boolean(a, b, OverlayRule::Union)
}

fn boolean(a: &Region, b: &Region, rule: OverlayRule) -> Region {
    match (a.is_empty(), b.is_empty(), rule) {
        (true, _, OverlayRule::Difference | OverlayRule::Intersect) => Region::new(),
        (_, true, OverlayRule::Intersect) => Region::new(),
        (_, true, _) => a.clone(),
        (true, _, _) => b.clone(),
        _ => a.overlay(b, rule, FillRule::NonZero),
    }
}

/// Where the line `p + t·d` meets the segment `a`–`b`: `(t, u)` with the point `a + u·(b − a)`
/// (Cramer's rule on `p + t·d = a + u·(b − a)`); `None` when they are parallel.
pub fn line_crossing(p: [f64; 2], d: [f64; 2], a: [f64; 2], b: [f64; 2]) -> Option<(f64, f64)> {
    let e = [b[0] - a[0], b[1] - a[1]];
    let den = d[0] * e[1] - d[1] * e[0];
    if den == 0.0 {
        return None;
    }
    let w = [a[0] - p[0], a[1] - p[1]];
    Some((
        (w[0] * e[1] - w[1] * e[0]) / den,
        (w[0] * d[1] - w[1] * d[0]) / den,
    ))
}

/// Signed area of one contour, mm² (shoelace; > 0 counter-clockwise).
pub fn contour_area(c: &[[f64; 2]]) -> f64 {
    let n = c.len();
    (0..n)
        .map(|i| {
            let (p, q) = (c[i], c[(i + 1) % n]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum::<f64>()
        / 2.0
}

/// Area of a region, mm² (holes subtract: they run clockwise).
pub fn area(region: &Region) -> f64 {
    region.iter().flatten().map(|c| contour_area(c)).sum()
}

/// Largest distance a simplified contour may leave its section's points, mm: PrusaSlicer's
/// `gcode_resolution` default (0.0125 mm). The cuts of a subdivided mesh have a vertex every
/// triangle (≤ 1 mm apart, many collinear); a printer cannot show detail below this, and the
/// offsets, skins and G-code then work on a few points per feature instead of thousands.
pub const RESOLUTION: f64 = 0.0125;

/// `c` with the points Douglas–Peucker drops at tolerance `tol` removed (closed: split at the
/// first point and the point farthest from it, each half simplified as an open chain).
pub fn simplify_closed(c: &[[f64; 2]], tol: f64) -> Contour {
    let n = c.len();
    if n < 4 {
        return c.to_vec();
    }
    let d2 = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
    let far = (1..n)
        .max_by(|&i, &j| d2(c[0], c[i]).total_cmp(&d2(c[0], c[j])))
        .unwrap_or(n / 2);
    let mut keep = vec![false; n + 1];
    keep[0] = true;
    keep[far] = true;
    let ring: Vec<[f64; 2]> = c.iter().copied().chain(std::iter::once(c[0])).collect();
    let mut stack = vec![(0usize, far), (far, n)];
    while let Some((a, b)) = stack.pop() {
        if b <= a + 1 {
            continue;
        }
        let (p, q) = (ring[a], ring[b]);
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        let len = (dx * dx + dy * dy).sqrt();
        let dist = |r: [f64; 2]| {
            if len == 0.0 {
                d2(p, r).sqrt()
            } else {
                ((r[0] - p[0]) * dy - (r[1] - p[1]) * dx).abs() / len
            }
        };
        let (i, d) = (a + 1..b)
            .map(|i| (i, dist(ring[i])))
            .max_by(|x, y| x.1.total_cmp(&y.1))
            .unwrap_or((a, 0.0));
        if d > tol {
            keep[i] = true;
            stack.push((a, i));
            stack.push((i, b));
        }
    }
    (0..n).filter(|&i| keep[i]).map(|i| c[i]).collect()
}
