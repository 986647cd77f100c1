//! Generated test parts (our own geometry, no licence strings attached): the meshes the tests,
//! the benchmark, the CLI demo and the web app's "try an example" use (built on
//! [`crate::mesh::shapes`]).

use glam::DVec3;

use crate::mesh::Mesh;

pub use crate::mesh::shapes::cuboid;

/// A cube of side `s` standing on z = 0, centred on the z axis.
pub fn cube(s: f64) -> Mesh {
    cuboid(
        DVec3::new(-s / 2.0, -s / 2.0, 0.0),
        DVec3::new(s / 2.0, s / 2.0, s),
    )
}

/// A closed cylinder of radius `r` and height `h` on z = 0, `n` sides.
pub fn cylinder(r: f64, h: f64, n: u32) -> Mesh {
    let n = n.max(3);
    let mut vertices = vec![DVec3::new(0.0, 0.0, 0.0), DVec3::new(0.0, 0.0, h)];
    for i in 0..n {
        let a = 2.0 * core::f64::consts::PI * i as f64 / n as f64;
        let (s, c) = (crate::num::sin(a), crate::num::cos(a));
        vertices.push(DVec3::new(r * c, r * s, 0.0));
        vertices.push(DVec3::new(r * c, r * s, h));
    }
    let mut triangles = Vec::new();
    for i in 0..n {
        let j = (i + 1) % n;
        let (b0, t0, b1, t1) = (2 + 2 * i, 3 + 2 * i, 2 + 2 * j, 3 + 2 * j);
        triangles.push([0, b1, b0]);
        triangles.push([1, t0, t1]);
        triangles.push([b0, b1, t1]);
        triangles.push([b0, t1, t0]);
    }
    Mesh {
        vertices,
        triangles,
    }
}

/// A UV sphere of radius `r` resting on z = 0.
pub fn sphere(r: f64, rings: u32, segments: u32) -> Mesh {
    crate::mesh::shapes::uv_sphere(DVec3::new(0.0, 0.0, r), r, rings, segments)
}

/// An overhang block: a 10 × 14 mm pillar 20 mm tall carrying a 30 × 20 × 5 mm slab that
/// overhangs it by 3 mm on three sides and 17 mm to +x (90° overhangs that conic and belt
/// warps make printable).
pub fn overhang_block() -> Mesh {
    let pillar = cuboid(DVec3::new(-12.0, -7.0, 0.0), DVec3::new(-2.0, 7.0, 20.0));
    let slab = cuboid(DVec3::new(-15.0, -10.0, 20.0), DVec3::new(15.0, 10.0, 25.0));
    union_stacked(&pillar, &slab)
}

/// The solid made of `lower` with `upper` standing on its top face, when upper's bottom face
/// strictly contains lower's top face (a T or mushroom shape). Built as one closed mesh: upper's bottom face
/// is replaced by the ring around lower's top face.
fn union_stacked(lower: &Mesh, upper: &Mesh) -> Mesh {
    let lb = lower.bbox();
    let ub = upper.bbox();
    let z = lb.max.z;
    let mut m = Mesh::default();
    let add = |p: DVec3, m: &mut Mesh| {
        m.vertices.push(p);
        (m.vertices.len() - 1) as u32
    };
    // lower: all faces but its top
    let lo = cuboid(lb.min, lb.max);
    let base = m.vertices.len() as u32;
    m.vertices.extend_from_slice(&lo.vertices);
    for t in &lo.triangles {
        if t.iter().all(|&i| lo.vertices[i as usize].z == z) {
            continue;
        }
        m.triangles.push([t[0] + base, t[1] + base, t[2] + base]);
    }
    // upper: all faces but its bottom
    let up = cuboid(ub.min, ub.max);
    let base = m.vertices.len() as u32;
    m.vertices.extend_from_slice(&up.vertices);
    for t in &up.triangles {
        if t.iter().all(|&i| up.vertices[i as usize].z == z) {
            continue;
        }
        m.triangles.push([t[0] + base, t[1] + base, t[2] + base]);
    }
    // ring between lower's top rectangle (inner) and upper's bottom rectangle (outer), facing down
    let inner = [
        DVec3::new(lb.min.x, lb.min.y, z),
        DVec3::new(lb.max.x, lb.min.y, z),
        DVec3::new(lb.max.x, lb.max.y, z),
        DVec3::new(lb.min.x, lb.max.y, z),
    ];
    let outer = [
        DVec3::new(ub.min.x, ub.min.y, z),
        DVec3::new(ub.max.x, ub.min.y, z),
        DVec3::new(ub.max.x, ub.max.y, z),
        DVec3::new(ub.min.x, ub.max.y, z),
    ];
    let ii: Vec<u32> = inner.iter().map(|&p| add(p, &mut m)).collect();
    let oo: Vec<u32> = outer.iter().map(|&p| add(p, &mut m)).collect();
    for k in 0..4 {
        let l = (k + 1) % 4;
        // facing down: clockwise seen from above
        m.triangles.push([oo[k], ii[k], ii[l]]);
        m.triangles.push([oo[k], ii[l], oo[l]]);
    }
    weld(&m)
}

/// Merge bit-identical vertices.
pub fn weld(m: &Mesh) -> Mesh {
    let mut map: std::collections::HashMap<[u64; 3], u32> = std::collections::HashMap::new();
    let mut out = Mesh::default();
    let mut remap = Vec::with_capacity(m.vertices.len());
    for v in &m.vertices {
        let key = [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
        let idx = *map.entry(key).or_insert_with(|| {
            out.vertices.push(*v);
            (out.vertices.len() - 1) as u32
        });
        remap.push(idx);
    }
    out.triangles = m
        .triangles
        .iter()
        .map(|t| t.map(|i| remap[i as usize]))
        .collect();
    out
}

/// The named example parts: `cube`, `cylinder`, `sphere`, `overhang`.
pub fn example(name: &str) -> Option<Mesh> {
    Some(match name {
        "cube" => cube(20.0),
        "cylinder" => cylinder(10.0, 20.0, 64),
        "sphere" => sphere(10.0, 24, 48),
        "overhang" => overhang_block(),
        _ => return None,
    })
}

/// Names accepted by [`example`].
pub const EXAMPLES: [&str; 4] = ["cube", "cylinder", "sphere", "overhang"];

#[cfg(test)]
mod tests {
    use super::*;

    fn edge_use(m: &Mesh) -> std::collections::HashMap<(u32, u32), i32> {
        let mut e = std::collections::HashMap::new();
        for t in &m.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *e.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        e
    }

    #[test]
    fn examples_are_closed_with_the_right_volume() {
        assert!((cube(20.0).signed_volume() - 8000.0).abs() < 1e-9);
        let cyl = cylinder(10.0, 20.0, 64);
        let poly = 0.5 * 64.0 * 100.0 * (2.0 * std::f64::consts::PI / 64.0).sin() * 20.0;
        assert!((cyl.signed_volume() - poly).abs() < 1e-6);
        assert!(
            sphere(10.0, 24, 48).signed_volume() > 0.95 * 4.0 / 3.0 * std::f64::consts::PI * 1000.0
        );
        assert!(
            (overhang_block().signed_volume() - (10.0 * 14.0 * 20.0 + 30.0 * 20.0 * 5.0)).abs()
                < 1e-9
        );
    }

    #[test]
    fn examples_are_closed_two_manifold() {
        for name in EXAMPLES {
            let m = example(name).unwrap();
            assert!(edge_use(&m).values().all(|&c| c == 2), "{name}");
        }
    }
}
