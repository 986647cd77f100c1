//! The overhang measure of issue 15: which facets of a model a warp leaves overhanging.
//!
//! Definitions (the same in the CLI, wasm, web, docs and tests):
//! - the local build direction at a model-frame point p is the warp's tool axis
//!   n(p) = ∇T_z / |∇T_z| (planar: n = +z);
//! - a facet with outward unit normal m and centroid c is an **overhang** when
//!   m·n(c) < −cos θ (by more than [`AT_THE_ANGLE`], the rounding of a facet at exactly θ),
//!   θ the printable overhang angle (default [`DEFAULT_OVERHANG_ANGLE_DEG`]),
//!   unless it lies on the bed: all three vertices within [`BED_TOLERANCE_MM`] of z = 0;
//! - the **overhang area** of a warp is the summed area of its overhang facets, taken on the
//!   input mesh in the model frame (not the subdivided one);
//! - the **largest tilt** is the largest angle between n and +z over the facet centroids and
//!   the mesh vertices, degrees.
//!
//! Everything the measure needs of the mesh (centroids, unit normals, areas, the bed flag) is
//! computed once in [`Facets::new`]; a warp then costs one tool-axis evaluation per facet and
//! per vertex, so a search over hundreds of warps stays fast on a 225k-triangle model.

use glam::DVec3;
use serde::Serialize;

use crate::mesh::Mesh;
use crate::warp::Warp;

/// A facet lies on the bed (never an overhang) when all its vertices are within this height of
/// z = 0, mm (model frame): half a 0.1 mm first layer, so a bottom the STL writes at
/// z = 1e-6 still counts, and a face one layer up does not.
pub const BED_TOLERANCE_MM: f64 = 0.05;

/// A facet leaning exactly θ (m·n = −cos θ: a flat underside under a 45° cone at θ = 45°) is
/// printable; this bounds the rounding of m·n (a few 1e-16 from tan, cos and the
/// normalisations) so such a facet does not flip with the last bit.
pub const AT_THE_ANGLE: f64 = 1e-9;

/// The printable overhang angle θ used when none is given, degrees from the vertical: a
/// facet whose normal leans more than 45° below the layer plane (m·n < −cos 45°) overhangs.
pub const DEFAULT_OVERHANG_ANGLE_DEG: f64 = 45.0;

/// The mesh's facets, prepared once for many measures (model frame, mm).
#[derive(Clone, Debug, Default)]
pub struct Facets {
    /// Centroid of each facet (mean of its three vertices), mm.
    pub centroids: Vec<DVec3>,
    /// Outward unit normal of each facet ((b − a) × (c − a) normalised; zero when degenerate).
    pub normals: Vec<DVec3>,
    /// Area of each facet, mm².
    pub areas: Vec<f64>,
    /// Whether each facet lies on the bed (all vertices within [`BED_TOLERANCE_MM`] of z = 0).
    pub on_bed: Vec<bool>,
    /// The mesh's vertices (where the largest tilt is sampled besides the centroids), mm.
    pub vertices: Vec<DVec3>,
    /// The summed area of every facet, mm².
    pub surface_mm2: f64,
}

