//! Generated meshes for tests and benchmarks (closed ones are counter-clockwise seen from
//! outside, welded, manifold).

use glam::DVec3;

use super::Mesh;

/// The closed box `[min, max]`: 8 vertices, 12 triangles.
pub fn cuboid(min: DVec3, max: DVec3) -> Mesh {
    let v = |i: u32| {
        DVec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        )
    };
    // vertex i has bits (x, y, z); faces as quads, counter-clockwise from outside
    let quads: [[u32; 4]; 6] = [
        [0, 2, 3, 1], // z = min, normal −z
        [4, 5, 7, 6], // z = max, +z
        [0, 1, 5, 4], // y = min, −y
        [2, 6, 7, 3], // y = max, +y
        [0, 4, 6, 2], // x = min, −x
        [1, 3, 7, 5], // x = max, +x
    ];
    let mut triangles = Vec::with_capacity(12);
    for [a, b, c, d] in quads {
        triangles.push([a, b, c]);
        triangles.push([a, c, d]);
    }
    Mesh {
        vertices: (0..8).map(v).collect(),
        triangles,
    }
}

/// A closed UV sphere about `center`: `rings ≥ 2` latitude bands, `segments ≥ 3` longitude
/// steps; `2 · segments · (rings − 1)` triangles (rings = 301, segments = 375 gives 225 000).
/// Fewer rings or segments are raised to the minimum.
pub fn uv_sphere(center: DVec3, radius: f64, rings: u32, segments: u32) -> Mesh {
    let (rings, segments) = (rings.max(2), segments.max(3));
    let mut vertices = Vec::with_capacity(((rings - 1) * segments + 2) as usize);
    vertices.push(center + DVec3::Z * radius); // north pole, index 0
    for i in 1..rings {
        let theta = core::f64::consts::PI * f64::from(i) / f64::from(rings);
        let (st, ct) = (crate::num::sin(theta), crate::num::cos(theta));
        for j in 0..segments {
            let phi = 2.0 * core::f64::consts::PI * f64::from(j) / f64::from(segments);
            vertices.push(
                center
                    + radius * DVec3::new(st * crate::num::cos(phi), st * crate::num::sin(phi), ct),
            );
        }
    }
    let south = vertices.len() as u32;
    vertices.push(center - DVec3::Z * radius);
    let ring = |i: u32, j: u32| 1 + (i - 1) * segments + (j % segments);
    let mut triangles = Vec::with_capacity((2 * segments * (rings - 1)) as usize);
    for j in 0..segments {
        triangles.push([0, ring(1, j), ring(1, j + 1)]);
    }
    for i in 1..rings - 1 {
        for j in 0..segments {
            let (a, b, c, d) = (
                ring(i, j),
                ring(i + 1, j),
                ring(i + 1, j + 1),
                ring(i, j + 1),
            );
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    for j in 0..segments {
        triangles.push([south, ring(rings - 1, j + 1), ring(rings - 1, j)]);
    }
    Mesh {
        vertices,
        triangles,
    }
}

/// A flat open sheet in the plane z = 0: `nx × ny` square cells of side `cell` from the
/// origin, two triangles each (`2 · nx · ny` triangles), facing +z.
pub fn grid(nx: u32, ny: u32, cell: f64) -> Mesh {
    let mut vertices = Vec::with_capacity(((nx + 1) * (ny + 1)) as usize);
    for j in 0..=ny {
        for i in 0..=nx {
            vertices.push(DVec3::new(f64::from(i) * cell, f64::from(j) * cell, 0.0));
        }
    }
    let id = |i: u32, j: u32| j * (nx + 1) + i;
    let mut triangles = Vec::with_capacity((2 * nx * ny) as usize);
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    Mesh {
        vertices,
        triangles,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshReport, StlFormat};

    #[test]
    fn cuboid_is_closed_and_outward() {
        let m = cuboid(DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0));
        let r = MeshReport::of(&m, StlFormat::Binary);
        assert!(r.is_watertight());
        assert_eq!(r.degenerate, 0);
        assert!((m.signed_volume() - 6.0).abs() < 1e-12);
    }

    #[test]
    fn sphere_is_closed_and_outward() {
        let m = uv_sphere(DVec3::ZERO, 1.0, 12, 16);
        assert_eq!(m.triangles.len(), 2 * 16 * 11);
        let r = MeshReport::of(&m, StlFormat::Binary);
        assert!(r.is_watertight(), "{r:?}");
        assert_eq!(r.degenerate, 0);
        let v = m.signed_volume();
        assert!(v > 3.5 && v < 4.0 * core::f64::consts::PI / 3.0, "{v}");
    }

    #[test]
    fn grid_is_open_on_its_rim() {
        let m = grid(3, 2, 1.0);
        let r = MeshReport::of(&m, StlFormat::Binary);
        assert_eq!(
            (r.triangles, r.open_edges, r.nonmanifold_edges),
            (12, 10, 0)
        );
    }
}
