//! The warped mesh's cross-section at a layer's mid-height, for the shape check by
//! cross-section ([`super::shape`]).
//!
//! A planar slicer prints layer k inside the warped mesh's cut by the plane z = z_k − h_k/2
//! (PrusaSlicer, Slic3r and CuraEngine slice at the middle of the layer). The cut is the set of
//! segments where the plane meets the triangles (a triangle whose z-span straddles the plane
//! gives one segment between its two crossing edges). A point q (XY, STL frame) is inside when
//! a ray from q toward +x crosses the segments an odd number of times **or** with a non-zero
//! winding number (each segment oriented with the triangle's outward normal on its right; so
//! overlapping shells, which slicers unite, count as inside). Its signed distance is the
//! distance to the nearest segment, negative inside, clamped to ±[`SEARCH_RADIUS`].
//!
//! Segments are kept in a uniform grid of [`CELL`] cells over the cut's box: the distance
//! looks at the cells within [`SEARCH_RADIUS`], the ray at the segments of q's row that reach
//! q's column or beyond (each row lists its segments once, with the last column each
//! occupies: the segments met in the row's cells from q's to the right, without visiting the
//! cells or de-duplicating a segment met in several).

use glam::{DVec2, DVec3};

use crate::emit::clearance::segment_distance;
use crate::mesh::Mesh;

/// Grid cell size, mm.
pub const CELL: f64 = 1.0;
/// Distances are searched (and clamped) to this, mm: more than any tolerance of the check and
/// half a layer.
pub const SEARCH_RADIUS: f64 = 1.0;

/// One cut: its segments, oriented, in a grid.
#[derive(Clone, Debug, Default)]
struct Cut {
    z: f64,
    segs: Vec<(DVec2, DVec2)>,
    origin: DVec2,
    nx: usize,
    ny: usize,
    cells: Vec<Vec<u32>>,
    /// Per grid row, its segments once each with the last grid column they occupy.
    rows: Vec<Vec<(DVec2, DVec2, usize)>>,
}

/// The warped mesh, cut at the current layer's mid-height on demand.
#[derive(Clone, Debug)]
pub struct Sections {
    /// Triangles sorted by their lowest z, with their (lowest, highest) z.
    tris: Vec<([DVec3; 3], f64, f64)>,
    /// The last cut made.
    cut: Option<Cut>,
}

impl Sections {
    /// The sections of `mesh` (STL frame).
    pub fn new(mesh: &Mesh) -> Sections {
        let mut tris: Vec<([DVec3; 3], f64, f64)> = mesh
            .triangles
            .iter()
            .map(|t| {
                let p = t.map(|i| mesh.vertices[i as usize]);
                let lo = p[0].z.min(p[1].z).min(p[2].z);
                let hi = p[0].z.max(p[1].z).max(p[2].z);
                (p, lo, hi)
            })
            .collect();
        tris.sort_by(|a, b| a.1.total_cmp(&b.1));
        Sections { tris, cut: None }
    }

    fn cut_at(&mut self, z: f64) -> &Cut {
        if self.cut.as_ref().is_none_or(|c| c.z != z) {
            let mut segs = Vec::new();
            let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
            for (p, zl, zh) in &self.tris {
                // a vertex exactly on the plane counts as above it (`a.z < z` is below): a
                // triangle crosses when it has a vertex below and one on or above. So a plane
                // through a ring of vertices (a subdivided wall's row at a layer's mid-height)
                // takes the segment from the triangles below the ring, whose top edge lies on
                // it; skipping triangles with their highest vertex on the plane lost the wall
                if *zl >= z {
                    break;
                }
                if *zh < z {
                    continue;
                }
                let mut ends = [DVec2::ZERO; 2];
                let mut k = 0;
                for (a, b) in [(p[0], p[1]), (p[1], p[2]), (p[2], p[0])] {
                    if (a.z < z) != (b.z < z) && k < 2 {
                        let s = (z - a.z) / (b.z - a.z);
                        let q = a + (b - a) * s;
                        ends[k] = DVec2::new(q.x, q.y);
                        k += 1;
                    }
                }
                if k != 2 {
                    continue;
                }
                // outward normal (XY) on the segment's right: (e1 − e0) rotated −90°
                let n = (p[1] - p[0]).cross(p[2] - p[0]);
                let d = ends[1] - ends[0];
                if DVec2::new(d.y, -d.x).dot(DVec2::new(n.x, n.y)) < 0.0 {
                    ends.swap(0, 1);
                }
                lo = lo.min(ends[0]).min(ends[1]);
                hi = hi.max(ends[0]).max(ends[1]);
                segs.push((ends[0], ends[1]));
            }
            let (nx, ny) = if segs.is_empty() {
                (0, 0)
            } else {
                (
                    ((hi.x - lo.x) / CELL).floor() as usize + 1,
                    ((hi.y - lo.y) / CELL).floor() as usize + 1,
                )
            };
            let mut cells = vec![Vec::new(); nx * ny];
            let mut rows = vec![Vec::new(); ny];
            for (i, (a, b)) in segs.iter().enumerate() {
                let c0 = ((a.min(*b) - lo) / CELL).floor();
                let c1 = ((a.max(*b) - lo) / CELL).floor();
                let last = (c1.x as usize).min(nx - 1);
                for iy in c0.y as usize..=(c1.y as usize).min(ny - 1) {
                    for ix in c0.x as usize..=last {
                        cells[iy * nx + ix].push(i as u32);
                    }
                    rows[iy].push((*a, *b, last));
                }
            }
            self.cut = Some(Cut {
                z,
                segs,
                origin: lo,
                nx,
                ny,
                cells,
                rows,
            });
        }
        self.cut.as_ref().expect("cut")
    }