impl Facets {
    /// Prepare the facets of a model-frame mesh (its lowest point at z = 0).
    pub fn new(mesh: &Mesh) -> Facets {
        let n = mesh.triangles.len();
        let mut f = Facets {
            centroids: Vec::with_capacity(n),
            normals: Vec::with_capacity(n),
            areas: Vec::with_capacity(n),
            on_bed: Vec::with_capacity(n),
            vertices: mesh.vertices.clone(),
            surface_mm2: 0.0,
        };
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
            let cross = (b - a).cross(c - a);
            let len = cross.length();
            let area = 0.5 * len;
            f.centroids.push((a + b + c) / 3.0);
            f.normals
                .push(if len > 0.0 { cross / len } else { DVec3::ZERO });
            f.areas.push(area);
            f.on_bed.push(
                a.z.abs() <= BED_TOLERANCE_MM
                    && b.z.abs() <= BED_TOLERANCE_MM
                    && c.z.abs() <= BED_TOLERANCE_MM,
            );
            f.surface_mm2 += area;
        }
        f
    }

    /// The facets that can overhang under some tool axis tilted at most `max_tilt_deg` from +z
    /// (all others are left out, the vertices kept): a facet with m·n < −cos θ has
    /// ∠(m, −z) ≤ ∠(m, −n) + ∠(n, z) < θ + τ, so facets with ∠(m, −z) ≥ θ + τ never count.
    /// The area, percent and tilt of [`Facets::measure`] on the subset equal those on the whole
    /// (the surface is kept); the subset is ordered most downward (smallest m_z) first.
    pub fn that_can_overhang(&self, angle_deg: f64, max_tilt_deg: f64) -> Facets {
        let reach = crate::num::rad((angle_deg + max_tilt_deg).min(180.0));
        let cos_reach = crate::num::cos(reach);
        let mut f = Facets {
            vertices: self.vertices.clone(),
            surface_mm2: self.surface_mm2,
            ..Facets::default()
        };
        // most downward first: a search's cutoff ([`Facets::area_up_to`]) is passed soonest
        let mut order: Vec<usize> = (0..self.areas.len())
            // ∠(m, −z) < reach ⇔ −m_z > cos(reach)
            .filter(|&i| !self.on_bed[i] && self.areas[i] > 0.0 && -self.normals[i].z > cos_reach)
            .collect();
        order.sort_by(|&a, &b| {
            self.normals[a]
                .z
                .total_cmp(&self.normals[b].z)
                .then(a.cmp(&b))
        });
        for i in order {
            f.centroids.push(self.centroids[i]);
            f.normals.push(self.normals[i]);
            f.areas.push(self.areas[i]);
            f.on_bed.push(false);
        }
        f
    }

    /// Every `k`-th facet (k ≥ 1), its area multiplied by k: a stratified sample whose
    /// overhang area estimates the whole's (the surface and vertices are kept).
    pub fn every_kth(&self, k: usize) -> Facets {
        let k = k.max(1);
        let pick = |v: &Vec<_>| -> Vec<_> { v.iter().step_by(k).copied().collect() };
        Facets {
            centroids: pick(&self.centroids),
            normals: pick(&self.normals),
            areas: self.areas.iter().step_by(k).map(|a| a * k as f64).collect(),
            on_bed: self.on_bed.iter().step_by(k).copied().collect(),
            vertices: self.vertices.clone(),
            surface_mm2: self.surface_mm2,
        }
    }

    /// The overhang flag of every facet under `warp` (`None`: planar) and the printable
    /// angle θ = `angle_deg`.
    pub fn flags(&self, warp: Option<&dyn Warp>, angle_deg: f64) -> Vec<bool> {
        let limit = -crate::num::cos(crate::num::rad(angle_deg));
        (0..self.areas.len())
            .map(|i| self.overhangs(i, warp, limit))
            .collect()
    }

    /// Whether facet `i` overhangs under `warp`: m·n(c) < `limit` (= −cos θ) by more than
    /// [`AT_THE_ANGLE`], not on the bed.
    fn overhangs(&self, i: usize, warp: Option<&dyn Warp>, limit: f64) -> bool {
        !self.on_bed[i]
            && self.normals[i].dot(tool_axis(warp, self.centroids[i])) < limit - AT_THE_ANGLE
    }

    /// The overhang area (mm²) and the number of overhang facets under `warp` (`None`:
    /// planar) and the printable angle θ = `angle_deg`.
    pub fn area(&self, warp: Option<&dyn Warp>, angle_deg: f64) -> (f64, usize) {
        self.area_up_to(warp, angle_deg, f64::INFINITY)
            .unwrap_or((f64::INFINITY, 0))
    }

    /// [`Facets::area`], or `None` as soon as the area passes `cutoff` (mm²): a search that
    /// only needs to know whether a warp beats one it has stops there.
    pub fn area_up_to(
        &self,
        warp: Option<&dyn Warp>,
        angle_deg: f64,
        cutoff: f64,
    ) -> Option<(f64, usize)> {
        let limit = -crate::num::cos(crate::num::rad(angle_deg));
        let mut area = 0.0;
        let mut count = 0;
        for i in 0..self.areas.len() {
            if self.overhangs(i, warp, limit) {
                area += self.areas[i];
                count += 1;
                if area > cutoff {
                    return None;
                }
            }
        }
        Some((area, count))
    }

    /// The overhang area, its share of the surface and the largest tilt under `warp`
    /// (`None`: planar) and the printable angle θ = `angle_deg`.
    pub fn measure(&self, warp: Option<&dyn Warp>, angle_deg: f64) -> OverhangMeasure {
        let (area, count) = self.area(warp, angle_deg);
        OverhangMeasure {
            area_mm2: area,
            surface_mm2: self.surface_mm2,
            percent: if self.surface_mm2 > 0.0 {
                100.0 * area / self.surface_mm2
            } else {
                0.0
            },
            facets: count,
            largest_tilt_deg: warp.map_or(0.0, |w| self.largest_tilt_deg(w)),
        }
    }

    /// The largest tilt of `warp`'s tool axis from +z over the centroids and vertices,
    /// degrees.
    pub fn largest_tilt_deg(&self, warp: &dyn Warp) -> f64 {
        let min_cos = self
            .centroids
            .iter()
            .chain(&self.vertices)
            .map(|&p| warp.tool_axis(p).z)
            .fold(1.0_f64, f64::min);
        tilt_deg(min_cos)
    }

    /// The tilt of `warp`'s tool axis from +z at each facet's centroid (the point the overhang
    /// rule reads n at), degrees, facet order: the page's tilt map.
    pub fn tilts_deg(&self, warp: &dyn Warp) -> Vec<f64> {
        self.centroids
            .iter()
            .map(|&p| tilt_deg(warp.tool_axis(p).z))
            .collect()
    }
}

