//! Mesh defects: counted and reported, never refused.
//!
//! - **degenerate** triangle: its smallest altitude `h = |(b−a)×(c−a)| / ℓ_max` (ℓ_max its
//!   longest edge) is below [`DEGENERATE_ALTITUDE`] — zero or near-zero area for its size
//!   (this also catches a triangle that uses one vertex twice, and long slivers whose area is
//!   not small but whose width is).
//! - **open** edge: an undirected edge used by exactly one triangle (a hole's rim).
//! - **non-manifold** edge: an undirected edge used by more than two triangles.
//!
//! A closed, manifold mesh has no open and no non-manifold edge.

use serde::{Deserialize, Serialize};

use super::edges::EdgeTable;
use super::{Aabb, Mesh, StlFormat};

/// A triangle whose smallest altitude is below this is degenerate, mm. 1e-6 mm is far below
/// anything a printer resolves yet above the rounding noise of f32 coordinates for parts up
/// to ≈ 10 mm from the origin; collinear-by-construction triangles far from the origin can
/// keep an altitude of a few f32 ulps (≈ 1e-4 mm at 1 m) and are then not flagged, which is
/// harmless: they slice like any thin sliver.
pub const DEGENERATE_ALTITUDE: f64 = 1e-6;

/// What was read and what is wrong with it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeshReport {
    /// Which kind of STL was read.
    pub format: StlFormat,
    /// Number of triangles.
    pub triangles: usize,
    /// Number of vertices (for a read STL: distinct coordinates after welding).
    pub vertices: usize,
    /// Triangles with (near) zero area (see [`DEGENERATE_ALTITUDE`]).
    pub degenerate: usize,
    /// Edges used by one triangle only.
    pub open_edges: usize,
    /// Edges used by more than two triangles.
    pub nonmanifold_edges: usize,
    /// Bounding box of the vertices that triangles use, mm (the mesh's own frame).
    pub bbox: Aabb,
    /// Facets whose stored normal is (0, 0, 0). Harmless: normals are recomputed from the
    /// vertex order (counter-clockwise seen from outside). Set by `read_stl` only.
    #[serde(default)]
    pub zero_normals: usize,
    /// Facets whose stored normal points against the normal of their vertex order (a hint
    /// that the file's winding is clockwise, i.e. the model may be inside out). Set by
    /// `read_stl` only.
    #[serde(default)]
    pub flipped_normals: usize,
    /// Other things the reader tolerated (missing `endsolid`, trailing bytes, …), one
    /// sentence each.
    #[serde(default)]
    pub warnings: Vec<String>,
}

/// Whether triangle `(a, b, c)` is degenerate (see [`DEGENERATE_ALTITUDE`]).
pub fn is_degenerate(a: glam::DVec3, b: glam::DVec3, c: glam::DVec3) -> bool {
    let l2 = (b - a)
        .length_squared()
        .max((c - b).length_squared())
        .max((a - c).length_squared());
    let twice_area = (b - a).cross(c - a).length();
    // h = 2A / ℓ_max < ε  ⇔  2A < ε ℓ_max  (no division; ℓ_max = 0 counts as degenerate)
    !(twice_area >= DEGENERATE_ALTITUDE * l2.sqrt() && l2 > 0.0)
}

impl MeshReport {
    /// Count the defects of `mesh`. Triangles with an out-of-range vertex index count as
    /// degenerate and add no edges.
    pub fn of(mesh: &Mesh, format: StlFormat) -> MeshReport {
        let nv = mesh.vertices.len();
        let mut degenerate = 0;
        let mut bbox = Aabb::EMPTY;
        for t in &mesh.triangles {
            let p = t.map(|i| mesh.vertices.get(i as usize).copied());
            match p {
                [Some(a), Some(b), Some(c)] => {
                    if is_degenerate(a, b, c) {
                        degenerate += 1;
                    }
                    bbox.include(a);
                    bbox.include(b);
                    bbox.include(c);
                }
                _ => degenerate += 1,
            }
        }
        let table = EdgeTable::build(nv, &mesh.triangles);
        let (mut open_edges, mut nonmanifold_edges) = (0, 0);
        table.for_each(|e| match e.uses {
            1 => open_edges += 1,
            2 => {}
            _ => nonmanifold_edges += 1,
        });
        MeshReport {
            format,
            triangles: mesh.triangles.len(),
            vertices: nv,
            degenerate,
            open_edges,
            nonmanifold_edges,
            bbox,
            zero_normals: 0,
            flipped_normals: 0,
            warnings: Vec::new(),
        }
    }

    /// Whether the mesh is closed and manifold (no open and no non-manifold edge).
    pub fn is_watertight(&self) -> bool {
        self.open_edges == 0 && self.nonmanifold_edges == 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn tetra() -> Mesh {
        Mesh {
            vertices: vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z],
            triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        }
    }

    #[test]
    fn closed_tetrahedron_has_no_defects() {
        let r = MeshReport::of(&tetra(), StlFormat::Binary);
        assert_eq!(
            (
                r.triangles,
                r.vertices,
                r.degenerate,
                r.open_edges,
                r.nonmanifold_edges
            ),
            (4, 4, 0, 0, 0)
        );
        assert!(r.is_watertight());
        assert_eq!(
            r.bbox,
            Aabb {
                min: DVec3::ZERO,
                max: DVec3::ONE
            }
        );
    }

    #[test]
    fn missing_face_opens_three_edges() {
        let mut m = tetra();
        m.triangles.pop();
        let r = MeshReport::of(&m, StlFormat::Binary);
        assert_eq!((r.open_edges, r.nonmanifold_edges), (3, 0));
    }

    #[test]
    fn fin_on_an_edge_is_nonmanifold() {
        let mut m = tetra();
        m.vertices.push(DVec3::new(0.5, -1.0, 0.0));
        m.triangles.push([0, 1, 4]); // a third triangle on edge 0-1, itself open on 2 edges
        let r = MeshReport::of(&m, StlFormat::Binary);
        assert_eq!((r.open_edges, r.nonmanifold_edges), (2, 1));
    }

    #[test]
    fn repeated_vertex_and_collinear_triangles_are_degenerate() {
        let m = Mesh {
            vertices: vec![
                DVec3::ZERO,
                DVec3::X,
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(0.5, 1e-9, 0.0),
            ],
            triangles: vec![[0, 0, 1], [0, 1, 2], [0, 1, 3]],
        };
        assert_eq!(MeshReport::of(&m, StlFormat::Ascii).degenerate, 3);
        // and a thin but real triangle is not
        assert!(!is_degenerate(
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(0.5, 1e-3, 0.0)
        ));
    }

    #[test]
    fn out_of_range_index_is_counted_not_a_panic() {
        let m = Mesh {
            vertices: vec![DVec3::ZERO, DVec3::X],
            triangles: vec![[0, 1, 5]],
        };
        let r = MeshReport::of(&m, StlFormat::Binary);
        assert_eq!(r.degenerate, 1);
        assert!(r.bbox.is_empty());
    }
}
