//! The removable flat anchor.
//!
//! A non-planar warp lifts the model's flat bottom into a curved surface (a cone for the conic
//! warp) that touches the bed at a point or a line. Planar slicers then find (almost) nothing
//! to print in the first layer, and PrusaSlicer refuses outright ("There is an object with no
//! extrusions in the first layer"). warpslice puts a thin slab under the warped part: the
//! convex hull of the part's XY projection, one layer (`job.layer_height`) thick, touching the
//! part's lowest points. The slicer's first layer then holds only the anchor (and skirt/brim,
//! which go around the hull and so around the real part); `unwarp` drops the anchor's
//! extrusions, so the part's own first layers print straight onto the bed where the warp puts
//! them. The slab lies inside the part's XY bounding box, so the slicer's centring and the
//! registration are unaffected.
//!
//! The anchor is added when the slicer's first layer would hold too little of the part: when
//! the XY area of the part's triangles lying within half a layer of its lowest point is below
//! [`MIN_FIRST_LAYER_AREA`] (a cone's tip, a crease line, the corners of an inward cone). A
//! flat warped bottom (the `--base` blend, or no warp at the bottom) needs none.

use glam::{DVec2, DVec3};

use crate::mesh::Mesh;

/// Smallest XY area (mm²) of the part's first-layer region below which the anchor is added.
pub const MIN_FIRST_LAYER_AREA: f64 = 25.0;

/// Whether the warped part (T-space) needs an anchor when sliced with `layer_height`.
pub fn needs_anchor(warped: &Mesh, layer_height: f64) -> bool {
    let area = first_layer_area(warped, layer_height);
    area < MIN_FIRST_LAYER_AREA || area.is_nan()
}

/// The XY area (mm²) of the warped part's triangles lying within half a layer of its lowest
/// point: what the slicer's first layer holds of it.
pub fn first_layer_area(warped: &Mesh, layer_height: f64) -> f64 {
    let zmin = warped
        .vertices
        .iter()
        .map(|v| v.z)
        .fold(f64::INFINITY, f64::min);
    let limit = zmin + 0.5 * layer_height;
    warped
        .triangles
        .iter()
        .map(|t| t.map(|i| warped.vertices[i as usize]))
        .filter(|[a, b, c]| a.z <= limit && b.z <= limit && c.z <= limit)
        .map(|[a, b, c]| 0.5 * (b - a).truncate().perp_dot((c - a).truncate()).abs())
        .sum()
}

/// Convex hull (counter-clockwise, no repeated first point) of 2-D points (Andrew's monotone
/// chain). Collinear points are dropped.
pub fn convex_hull(points: &mut [DVec2]) -> Vec<DVec2> {
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    let cross = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<DVec2> = Vec::with_capacity(64);
    for &p in points.iter() {
        while hull.len() >= 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
            hull.pop();
        }
        hull.push(p);
    }
    let lower = hull.len() + 1;
    for &p in points.iter().rev().skip(1) {
        while hull.len() >= lower && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
            hull.pop();
        }
        hull.push(p);
    }
    hull.pop();
    hull
}

/// Append the anchor slab to `mesh`: the prism over the convex hull of `mesh`'s XY projection
/// between z = `top − thickness` and z = `top`. Returns false (and adds nothing) if the hull
/// is degenerate (fewer than 3 points).
pub fn add_slab(mesh: &mut Mesh, top: f64, thickness: f64) -> bool {
    let mut pts: Vec<DVec2> = mesh.vertices.iter().map(|v| v.truncate()).collect();
    let hull = convex_hull(&mut pts);
    if hull.len() < 3 {
        return false;
    }
    let n = hull.len() as u32;
    let base = mesh.vertices.len() as u32;
    let bottom = top - thickness;
    for p in &hull {
        mesh.vertices.push(DVec3::new(p.x, p.y, bottom));
    }
    for p in &hull {
        mesh.vertices.push(DVec3::new(p.x, p.y, top));
    }
    // Bottom (seen from below: clockwise in XY), top (counter-clockwise), sides.
    for i in 1..n - 1 {
        mesh.triangles.push([base, base + i + 1, base + i]);
        mesh.triangles
            .push([base + n, base + n + i, base + n + i + 1]);
    }
    for i in 0..n {
        let j = (i + 1) % n;
        mesh.triangles.push([base + i, base + j, base + n + j]);
        mesh.triangles.push([base + i, base + n + j, base + n + i]);
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hull_of_square_with_inner_points() {
        let mut pts = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 1.0),
            DVec2::new(0.5, 0.5),
            DVec2::new(0.5, 0.0),
        ];
        let h = convex_hull(&mut pts);
        assert_eq!(h.len(), 4);
        // counter-clockwise: positive signed area
        let area: f64 = (0..h.len())
            .map(|i| h[i].perp_dot(h[(i + 1) % h.len()]))
            .sum::<f64>()
            / 2.0;
        assert!((area - 1.0).abs() < 1e-12);
    }

    #[test]
    fn slab_is_closed_prism() {
        let mut m = Mesh {
            vertices: vec![
                DVec3::new(0.0, 0.0, 1.0),
                DVec3::new(2.0, 0.0, 1.0),
                DVec3::new(0.0, 2.0, 1.0),
            ],
            triangles: vec![],
        };
        assert!(add_slab(&mut m, 1.0, 0.2));
        assert_eq!(m.triangles.len(), 2 + 2 * 3); // top + bottom fans of a triangle, 3 side quads
                                                  // volume by the divergence theorem = area · thickness = 2 · 0.2
        let vol = m.signed_volume();
        assert!((vol - 0.4).abs() < 1e-12, "{vol}");
    }
}