/// ∠(n, +z) = acos n_z of a unit n with z component `cos`, degrees.
fn tilt_deg(cos: f64) -> f64 {
    crate::num::deg(crate::num::acos(cos.clamp(-1.0, 1.0)))
}

fn tool_axis(warp: Option<&dyn Warp>, p: DVec3) -> DVec3 {
    warp.map_or(DVec3::Z, |w| w.tool_axis(p))
}

/// What [`Facets::measure`] finds.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct OverhangMeasure {
    /// Summed area of the overhang facets, mm².
    pub area_mm2: f64,
    /// Summed area of all facets, mm².
    pub surface_mm2: f64,
    /// `area_mm2` as a percentage of `surface_mm2`.
    pub percent: f64,
    /// How many facets overhang.
    pub facets: usize,
    /// The largest tilt of the tool axis from +z over the centroids and vertices, degrees
    /// (0 for planar).
    pub largest_tilt_deg: f64,
}

#[cfg(test)]
mod tests {
    //! Hand-made meshes with areas worked out by hand (the facet normals and tool axes below
    //! are written from the geometry and the seed formulas, not from the code under test).
    use super::*;
    use crate::mesh::Aabb;
    use crate::warp::{Direction, WarpParams, WarpSpec};

    /// Exact-area comparisons: sums of a few products of small decimals.
    const AREA_EPS: f64 = 1e-9;

    fn build(spec: WarpSpec, mesh: &Mesh) -> Box<dyn Warp> {
        let bbox: Aabb = mesh.bbox();
        WarpParams { spec, base: None }.build(&bbox).unwrap()
    }

    /// A quad a b c d (counter-clockwise seen from outside) as two triangles.
    fn quad(m: &mut Mesh, p: [[f64; 3]; 4]) {
        let base = m.vertices.len() as u32;
        m.vertices.extend(p.iter().map(|v| DVec3::from_array(*v)));
        m.triangles.push([base, base + 1, base + 2]);
        m.triangles.push([base, base + 2, base + 3]);
    }

