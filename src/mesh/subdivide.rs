//! Subdivision before warping.
//!
//! A warp `W` moves vertices only; a straight edge `ab` stays straight after warping while
//! the exact image `W(ab)` bends. So, before warping, every edge is split at its midpoint
//! `m = (a + b)/2` while
//!
//! - it is longer than `max_edge`: `|b − a| > max_edge`, or
//! - its warped chord misses the warped midpoint by more than `tolerance`:
//!   `|W(m) − (W(a) + W(b))/2| > tolerance`,
//!
//! whichever is reached first, repeated pass after pass until no edge needs a split. (The
//! midpoint is where a smooth warp's chord error is largest to second order, so the test
//! bounds the whole edge's error up to third-order terms.) An
//! affine warp keeps every chord exact (deviation = rounding noise), so it refines only to
//! `max_edge`. Units: mm; the frame is whatever the mesh and the warp share (the model frame
//! in the pipeline).
//!
//! ## One pass (red–green refinement, conforming)
//! Every edge has one id, whatever the number of triangles using it (the input's edges are
//! found once with an edge table, `edges.rs`; later ones get ids as triangles are split), so
//! a shared edge is split at ONE new vertex: a closed mesh stays closed, no T-junctions.
//! Each triangle `(a, b, c)` (counter-clockwise) is then replaced according to how many of
//! its edges were split, keeping its orientation:
//!
//! - 0: `(a, b, c)`;
//! - 1 (`ab` at `m`): `(a, m, c)`, `(m, b, c)`;
//! - 2 (`ab` at `p`, `bc` at `q`): `(p, b, q)` plus the quad `a p q c` cut along its shorter
//!   diagonal: `(a, p, q)`, `(a, q, c)` if `|a − q| ≤ |p − c|`, else `(a, p, c)`, `(p, q, c)`;
//! - 3 (`ab`, `bc`, `ca` at `p`, `q`, `r`): `(a, p, r)`, `(p, b, q)`, `(r, q, c)`, `(p, q, r)`.
//!
//! An edge that was tested and kept never changes, so each pass tests only the edges the
//! previous pass created (halves of split edges and inner edges of split triangles). Each
//! vertex is warped exactly once ([`subdivide_warped`] returns those warped positions).
//!
//! ## Runaway guard
//! A pass that would exceed [`MAX_TRIANGLES`] triangles, or a pass beyond [`MAX_PASSES`], is
//! not made: the mesh of the last completed pass is returned and
//! [`SubdivideStats::limit_hit`] says which cap stopped it (edges may then still exceed the
//! bounds). Non-positive `max_edge`/`tolerance` ask for refinement without end and hit a cap;
//! NaN disables the criterion.
//!
//! ## Dropped triangles
//! A triangle that uses one vertex twice (STL facets with two identical corners weld to
//! those) has no area and a self-loop edge; splitting its other edge would make nonsense
//! topology, so it is dropped, as is a triangle with an out-of-range vertex index
//! ([`SubdivideStats::dropped_triangles`]). Collinear triangles with three distinct vertices
//! are kept and subdivided like any other. Two triangles over the same three vertices (a
//! doubled facet) each own the inner edges of their subdivisions, so those are not shared:
//! refined further, such a pair may get two coincident midpoints (harmless geometry, but
//! the edge counts of the result then report it as open).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::edges::EdgeTable;
use super::Mesh;
use crate::tolerance::{DEFAULT_MAX_EDGE, DEFAULT_TOLERANCE};

/// Most refinement passes. Each pass halves every edge it splits, so 40 passes shrink an
/// edge by 2⁴⁰ ≈ 10¹²: a 1 km edge down to 1 nm. Reaching it means the bounds cannot be met
/// (e.g. a warp that is not continuous).
pub const MAX_PASSES: usize = 40;
/// Most triangles subdivision may produce. Peak memory is about 100 bytes per output
/// triangle (triangles and their edge ids, vertices and their warped images, edges), so
/// ≈ 1 GB at the cap; the wasm32 heap is at most 4 GiB and a 10 M-triangle STL is 500 MB.
pub const MAX_TRIANGLES: usize = 10_000_000;

/// When to split an edge.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SubdivideOptions {
    /// Split every edge longer than this, mm (`--max-edge`).
    pub max_edge: f64,
    /// Split every edge whose warped midpoint is further than this from the midpoint of its
    /// warped ends, mm (`--tolerance`).
    pub tolerance: f64,
}

impl Default for SubdivideOptions {
    /// [`DEFAULT_MAX_EDGE`] (1 mm) and [`DEFAULT_TOLERANCE`] (0.01 mm).
    fn default() -> Self {
        SubdivideOptions {
            max_edge: DEFAULT_MAX_EDGE,
            tolerance: DEFAULT_TOLERANCE,
        }
    }
}

