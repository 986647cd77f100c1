//! Mesh defects: counted and reported, never refused. STUB: being written.

use serde::{Deserialize, Serialize};

use super::{Aabb, Mesh, StlFormat};

/// What was read and what is wrong with it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeshReport {
    pub format: StlFormat,
    pub triangles: usize,
    pub vertices: usize,
    /// Triangles with (near) zero area.
    pub degenerate: usize,
    /// Edges used by one triangle only.
    pub open_edges: usize,
    /// Edges used by more than two triangles.
    pub nonmanifold_edges: usize,
    pub bbox: Aabb,
}

impl MeshReport {
    pub fn of(mesh: &Mesh, format: StlFormat) -> MeshReport {
        MeshReport {
            format,
            triangles: mesh.triangles.len(),
            vertices: mesh.vertices.len(),
            degenerate: 0,
            open_edges: 0,
            nonmanifold_edges: 0,
            bbox: mesh.bbox(),
        }
    }
}
