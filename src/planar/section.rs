//! Mesh → closed polygons at one height z (the layer's cut plane).
//!
//! # Cut
//! A vertex with `z_v ≥ z` counts as **above** the plane, one with `z_v < z` as below (a vertex
//! exactly on the plane is above: the triangles under a row of vertices on the plane then give
//! that row's segments, and a face lying in the plane gives none — the rule of
//! `unwarp/section.rs`, whose old "skip the triangle whose highest vertex is on the plane"
//! lost the whole wall at such a row). A triangle with vertices on both sides has exactly one
//! vertex alone on its side; its two edges from that vertex cross the plane at
//! `p = a + (z − z_a)/(z_b − z_a)·(b − a)` (z_b > z_a, so the division is safe).
//!
//! # Orientation
//! The segment runs along `ẑ × n` (n the outward normal of the triangle from its winding), so
//! the material is on its left: outer loops come out counter-clockwise, holes clockwise. With
//! the triangle rotated so that the lone vertex `a` is first (`a, b, c` in winding order), the
//! segment runs from the crossing on edge `c–a` to the one on `a–b` when `a` is below, and
//! the other way when `a` is above.
//!
//! # Chaining
//! Each crossing point is named by what it lies on: the mesh edge `(min(i, j), max(i, j))`, or
//! the vertex itself when the edge's upper end lies exactly on the plane (so neighbouring
//! triangles name a vertex on the plane alike). Names are exact integers, so the many small
//! triangles of a subdivided mesh chain without any distance tolerance. Segments whose two
//! ends have the same name (a triangle touching the plane at one vertex) are dropped.
//!
//! # Repairs
//! An open mesh (a missing triangle) leaves chains that stop. Each open chain's end is joined
//! to the nearest open chain's start within [`REPAIR_GAP`] (possibly its own start): the
//! result is closed and counted in [`Section::repaired`]; chains with no start within reach
//! are dropped and counted in [`Section::dropped`].

use std::collections::HashMap;

use crate::mesh::Mesh;

use super::region::Contour;

/// Largest gap closed between the end of an open chain and the start of another (or its own),
/// mm: a hole of a missing triangle in a subdivided mesh (edges ≤ 1 mm,
/// [`crate::tolerance::DEFAULT_MAX_EDGE`]) leaves a gap of at most one edge length; a wider
/// gap is not a defect this repair can guess across.
pub const REPAIR_GAP: f64 = 2.0;

/// The closed loops of one cut and what had to be repaired.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Section {
    /// Closed loops (first point not repeated), material on the left.
    pub loops: Vec<Contour>,
    /// Open chains closed across a gap of at most [`REPAIR_GAP`].
    pub repaired: usize,
    /// Open chains that could not be closed and were left out.
    pub dropped: usize,
}

/// The name of a crossing point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Key {
    Edge(u32, u32),
    Vertex(u32),
}

/// Cut `mesh` with the plane at height `z`.
pub fn section(mesh: &Mesh, z: f64) -> Section {
    let v = &mesh.vertices;
    let mut segments: Vec<([Key; 2], [[f64; 2]; 2])> = Vec::new();
    let cross = |below: u32, above: u32| -> (Key, [f64; 2]) {
        let (a, b) = (v[below as usize], v[above as usize]);
        if b.z == z {
            return (Key::Vertex(above), [b.x, b.y]);
        }
        let t = (z - a.z) / (b.z - a.z);
        let key = Key::Edge(below.min(above), below.max(above));
        (key, [a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)])
    };
    for tri in &mesh.triangles {
        let above = tri.map(|i| v[i as usize].z >= z);
        let n_above = above.iter().filter(|&&x| x).count();
        if n_above == 0 || n_above == 3 {
            continue;
        }
        // the lone vertex: the one whose side has one member
        let lone_is_above = n_above == 1;
        let k = (0..3)
            .find(|&k| above[k] == lone_is_above)
            .unwrap_or_default();
        let (a, b, c) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
        let (on_ca, on_ab) = if lone_is_above {
            (cross(c, a), cross(b, a))
        } else {
            (cross(a, c), cross(a, b))
        };
        let (from, to) = if lone_is_above {
            (on_ab, on_ca)
        } else {
            (on_ca, on_ab)
        };
        if from.0 != to.0 {
            segments.push(([from.0, to.0], [from.1, to.1]));
        }
    }
    chain(&segments)
}

/// Chain directed segments into loops by their end names; close or drop open chains.
fn chain(segments: &[([Key; 2], [[f64; 2]; 2])]) -> Section {
    let mut starting: HashMap<Key, Vec<usize>> = HashMap::with_capacity(segments.len());
    for (i, s) in segments.iter().enumerate() {
        starting.entry(s.0[0]).or_default().push(i);
    }
    let mut used = vec![false; segments.len()];
    let mut take = |key: Key, used: &mut Vec<bool>| -> Option<usize> {
        let list = starting.get_mut(&key)?;
        let pos = list.iter().position(|&i| !used[i])?;
        let i = list.swap_remove(pos);
        used[i] = true;
        Some(i)
    };
    let mut out = Section::default();
    let mut open: Vec<Contour> = Vec::new();
    for first in 0..segments.len() {
        if used[first] {
            continue;
        }
        used[first] = true;
        let start = segments[first].0[0];
        let mut points = vec![segments[first].1[0]];
        let mut at = first;
        let closed = loop {
            let end = segments[at].0[1];
            if end == start {
                break true;
            }
            points.push(segments[at].1[1]);
            match take(end, &mut used) {
                Some(next) => at = next,
                None => break false,
            }
        };
        if closed {
            if points.len() >= 3 {
                out.loops.push(points);
            }
        } else {
            open.push(points);
        }
    }
    close_open(open, &mut out);
    out
}

/// Join open chains end-to-start across gaps of at most [`REPAIR_GAP`], nearest first.
fn close_open(mut open: Vec<Contour>, out: &mut Section) {
    let dist = |p: [f64; 2], q: [f64; 2]| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt();
    while let Some(mut chain) = open.pop() {
        while let (Some(&end), Some(&start)) = (chain.last(), chain.first()) {
            let own = dist(end, start);
            let other = open
                .iter()
                .enumerate()
                .filter_map(|(i, c)| c.first().map(|&s| (i, dist(end, s))))
                .min_by(|a, b| a.1.total_cmp(&b.1));
            match other {
                Some((i, d)) if d < own && d <= REPAIR_GAP => {
                    let next = open.swap_remove(i);
                    chain.extend(next);
                }
                _ if own <= REPAIR_GAP && chain.len() >= 3 => {
                    out.loops.push(chain);
                    out.repaired += 1;
                    break;
                }
                _ => {
                    out.dropped += 1;
                    break;
                }
            }
        }
    }
}