    /// The T (mushroom) of [`crate::shapes::overhang_block`]: a pillar x ∈ [−12, −2],
    /// y ∈ [−7, 7], z ∈ [0, 20] under a slab x ∈ [−15, 15], y ∈ [−10, 10], z ∈ [20, 25].
    /// The slab's underside ring is 30·20 − 10·14 = 460 mm² facing −z.
    #[test]
    fn t_shape_planar_overhang_is_the_underside_of_the_bar() {
        let m = crate::shapes::overhang_block();
        let f = Facets::new(&m);
        let r = f.measure(None, 45.0);
        assert!((r.area_mm2 - 460.0).abs() < AREA_EPS, "{r:?}");
        // pillar sides 2·(10+14)·20, pillar bottom 140, slab top 600, slab sides 2·(30+20)·5, ring 460
        let surface = 960.0 + 140.0 + 600.0 + 500.0 + 460.0;
        assert!((r.surface_mm2 - surface).abs() < AREA_EPS);
        assert!((r.percent - 100.0 * 460.0 / surface).abs() < 1e-9);
        assert_eq!(r.largest_tilt_deg, 0.0);
    }

    /// Belt toward +x at α: n = (sin α, 0, cos α). The −z ring: m·n = −cos α; the −x faces
    /// (pillar 14·20 = 280, slab 20·5 = 100): m·n = −sin α. At α = 30° only the ring
    /// (−0.866 < −0.707); at α = 50° only the −x faces (−0.766), 380 mm².
    #[test]
    fn t_shape_under_a_belt_trades_the_underside_for_the_back_faces() {
        let m = crate::shapes::overhang_block();
        let f = Facets::new(&m);
        for (angle, want) in [(30.0, 460.0), (50.0, 380.0)] {
            let w = build(
                WarpSpec::Belt {
                    angle,
                    toward: [1.0, 0.0],
                },
                &m,
            );
            let r = f.measure(Some(w.as_ref()), 45.0);
            assert!((r.area_mm2 - want).abs() < AREA_EPS, "belt {angle}: {r:?}");
            assert!((r.largest_tilt_deg - angle).abs() < 1e-9);
            // the subset that can overhang at tilts up to the belt's gives the same answer
            let s = f.that_can_overhang(45.0, angle);
            assert!((s.measure(Some(w.as_ref()), 45.0).area_mm2 - want).abs() < AREA_EPS);
            if angle > 45.0 {
                // the faces left are those the layers fall away from: −x, not +x
                for (i, &on) in f.flags(Some(w.as_ref()), 45.0).iter().enumerate() {
                    assert_eq!(
                        on,
                        f.normals[i].x < -0.5,
                        "facet {i}, normal {}",
                        f.normals[i]
                    );
                }
            }
        }
    }

    /// Conic outward α about the axis: n = (sin α·r̂, cos α), so on a flat underside
    /// m·n = −cos α everywhere: the ring overhangs at 30° (−0.866) and not at 50° (−0.643);
    /// the side faces have m·n = sin α·(m·r̂) ≥ −sin α, never below −cos 45° at α = 30°.
    #[test]
    fn t_shape_under_a_cone_keeps_or_clears_the_flat_underside() {
        let m = crate::shapes::overhang_block();
        let f = Facets::new(&m);
        let cone = |angle| {
            build(
                WarpSpec::Conic {
                    angle,
                    direction: Direction::Outward,
                    center: [0.0, 0.0],
                },
                &m,
            )
        };
        let r30 = f.measure(Some(cone(30.0).as_ref()), 45.0);
        assert!((r30.area_mm2 - 460.0).abs() < AREA_EPS, "{r30:?}");
        let w50 = cone(50.0);
        let flags = f.flags(Some(w50.as_ref()), 45.0);
        for (i, &on) in flags.iter().enumerate() {
            if f.normals[i].z < -0.5 {
                assert!(!on, "facet {i} of the underside still overhangs at 50°");
            }
        }
    }

