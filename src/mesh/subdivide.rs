//! Subdivision before warping. STUB: being written.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::Mesh;

/// When to split an edge.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SubdivideOptions {
    /// Split every edge longer than this, mm (`--max-edge`).
    pub max_edge: f64,
    /// Split every edge whose warped midpoint is further than this from the midpoint of its
    /// warped ends, mm (`--tolerance`).
    pub tolerance: f64,
}

/// Counts before and after.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct SubdivideStats {
    pub triangles_before: usize,
    pub triangles_after: usize,
    pub passes: usize,
}

/// Split edges until none is longer than `max_edge` and none deviates more than `tolerance`
/// under `warp`. Shared edges are split at one shared vertex, so a closed mesh stays closed.
pub fn subdivide(mesh: &Mesh, _opts: &SubdivideOptions, _warp: &dyn Fn(DVec3) -> DVec3) -> (Mesh, SubdivideStats) {
    (mesh.clone(), SubdivideStats::default())
}