    /// Signed distance of `q` (XY, STL frame) from the cut at height `z`: positive outside,
    /// negative inside, clamped to ±[`SEARCH_RADIUS`], mm.
    pub fn signed_distance(&mut self, z: f64, q: DVec2) -> f64 {
        self.cut_at(z);
        let cut = self.cut.as_ref().expect("cut");
        if cut.segs.is_empty() {
            return SEARCH_RADIUS;
        }
        let (nx, ny) = (cut.nx as i64, cut.ny as i64);
        let c = ((q - cut.origin) / CELL).floor();
        let (cx, cy) = (c.x as i64, c.y as i64);
        // nearest segment within the search radius
        let r = (SEARCH_RADIUS / CELL).ceil() as i64;
        let mut best = SEARCH_RADIUS;
        for iy in (cy - r).max(0)..=(cy + r).min(ny - 1) {
            for ix in (cx - r).max(0)..=(cx + r).min(nx - 1) {
                for &s in &cut.cells[(iy * nx + ix) as usize] {
                    let (a, b) = cut.segs[s as usize];
                    best = crate::num::min(best, segment_distance(q, a, b));
                }
            }
        }
        // the ray toward +x along q's row: parity and winding, over the row's segments in a
        // cell from q's column on (a segment's cells in a row are contiguous and start at or
        // before its last, so it has one there exactly when its last column is q's or beyond)
        let inside = if cy < 0 || cy >= ny {
            false
        } else {
            let (mut crossings, mut winding) = (0u32, 0i32);
            for &(a, b, last) in &cut.rows[cy as usize] {
                if (last as i64) < cx || (a.y <= q.y) == (b.y <= q.y) {
                    continue;
                }
                let x = a.x + (q.y - a.y) / (b.y - a.y) * (b.x - a.x);
                if x > q.x {
                    crossings += 1;
                    // with the outward normal on each segment's right, a closed outline
                    // runs counter-clockwise: the ray leaves it through an upward segment
                    winding += if b.y > a.y { 1 } else { -1 };
                }
            }
            crossings % 2 == 1 || winding != 0
        };
        if inside {
            -best
        } else {
            best
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;

    #[test]
    fn a_cube_cut_at_mid_height_is_signed_inside_and_outside() {
        let m = crate::shapes::example("cube").unwrap();
        let b = m.bbox();
        let mut s = Sections::new(&m);
        let z = 0.5 * (b.min.z + b.max.z);
        let c = DVec2::new(0.5 * (b.min.x + b.max.x), 0.5 * (b.min.y + b.max.y));
        let half = 0.5 * (b.max.x - b.min.x);
        // 0.3 mm inside the +x face, 0.2 mm outside it, far inside, far outside
        assert!((s.signed_distance(z, c + DVec2::new(half - 0.3, 0.0)) + 0.3).abs() < 1e-9);
        assert!((s.signed_distance(z, c + DVec2::new(half + 0.2, 0.0)) - 0.2).abs() < 1e-9);
        assert_eq!(s.signed_distance(z, c), -SEARCH_RADIUS);
        assert_eq!(
            s.signed_distance(z, c + DVec2::new(half + 5.0, 0.0)),
            SEARCH_RADIUS
        );
        // above the top: no cut, outside
        assert_eq!(s.signed_distance(b.max.z + 1.0, c), SEARCH_RADIUS);
    }

    /// A subdivided cube's walls have rows of vertices; a layer's mid-height can fall exactly
    /// on one (found on CuraEngine's files of a curved warp: a 20 mm cube's wall row at z = 5.5,
    /// the layer at 5.6 with h = 0.2): the cut must still hold the walls.
    #[test]
    fn a_cut_exactly_through_a_row_of_vertices_keeps_the_walls() {
        let m = crate::shapes::example("cube").unwrap();
        let b = m.bbox();
        let (m, _) = crate::mesh::subdivide(
            &m,
            &crate::mesh::SubdivideOptions {
                max_edge: 0.25 * (b.max.z - b.min.z),
                ..Default::default()
            },
            &|v| v,
        );
        // a height where the subdivided walls have vertices
        let z = m
            .vertices
            .iter()
            .map(|v| v.z)
            .find(|&z| z > b.min.z + 1e-9 && z < b.max.z - 1e-9)
            .expect("a vertex inside the wall");
        let mut s = Sections::new(&m);
        let c = DVec2::new(0.5 * (b.min.x + b.max.x), 0.5 * (b.min.y + b.max.y));
        let half = 0.5 * (b.max.x - b.min.x);
        for dir in [DVec2::X, DVec2::Y, -DVec2::X, -DVec2::Y] {
            let d = s.signed_distance(z, c + dir * (half - 0.3));
            assert!((d + 0.3).abs() < 1e-9, "0.3 mm inside the wall {dir}: {d}");
            let d = s.signed_distance(z, c + dir * (half + 0.2));
            assert!((d - 0.2).abs() < 1e-9, "0.2 mm outside the wall {dir}: {d}");
        }
        assert_eq!(s.signed_distance(z, c), -SEARCH_RADIUS);
    }

    /// Three shells, two of them overlapping (a slicer unites them: inside by winding), cut
    /// at several heights: at random points in and around them the signed distance is the
    /// one found over every segment of the cut without the grid (the point–segment distance
    /// written out here, the ray cast against all segments), so the grid's cells and the rows'
    /// segment lists find what the whole cut holds.
    #[test]
    fn signed_distance_matches_a_search_of_every_segment() {
        let mut m = crate::shapes::sphere(10.0, 24, 48);
        let mut add = |part: Mesh, by: DVec3| {
            let base = m.vertices.len() as u32;
            m.vertices.extend(part.vertices.iter().map(|&v| v + by));
            m.triangles
                .extend(part.triangles.iter().map(|t| t.map(|i| i + base)));
        };
        add(
            crate::shapes::cylinder(6.0, 20.0, 40),
            DVec3::new(8.0, 3.0, -10.0),
        );
        add(crate::shapes::cube(8.0), DVec3::new(-30.0, 0.0, -4.0));
        let b = m.bbox();
        let mut s = Sections::new(&m);
        let mut rng = crate::test_rng::Lcg(5);
        let (mut inside, mut near) = (0, 0);
        for k in 0..7 {
            let z = b.min.z + (b.max.z - b.min.z) * (k as f64 + 0.5) / 7.0;
            for _ in 0..3000 {
                let q = DVec2::new(
                    rng.range(b.min.x - 2.0, b.max.x + 2.0),
                    rng.range(b.min.y - 2.0, b.max.y + 2.0),
                );
                let got = s.signed_distance(z, q);
                let segs = &s.cut.as_ref().expect("cut").segs;
                let (mut d, mut crossings, mut winding) = (SEARCH_RADIUS, 0, 0);
                for &(a, c) in segs {
                    let (ab, aq) = (c - a, q - a);
                    let t = (aq.dot(ab) / ab.dot(ab)).clamp(0.0, 1.0);
                    let e = aq - ab * t;
                    d = d.min((e.x * e.x + e.y * e.y).sqrt());
                    if (a.y > q.y) != (c.y > q.y) {
                        let x = a.x + (c.x - a.x) * (q.y - a.y) / (c.y - a.y);
                        if x > q.x {
                            crossings += 1;
                            winding += if c.y > a.y { 1 } else { -1 };
                        }
                    }
                }
                let want = if crossings % 2 == 1 || winding != 0 {
                    inside += 1;
                    -d
                } else {
                    d
                };
                near += usize::from(d < SEARCH_RADIUS);
                assert!(
                    (got - want).abs() < 1e-9,
                    "z {z}, q {q}: {got}, over every segment {want}"
                );
            }
        }
        // the points cover the inside, the outside and the outlines' neighbourhood
        assert!(
            inside > 2000 && near > 2000,
            "{inside} inside, {near} near an outline"
        );
    }
}