    /// A bridge: two pillars x ∈ [−15, −10] and [10, 15] (y ∈ [−5, 5], z ∈ [0, 10]) under a
    /// deck z ∈ [10, 13]; the deck's underside between them is 20·10 = 200 mm² facing −z.
    fn bridge() -> Mesh {
        let mut m = Mesh::default();
        // the span's underside, facing −z (clockwise seen from above)
        quad(
            &mut m,
            [
                [-10.0, -5.0, 10.0],
                [-10.0, 5.0, 10.0],
                [10.0, 5.0, 10.0],
                [10.0, -5.0, 10.0],
            ],
        );
        // deck top, facing +z
        quad(
            &mut m,
            [
                [-15.0, -5.0, 13.0],
                [15.0, -5.0, 13.0],
                [15.0, 5.0, 13.0],
                [-15.0, 5.0, 13.0],
            ],
        );
        for (x0, x1) in [(-15.0, -10.0), (10.0, 15.0)] {
            // pillar bottom on the bed, facing −z
            quad(
                &mut m,
                [
                    [x0, -5.0, 0.0],
                    [x0, 5.0, 0.0],
                    [x1, 5.0, 0.0],
                    [x1, -5.0, 0.0],
                ],
            );
            // outer (x0 = −15: −x) or inner (x0 = 10: −x) face at x = x0, facing −x
            quad(
                &mut m,
                [
                    [x0, -5.0, 0.0],
                    [x0, -5.0, 10.0],
                    [x0, 5.0, 10.0],
                    [x0, 5.0, 0.0],
                ],
            );
            // face at x = x1, facing +x
            quad(
                &mut m,
                [
                    [x1, -5.0, 0.0],
                    [x1, 5.0, 0.0],
                    [x1, 5.0, 10.0],
                    [x1, -5.0, 10.0],
                ],
            );
        }
        // deck ends, 10 × 3: x = −15 facing −x, x = 15 facing +x
        quad(
            &mut m,
            [
                [-15.0, -5.0, 10.0],
                [-15.0, -5.0, 13.0],
                [-15.0, 5.0, 13.0],
                [-15.0, 5.0, 10.0],
            ],
        );
        quad(
            &mut m,
            [
                [15.0, -5.0, 10.0],
                [15.0, 5.0, 10.0],
                [15.0, 5.0, 13.0],
                [15.0, -5.0, 13.0],
            ],
        );
        m
    }

    #[test]
    fn bridge_planar_overhang_is_the_span_and_not_the_feet_on_the_bed() {
        let m = bridge();
        let f = Facets::new(&m);
        let r = f.measure(None, 45.0);
        assert!((r.area_mm2 - 200.0).abs() < AREA_EPS, "{r:?}");
        assert_eq!(r.facets, 2);
        // at θ = 0 (nothing may lean out) the same: vertical walls have m·n = 0, not < −1
        assert!((f.measure(None, 0.0).area_mm2).abs() < AREA_EPS);
    }

    /// Tilted (seed 000 Eq. 2) s = 1.5, crease at x = 0: n = (±s·c, 0, 1)/√(1+s²) on x ≷ 0.
    /// The span: m·n = −1/√3.25 = −0.555, not an overhang. Outward (c = +1): the pillars' inner
    /// faces (x = −10 facing +x, x = 10 facing −x) get m·n = −1.5/√3.25 = −0.832: 2·100 mm².
    /// Inward (c = −1): the outer faces at x = ±15 instead, pillars 2·100 + deck ends 2·30.
    #[test]
    fn bridge_under_a_roof_warp_moves_the_overhang_to_the_faces_it_tilts_away_from() {
        let m = bridge();
        let f = Facets::new(&m);
        for (direction, want) in [(Direction::Outward, 200.0), (Direction::Inward, 260.0)] {
            let w = build(
                WarpSpec::Tilted {
                    strength: 1.5,
                    direction,
                    offset: 0.0,
                },
                &m,
            );
            let r = f.measure(Some(w.as_ref()), 45.0);
            assert!((r.area_mm2 - want).abs() < AREA_EPS, "{direction:?}: {r:?}");
            let flags = f.flags(Some(w.as_ref()), 45.0);
            assert!(!flags[0] && !flags[1], "the span overhangs under the roof");
        }
    }

