//! The model as the overhang search sees it: the mesh in the model frame, its facets prepared
//! once ([`Facets`]), the points where admissibility is checked, and its footprint.

use glam::{DVec2, DVec3};

use crate::anchor;
use crate::mesh::{Aabb, Mesh};
use crate::overhang::Facets;

/// Cells of the coarse sample grid per bounding-box diagonal: the search checks a warp's
/// tilt at one point per cell (at most a few tens of thousands on any model), the reported
/// suggestions at every centroid and vertex.
pub const COARSE_CELLS_PER_DIAGONAL: f64 = 60.0;

/// A model ready for measuring and searching (model frame, mm).
#[derive(Clone, Debug)]
pub struct Model {
    /// The mesh in the model frame (XY box centred on the origin, lowest point at z = 0).
    pub mesh: Mesh,
    /// Its bounding box.
    pub bbox: Aabb,
    /// Its facets, prepared once.
    pub facets: Facets,
    /// Every facet centroid and vertex: where a reported warp's admissibility is checked.
    pub samples: Vec<DVec3>,
    /// One sample per cell of a grid [`COARSE_CELLS_PER_DIAGONAL`] cells across (the first
    /// sample met in each cell, in mesh order): where the search checks a candidate.
    pub coarse_samples: Vec<DVec3>,
    /// Area of the convex hull of the XY footprint, mm² (the anchor slab's, [`anchor`]).
    pub hull_area_mm2: f64,
    /// Area-weighted centroid (x, y) of the facets on the bed (the box centre when none).
    pub bed_centroid: [f64; 2],
}

impl Model {
    /// Prepare a mesh already in the model frame.
    pub fn new(mesh: Mesh) -> Model {
        let bbox = mesh.bbox();
        let facets = Facets::new(&mesh);
        let samples: Vec<DVec3> = facets
            .centroids
            .iter()
            .chain(&mesh.vertices)
            .copied()
            .collect();
        let cell = (bbox.size().length() / COARSE_CELLS_PER_DIAGONAL).max(1e-6);
        let mut seen = std::collections::HashSet::new();
        let coarse_samples = samples
            .iter()
            .copied()
            .filter(|p| {
                let k = ((p - bbox.min) / cell).floor();
                seen.insert([k.x as i64, k.y as i64, k.z as i64])
            })
            .collect();
        let mut pts: Vec<DVec2> = mesh.vertices.iter().map(|v| v.truncate()).collect();
        let hull = anchor::convex_hull(&mut pts);
        let hull_area_mm2 = if hull.len() < 3 {
            0.0
        } else {
            0.5 * (0..hull.len())
                .map(|i| hull[i].perp_dot(hull[(i + 1) % hull.len()]))
                .sum::<f64>()
        };
        let (mut a, mut c) = (0.0, DVec2::ZERO);
        for i in 0..facets.areas.len() {
            if facets.on_bed[i] {
                a += facets.areas[i];
                c += facets.areas[i] * facets.centroids[i].truncate();
            }
        }
        let bed_centroid = if a > 0.0 {
            (c / a).to_array()
        } else {
            bbox.center().truncate().to_array()
        };
        Model {
            mesh,
            bbox,
            facets,
            samples,
            coarse_samples,
            hull_area_mm2,
            bed_centroid,
        }
    }
}
