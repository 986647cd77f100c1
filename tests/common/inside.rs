//! How far a point lies outside a triangle mesh (0 inside), with a uniform grid so that the
//! real-slicer tests stay fast on 20k-triangle models.

use glam::{DVec2, DVec3};
use warpslice::mesh::Mesh;

pub struct Inside {
    tris: Vec<[DVec3; 3]>,
    origin: DVec3,
    cell: f64,
    dims: [usize; 3],
    cells: Vec<Vec<u32>>,
    /// XY columns for the parity ray.
    cols: Vec<Vec<u32>>,
    reach: f64,
}

fn closest_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    // Ericson, Real-Time Collision Detection §5.1.5
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

impl Inside {
    /// `reach`: the largest outside distance that needs to be measured exactly.
    pub fn new(m: &Mesh, reach: f64) -> Inside {
        let tris: Vec<[DVec3; 3]> = m
            .triangles
            .iter()
            .map(|t| t.map(|i| m.vertices[i as usize]))
            .collect();
        let bb = m.bbox();
        let size = bb.size().max_element().max(1e-3);
        let cell = (size / 64.0).max(reach).max(0.5);
        let origin = bb.min - DVec3::splat(reach + cell);
        let ext = bb.size() + DVec3::splat(2.0 * (reach + cell));
        let dims = [
            (ext.x / cell).ceil() as usize + 1,
            (ext.y / cell).ceil() as usize + 1,
            (ext.z / cell).ceil() as usize + 1,
        ];
        let mut cells = vec![Vec::new(); dims[0] * dims[1] * dims[2]];
        let mut cols = vec![Vec::new(); dims[0] * dims[1]];
        for (k, t) in tris.iter().enumerate() {
            let lo = t[0].min(t[1]).min(t[2]);
            let hi = t[0].max(t[1]).max(t[2]);
            let i0 = ((lo - origin) / cell).floor();
            let i1 = ((hi - origin) / cell).floor();
            for x in i0.x as usize..=i1.x as usize {
                for y in i0.y as usize..=i1.y as usize {
                    cols[y * dims[0] + x].push(k as u32);
                    for z in i0.z as usize..=i1.z as usize {
                        cells[(z * dims[1] + y) * dims[0] + x].push(k as u32);
                    }
                }
            }
        }
        Inside {
            tris,
            origin,
            cell,
            dims,
            cells,
            cols,
            reach,
        }
    }

    fn index(&self, p: DVec3) -> Option<[usize; 3]> {
        let c = ((p - self.origin) / self.cell).floor();
        (c.x >= 0.0
            && c.y >= 0.0
            && c.z >= 0.0
            && (c.x as usize) < self.dims[0]
            && (c.y as usize) < self.dims[1]
            && (c.z as usize) < self.dims[2])
            .then_some([c.x as usize, c.y as usize, c.z as usize])
    }

    /// Parity of crossings of the ray from p toward +z (x and y nudged off edges).
    fn inside(&self, p: DVec3) -> bool {
        let Some([x, y, _]) = self.index(p) else {
            return false;
        };
        let q = DVec2::new(p.x + 1.234e-7, p.y + 2.345e-7);
        let mut n = 0;
        for &k in &self.cols[y * self.dims[0] + x] {
            let [a, b, c] = self.tris[k as usize];
            let (a2, b2, c2) = (a.truncate(), b.truncate(), c.truncate());
            let d = (b2 - a2).perp_dot(c2 - a2);
            if d == 0.0 {
                continue;
            }
            let u = (b2 - q).perp_dot(c2 - q) / d;
            let v = (c2 - q).perp_dot(a2 - q) / d;
            let w = 1.0 - u - v;
            if u < 0.0 || v < 0.0 || w < 0.0 {
                continue;
            }
            let z = u * a.z + v * b.z + w * c.z;
            if z > p.z {
                n += 1;
            }
        }
        n % 2 == 1
    }

    /// 0 inside; else the distance to the surface, capped at a value > `reach` when further.
    pub fn outside_distance(&self, p: DVec3) -> f64 {
        if self.inside(p) {
            return 0.0;
        }
        let Some([x, y, z]) = self.index(p) else {
            return f64::INFINITY;
        };
        let r = (self.reach / self.cell).ceil() as usize + 1;
        let mut best = f64::INFINITY;
        for zz in z.saturating_sub(r)..=(z + r).min(self.dims[2] - 1) {
            for yy in y.saturating_sub(r)..=(y + r).min(self.dims[1] - 1) {
                for xx in x.saturating_sub(r)..=(x + r).min(self.dims[0] - 1) {
                    for &k in &self.cells[(zz * self.dims[1] + yy) * self.dims[0] + xx] {
                        let [a, b, c] = self.tris[k as usize];
                        best = best.min((closest_on_triangle(p, a, b, c) - p).length());
                    }
                }
            }
        }
        best
    }
}