    /// An upside-down cone: apex on the bed at the origin, rim of radius R = 20 at z = h = 10,
    /// `n` = 64 segments, a flat top. Facet i spans the angles 2π·i/n … 2π·(i+1)/n; its outward
    /// normal is (h·cos φᵢ, h·sin φᵢ, −R_c)/L at the mid angle φᵢ, with R_c = R·cos(π/n) and
    /// L = √(h² + R_c²) (the apex-to-chord-midpoint length), and its area ½·2R·sin(π/n)·L.
    fn upside_down_cone() -> (Mesh, f64, f64, f64, usize) {
        let (r, h, n) = (20.0, 10.0, 64usize);
        let mut m = Mesh {
            vertices: vec![DVec3::ZERO, DVec3::new(0.0, 0.0, h)],
            triangles: vec![],
        };
        for i in 0..n {
            let a = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
            m.vertices.push(DVec3::new(r * a.cos(), r * a.sin(), h));
        }
        for i in 0..n {
            let (a, b) = (2 + i as u32, 2 + ((i + 1) % n) as u32);
            m.triangles.push([0, b, a]); // lateral, facing outward and down
            m.triangles.push([1, a, b]); // top, facing +z
        }
        (m, r, h, std::f64::consts::PI / n as f64, n)
    }

    #[test]
    fn upside_down_cone_planar_overhang_is_the_whole_lateral_surface() {
        let (m, r, h, half, n) = upside_down_cone();
        let rc = r * half.cos();
        let l = (h * h + rc * rc).sqrt();
        let facet = r * half.sin() * l;
        // m_z = −R_c/L = −0.894 < −cos 45°: every lateral facet
        let f = Facets::new(&m);
        let got = f.measure(None, 45.0);
        assert!((got.area_mm2 - n as f64 * facet).abs() < 1e-9, "{got:?}");
        assert_eq!(got.facets, n);
    }

    /// Belt toward +x at 45° (n = (√½, 0, √½)) with θ = 45°: a lateral facet overhangs when
    /// (h·cos φ·√½ − R_c·√½)/L < −√½, i.e. cos φ < (R_c − L)/h = −0.2363, φ ∈ (103.67°, 256.33°):
    /// mid angles (i + ½)·5.625° for i = 18 … 45, 28 of the 64 facets.
    #[test]
    fn upside_down_cone_under_a_belt_keeps_the_fraction_facing_away() {
        let (m, r, h, half, _) = upside_down_cone();
        let rc = r * half.cos();
        let l = (h * h + rc * rc).sqrt();
        let facet = r * half.sin() * l;
        let w = build(
            WarpSpec::Belt {
                angle: 45.0,
                toward: [1.0, 0.0],
            },
            &m,
        );
        let f = Facets::new(&m);
        let got = f.measure(Some(w.as_ref()), 45.0);
        assert_eq!(got.facets, 28, "{got:?}");
        assert!((got.area_mm2 - 28.0 * facet).abs() < 1e-9);
    }

    /// Conic outward 45° about the apex: n = (√½·r̂, √½) and r̂ is the facet's mid direction,
    /// so m·n = (h − R_c)·√½/L = −0.316 > −√½: the cone's whole overhang is gone.
    #[test]
    fn upside_down_cone_under_its_own_cone_has_no_overhang() {
        let (m, ..) = upside_down_cone();
        let w = build(
            WarpSpec::Conic {
                angle: 45.0,
                direction: Direction::Outward,
                center: [0.0, 0.0],
            },
            &m,
        );
        let got = Facets::new(&m).measure(Some(w.as_ref()), 45.0);
        assert_eq!(got.facets, 0, "{got:?}");
        assert!((got.largest_tilt_deg - 45.0).abs() < 1e-9);
    }

    #[test]
    fn a_face_a_layer_above_the_bed_is_not_on_it() {
        let mut m = Mesh::default();
        let z = BED_TOLERANCE_MM * 2.0;
        quad(
            &mut m,
            [[0.0, 0.0, z], [0.0, 1.0, z], [1.0, 1.0, z], [1.0, 0.0, z]],
        );
        let f = Facets::new(&m);
        assert!((f.measure(None, 45.0).area_mm2 - 1.0).abs() < AREA_EPS);
        let z = BED_TOLERANCE_MM * 0.5;
        let mut m = Mesh::default();
        quad(
            &mut m,
            [[0.0, 0.0, z], [0.0, 1.0, z], [1.0, 1.0, z], [1.0, 0.0, z]],
        );
        assert_eq!(Facets::new(&m).measure(None, 45.0).area_mm2, 0.0);
    }
}
