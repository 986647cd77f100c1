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