/// Which runaway guard stopped a subdivision.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SubdivideLimit {
    /// [`MAX_PASSES`] passes were made and edges still needed splitting.
    Passes,
    /// The next pass would have produced more than [`MAX_TRIANGLES`] triangles.
    Triangles,
}

/// Counts before and after.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct SubdivideStats {
    /// Triangles in the input mesh.
    pub triangles_before: usize,
    /// Triangles in the subdivided mesh.
    pub triangles_after: usize,
    /// Passes that split at least one edge.
    pub passes: usize,
    /// Edges split, over all passes (= vertices added).
    #[serde(default)]
    pub edges_split: usize,
    /// Input triangles dropped because they use one vertex twice (no area, and their
    /// self-loop edge has no sensible split) or have an out-of-range vertex index.
    #[serde(default)]
    pub dropped_triangles: usize,
    /// `Some` when a runaway guard stopped refinement before the bounds were met.
    #[serde(default)]
    pub limit_hit: Option<SubdivideLimit>,
}

/// Split edges until none is longer than `max_edge` and none deviates more than `tolerance`
/// under `warp`. Shared edges are split at one shared vertex, so a closed mesh stays closed.
/// See the module documentation for the rules.
pub fn subdivide(
    mesh: &Mesh,
    opts: &SubdivideOptions,
    warp: &dyn Fn(DVec3) -> DVec3,
) -> (Mesh, SubdivideStats) {
    let (m, _, s) = subdivide_warped(mesh, opts, warp);
    (m, s)
}

/// [`subdivide`], also returning `warp(v)` for every output vertex (computed once each during
/// subdivision), so the caller need not warp the result again.
pub fn subdivide_warped(
    mesh: &Mesh,
    opts: &SubdivideOptions,
    warp: &dyn Fn(DVec3) -> DVec3,
) -> (Mesh, Vec<DVec3>, SubdivideStats) {
    subdivide_warped_capped(mesh, opts, warp, MAX_TRIANGLES)
}

/// [`subdivide_warped`] with another triangle cap than [`MAX_TRIANGLES`] (tests reach it on a
/// small mesh).
pub fn subdivide_warped_capped(
    mesh: &Mesh,
    opts: &SubdivideOptions,
    warp: &dyn Fn(DVec3) -> DVec3,
    max_triangles: usize,
) -> (Mesh, Vec<DVec3>, SubdivideStats) {
    refine(mesh, opts, warp, MAX_PASSES, max_triangles)
}

/// No vertex / no edge.
const NONE: u32 = u32::MAX;

/// The edges of the mesh being refined, structure of arrays indexed by edge id. Ids are
/// never reused: a split edge stays (dead) and its two halves get the next two ids.
#[derive(Default)]
struct Edges {
    /// End vertices as first created (`ends[e][0]` is the end its first half touches).
    ends: Vec<[u32; 2]>,
    /// Midpoint vertex if split, else [`NONE`] (no triangle refers to a split edge after its
    /// pass).
    mid: Vec<u32>,
    /// Triangle corners using the edge (2 for an inner edge of a closed mesh).
    uses: Vec<u32>,
}

impl Edges {
    #[inline]
    fn push(&mut self, a: u32, b: u32, uses: u32) -> u32 {
        self.ends.push([a, b]);
        self.mid.push(NONE);
        self.uses.push(uses);
        (self.ends.len() - 1) as u32
    }
    fn truncate(&mut self, n: usize) {
        self.ends.truncate(n);
        self.mid.truncate(n);
        self.uses.truncate(n);
    }
}

