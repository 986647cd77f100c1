//! Unique undirected edges of a triangle list (used by the defect report and by subdivision).
//!
//! Layout (compressed rows keyed by the smaller vertex index): every half-edge `h = 3t + i` of
//! triangle `t` runs from `t[i]` to `t[(i+1) % 3]`; it is filed under `lo = min` as the entry
//! `(hi << 32) | h`. Each vertex's row is sorted, so the half-edges of one undirected edge
//! `{lo, hi}` form one run; the edge's id is the slot of the run's first entry. Building is
//! linear in the number of triangles (plus a sort of each tiny row), with no hashing and no
//! per-triangle allocation; the buffers are reused by [`EdgeTable::rebuild`].

/// The unique edges of a triangle list. Ids are slots in `0..3·T` (with gaps).
#[derive(Default, Debug, Clone)]
pub(crate) struct EdgeTable {
    /// Row of vertex `v`: slots `start[v]..start[v+1]`.
    start: Vec<u32>,
    /// `(hi << 32) | half_edge`, sorted within each row.
    entries: Vec<u64>,
    /// For every half-edge, the id (first slot) of its undirected edge.
    edge_of: Vec<u32>,
    /// Write cursors, scratch.
    cursor: Vec<u32>,
}

/// One undirected edge: its id, its two vertices (`lo ≤ hi`) and how many half-edges use it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Edge {
    pub id: u32,
    pub lo: u32,
    pub hi: u32,
    pub uses: u32,
}

impl EdgeTable {
    /// Build from `triangles` over `vertex_count` vertices. Triangles with an index
    /// `≥ vertex_count` must have been rejected by the caller (they are skipped here).
    pub fn build(vertex_count: usize, triangles: &[[u32; 3]]) -> EdgeTable {
        let mut t = EdgeTable::default();
        t.rebuild(vertex_count, triangles);
        t
    }

    /// Rebuild in place, reusing the buffers.
    pub fn rebuild(&mut self, vertex_count: usize, triangles: &[[u32; 3]]) {
        let nh = triangles.len() * 3;
        self.start.clear();
        self.start.resize(vertex_count + 1, 0);
        for tri in triangles {
            if !valid(tri, vertex_count) {
                continue;
            }
            for i in 0..3 {
                let lo = tri[i].min(tri[(i + 1) % 3]) as usize;
                self.start[lo + 1] += 1;
            }
        }
        for v in 0..vertex_count {
            self.start[v + 1] += self.start[v];
        }
        self.cursor.clear();
        self.cursor.extend_from_slice(&self.start[..vertex_count]);
        let used = self.start[vertex_count] as usize;
        self.entries.clear();
        self.entries.resize(used, 0);
        self.edge_of.clear();
        self.edge_of.resize(nh, u32::MAX);
        for (t, tri) in triangles.iter().enumerate() {
            if !valid(tri, vertex_count) {
                continue;
            }
            for i in 0..3 {
                let (a, b) = (tri[i], tri[(i + 1) % 3]);
                let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
                let c = &mut self.cursor[lo as usize];
                self.entries[*c as usize] = (u64::from(hi) << 32) | (3 * t + i) as u64;
                *c += 1;
            }
        }
        for v in 0..vertex_count {
            let (s, e) = (self.start[v] as usize, self.start[v + 1] as usize);
            let row = &mut self.entries[s..e];
            if row.len() > 1 {
                row.sort_unstable();
            }
            let mut first = s;
            for k in s..e {
                if (self.entries[k] >> 32) != (self.entries[first] >> 32) {
                    first = k;
                }
                let h = (self.entries[k] & 0xffff_ffff) as usize;
                self.edge_of[h] = first as u32;
            }
        }
    }

    /// Number of id slots (an upper bound of every id, for sizing per-edge arrays).
    pub fn slots(&self) -> usize {
        self.entries.len()
    }

    /// The id of the undirected edge of half-edge `3t + i` (u32::MAX for a skipped triangle).
    #[inline]
    pub fn edge_of(&self, half_edge: usize) -> u32 {
        self.edge_of.get(half_edge).copied().unwrap_or(u32::MAX)
    }

    /// Every undirected edge once, by increasing `lo`, then `hi`.
    pub fn for_each(&self, mut f: impl FnMut(Edge)) {
        for v in 0..self.start.len().saturating_sub(1) {
            let (s, e) = (self.start[v] as usize, self.start[v + 1] as usize);
            let mut k = s;
            while k < e {
                let hi = (self.entries[k] >> 32) as u32;
                let mut n = k + 1;
                while n < e && (self.entries[n] >> 32) as u32 == hi {
                    n += 1;
                }
                f(Edge {
                    id: k as u32,
                    lo: v as u32,
                    hi,
                    uses: (n - k) as u32,
                });
                k = n;
            }
        }
    }
}

#[inline]
fn valid(tri: &[u32; 3], vertex_count: usize) -> bool {
    tri.iter().all(|&i| (i as usize) < vertex_count)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_triangles_share_one_edge() {
        // square 0-1-2-3 split by diagonal 0-2
        let t = EdgeTable::build(4, &[[0, 1, 2], [0, 2, 3]]);
        let mut edges = Vec::new();
        t.for_each(|e| edges.push((e.lo, e.hi, e.uses)));
        assert_eq!(
            edges,
            vec![(0, 1, 1), (0, 2, 2), (0, 3, 1), (1, 2, 1), (2, 3, 1)]
        );
        // half-edge 2 of triangle 0 (2→0) and half-edge 0 of triangle 1 (0→2) share an id
        assert_eq!(t.edge_of(2), t.edge_of(3));
        assert_ne!(t.edge_of(0), t.edge_of(3));
    }

    #[test]
    fn out_of_range_triangle_is_skipped_not_a_panic() {
        let t = EdgeTable::build(3, &[[0, 1, 7], [0, 1, 2]]);
        let mut n = 0;
        t.for_each(|_| n += 1);
        assert_eq!(n, 3);
        assert_eq!(t.edge_of(0), u32::MAX);
    }
}
