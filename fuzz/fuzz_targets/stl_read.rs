//! Fuzz the STL reader: any bytes must give a mesh or a named error, never a panic; a mesh
//! that loads must be consistent with its report, survive a write/read round trip and a
//! subdivision pass.
#![no_main]

use libfuzzer_sys::fuzz_target;
use warpslice::mesh::{read_stl, subdivide, write_stl, MeshReport, SubdivideOptions};

fuzz_target!(|data: &[u8]| {
    let Ok((mesh, report)) = read_stl(data) else {
        return;
    };
    assert_eq!(report.triangles, mesh.triangles.len());
    assert_eq!(report.vertices, mesh.vertices.len());
    assert!(mesh
        .triangles
        .iter()
        .flatten()
        .all(|&i| (i as usize) < mesh.vertices.len()));
    assert!(mesh.vertices.iter().all(|v| v.is_finite()));
    // Written back as binary and read again: the same mesh (coordinates were f32 already and
    // vertices are numbered in order of first use, so the round trip is exact).
    let (again, _) = read_stl(&write_stl(&mesh, "fuzz")).expect("own output must read back");
    assert_eq!(again, mesh);
    // A small mesh is subdivided to a quarter of its size (a few passes) and must stay
    // consistent and as closed as it was.
    let diag = report.bbox.size().length();
    if mesh.triangles.len() <= 64 && diag.is_finite() && diag > 0.0 {
        let opts = SubdivideOptions {
            max_edge: diag / 4.0,
            tolerance: diag,
        };
        let (sub, stats) = subdivide(&mesh, &opts, &|p| p);
        assert_eq!(stats.triangles_after, sub.triangles.len());
        assert!(stats.limit_hit.is_none());
        let rs = MeshReport::of(&sub, report.format);
        // (a triangle given twice is "closed" by edge counts, yet both copies own the inner
        // edges of their subdivisions: those are then used four times)
        let mut sets: Vec<[u32; 3]> = mesh
            .triangles
            .iter()
            .map(|t| {
                let mut k = *t;
                k.sort_unstable();
                k
            })
            .collect();
        sets.sort_unstable();
        let doubled = sets.windows(2).any(|w| w[0] == w[1]);
        let repeated = mesh
            .triangles
            .iter()
            .any(|t| t[0] == t[1] || t[1] == t[2] || t[2] == t[0]);
        // triangles that use a vertex twice are dropped by subdivide, which changes the counts
        if !repeated {
            assert!(rs.open_edges >= report.open_edges);
        }
        if report.open_edges == 0 && report.nonmanifold_edges == 0 && !doubled && !repeated {
            assert_eq!((rs.open_edges, rs.nonmanifold_edges), (0, 0));
        }
    }
});