/// The refinement loop with explicit caps (the public functions use [`MAX_PASSES`] and
/// [`MAX_TRIANGLES`]; tests use small ones).
///
/// Bookkeeping: every triangle knows the ids of its three edges (`tri_e[t][i]` is edge
/// `t[i] → t[(i+1) % 3]`). The input's edges are found once ([`EdgeTable`]); after that each
/// pass creates the ids of the halves of the edges it splits (pushed in pairs, in split order,
/// so split `k` of a pass owns ids `first + 2k`, `first + 2k + 1`) and of the inner edges of
/// the split triangles. The edges created by a pass are exactly those the next pass must test
/// (every other edge was tested and kept), so the candidates of a pass are an id range.
fn refine(
    mesh: &Mesh,
    opts: &SubdivideOptions,
    warp: &dyn Fn(DVec3) -> DVec3,
    max_passes: usize,
    max_triangles: usize,
) -> (Mesh, Vec<DVec3>, SubdivideStats) {
    // Signed squares: a negative bound gives a negative square, which every length exceeds.
    let max2 = opts.max_edge * opts.max_edge.abs();
    let tol2 = opts.tolerance * opts.tolerance.abs();

    let mut verts = mesh.vertices.clone();
    let mut warped: Vec<DVec3> = verts.iter().map(|&p| warp(p)).collect();
    let nv = verts.len();
    let keep = |t: &&[u32; 3]| {
        t.iter().all(|&i| (i as usize) < nv) && t[0] != t[1] && t[1] != t[2] && t[2] != t[0]
    };
    let mut tris: Vec<[u32; 3]> = mesh.triangles.iter().filter(keep).copied().collect();
    let mut stats = SubdivideStats {
        triangles_before: mesh.triangles.len(),
        dropped_triangles: mesh.triangles.len() - tris.len(),
        ..SubdivideStats::default()
    };

    // The input's edges, numbered 0.. in table order.
    let mut edges = Edges::default();
    let mut tri_e: Vec<[u32; 3]> = vec![[NONE; 3]; tris.len()];
    {
        let table = EdgeTable::build(nv, &tris);
        let mut id_of_slot = vec![NONE; table.slots()];
        table.for_each(|e| id_of_slot[e.id as usize] = edges.push(e.lo, e.hi, e.uses));
        for (t, te) in tri_e.iter_mut().enumerate() {
            for (i, slot) in te.iter_mut().enumerate() {
                *slot = id_of_slot[table.edge_of(3 * t + i) as usize];
            }
        }
    }

    let mut next: Vec<[u32; 3]> = Vec::new();
    let mut next_e: Vec<[u32; 3]> = Vec::new();
    let mut candidates = 0..edges.ends.len();
    loop {
        // 1. Test the candidates; split ones get a midpoint (warped now, once) and two halves.
        let base_v = verts.len();
        let first_half = edges.ends.len();
        let mut extra = 0usize;
        for e in candidates.clone() {
            let [a, b] = edges.ends[e];
            let (pa, pb) = (verts[a as usize], verts[b as usize]);
            let m = (pa + pb) * 0.5;
            let wm = warp(m);
            let split = (pb - pa).length_squared() > max2
                || (wm - (warped[a as usize] + warped[b as usize]) * 0.5).length_squared() > tol2;
            if split {
                let mi = verts.len() as u32;
                verts.push(m);
                warped.push(wm);
                edges.mid[e] = mi;
                let u = edges.uses[e];
                edges.push(a, mi, u);
                edges.push(mi, b, u);
                extra += u as usize;
            }
        }
        let added = verts.len() - base_v;
        if added == 0 {
            break;
        }
        let limit = if stats.passes >= max_passes {
            Some(SubdivideLimit::Passes)
        } else if tris.len().saturating_add(extra) > max_triangles || verts.len() >= NONE as usize {
            Some(SubdivideLimit::Triangles)
        } else {
            None
        };
        if limit.is_some() {
            verts.truncate(base_v);
            warped.truncate(base_v);
            edges.truncate(first_half);
            stats.limit_hit = limit;
            break;
        }

        // 2. Replace every triangle by its children, with the ids of their edges.
        next.clear();
        next_e.clear();
        next.reserve(tris.len() + extra);
        next_e.reserve(tris.len() + extra);
        // The half of split edge `e` that touches its end `v`.
        let half = |edges: &Edges, e: u32, v: u32| -> u32 {
            let h = (first_half + 2 * (edges.mid[e as usize] as usize - base_v)) as u32;
            if edges.ends[e as usize][0] == v {
                h
            } else {
                h + 1
            }
        };
        for (&[a, b, c], &[eab, ebc, eca]) in tris.iter().zip(&tri_e) {
            let m = [
                edges.mid[eab as usize],
                edges.mid[ebc as usize],
                edges.mid[eca as usize],
            ];
            let mask =
                (m[0] != NONE) as u8 | ((m[1] != NONE) as u8) << 1 | ((m[2] != NONE) as u8) << 2;
            match mask {
                0 => {
                    next.push([a, b, c]);
                    next_e.push([eab, ebc, eca]);
                }
                1 | 2 | 4 => {
                    // rotate so that ab (at p) is the split edge
                    let (a, b, c, eab, ebc, eca, p) = match mask {
                        1 => (a, b, c, eab, ebc, eca, m[0]),
                        2 => (b, c, a, ebc, eca, eab, m[1]),
                        _ => (c, a, b, eca, eab, ebc, m[2]),
                    };
                    let pc = edges.push(p, c, 2);
                    next.push([a, p, c]);
                    next_e.push([half(&edges, eab, a), pc, eca]);
                    next.push([p, b, c]);
                    next_e.push([half(&edges, eab, b), ebc, pc]);
                }
                7 => {
                    let (p, q, r) = (m[0], m[1], m[2]);
                    let pq = edges.push(p, q, 2);
                    let qr = edges.push(q, r, 2);
                    let rp = edges.push(r, p, 2);
                    next.extend_from_slice(&[[a, p, r], [p, b, q], [r, q, c], [p, q, r]]);
                    next_e.extend_from_slice(&[
                        [half(&edges, eab, a), rp, half(&edges, eca, a)],
                        [half(&edges, eab, b), half(&edges, ebc, b), pq],
                        [qr, half(&edges, ebc, c), half(&edges, eca, c)],
                        [pq, qr, rp],
                    ]);
                }
                _ => {
                    // two splits: rotate so that ab (at p) and bc (at q) are split, ca is not
                    let (a, b, c, eab, ebc, eca, p, q) = match mask {
                        3 => (a, b, c, eab, ebc, eca, m[0], m[1]),
                        6 => (b, c, a, ebc, eca, eab, m[1], m[2]),
                        _ => (c, a, b, eca, eab, ebc, m[2], m[0]),
                    };
                    let pq = edges.push(p, q, 2);
                    let (ap, pb) = (half(&edges, eab, a), half(&edges, eab, b));
                    let (bq, qc) = (half(&edges, ebc, b), half(&edges, ebc, c));
                    next.push([p, b, q]);
                    next_e.push([pb, bq, pq]);
                    let len2 =
                        |i: u32, j: u32| (verts[i as usize] - verts[j as usize]).length_squared();
                    if len2(a, q) <= len2(p, c) {
                        let aq = edges.push(a, q, 2);
                        next.extend_from_slice(&[[a, p, q], [a, q, c]]);
                        next_e.extend_from_slice(&[[ap, pq, aq], [aq, qc, eca]]);
                    } else {
                        let pc = edges.push(p, c, 2);
                        next.extend_from_slice(&[[a, p, c], [p, q, c]]);
                        next_e.extend_from_slice(&[[ap, pc, eca], [pq, qc, pc]]);
                    }
                }
            }
        }
        std::mem::swap(&mut tris, &mut next);
        std::mem::swap(&mut tri_e, &mut next_e);
        candidates = first_half..edges.ends.len();
        stats.passes += 1;
        stats.edges_split += added;
    }
    stats.triangles_after = tris.len();
    (
        Mesh {
            vertices: verts,
            triangles: tris,
        },
        warped,
        stats,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;

    #[test]
    fn triangle_cap_stops_before_the_pass_that_would_exceed_it() {
        let cube = shapes::cuboid(DVec3::ZERO, DVec3::splat(8.0));
        let opts = SubdivideOptions {
            max_edge: 0.0,
            tolerance: 1.0,
        };
        // 12 → 48 → 192 → 768: a cap of 500 allows two passes
        let (m, w, s) = refine(&cube, &opts, &|p| p, MAX_PASSES, 500);
        assert_eq!(
            (s.passes, s.triangles_after, m.triangles.len()),
            (2, 192, 192)
        );
        assert_eq!(s.limit_hit, Some(SubdivideLimit::Triangles));
        // the rolled-back pass left no stray vertices
        assert_eq!(m.vertices.len(), w.len());
        assert_eq!(m.vertices.len(), 8 + 18 + 72);
    }

    #[test]
    fn pass_cap_stops_refinement() {
        let cube = shapes::cuboid(DVec3::ZERO, DVec3::splat(8.0));
        let opts = SubdivideOptions {
            max_edge: 0.0,
            tolerance: 1.0,
        };
        let (m, _, s) = refine(&cube, &opts, &|p| p, 1, usize::MAX);
        assert_eq!(
            (s.passes, m.triangles.len(), s.limit_hit),
            (1, 48, Some(SubdivideLimit::Passes))
        );
    }

    #[test]
    fn discontinuous_warp_hits_a_cap_and_leaves_a_closed_mesh() {
        // a step across x = 0.3: the edges crossing it can never meet the tolerance
        let step = |p: DVec3| if p.x > 0.3 { p + DVec3::Z } else { p };
        let cube = shapes::cuboid(DVec3::ZERO, DVec3::splat(1.0));
        let (m, _, s) = refine(
            &cube,
            &SubdivideOptions::default(),
            &step,
            MAX_PASSES,
            20_000,
        );
        assert_eq!(s.limit_hit, Some(SubdivideLimit::Triangles));
        assert!(m.triangles.len() <= 20_000);
        let r = crate::mesh::MeshReport::of(&m, crate::mesh::StlFormat::Binary);
        assert_eq!((r.open_edges, r.nonmanifold_edges), (0, 0));
    }
}
