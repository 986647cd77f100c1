//! An independent check of issue 15's admissibility, written from the README's warp table
//! (T_z of each family, the base blend's smoothstep), the preset JSON and the seeds — not from
//! the crate's warp, tool-axis or machine code:
//!
//! - the warp is read back from its **flags** (the string `warpslice warp` takes), and T_z is
//!   evaluated from the README formulas;
//! - the tool axis is ∇T_z/|∇T_z| by central differences of T_z (step [`FD_STEP`]);
//! - the tilt limit is the preset's own number (`max_tilt_deg`; the B head's clip
//!   b₀ + (90° − b₀)·min(z/z_clip, 1) of seed 000 §4.3.1 and its XZ plane; the rotating
//!   nozzle's fixed `tilt_deg`);
//! - monotonicity is ∂T_z/∂z > 0 by central differences at every sample (x, y) at its own z
//!   and at the middle of the blend, where w′ peaks;
//! - the anchor rule (README "The anchor"): the anchor slab, the convex hull of the part's
//!   footprint, can be put under the part (it has an area: it holds the quadrilateral of the
//!   footprint's extreme points), or the warped first layer covers 25 mm².

use glam::DVec3;
use warpslice::mesh::Mesh;

/// Central-difference step of T_z, mm.
pub const FD_STEP: f64 = 1e-5;
/// Slack on the tilt limits, degrees: finite differences of T_z (error ~1e-9) and the rounding
/// of the written flags.
pub const TILT_SLACK_DEG: f64 = 1e-4;
/// A machine that realises the tool axis in a plane or at a fixed angle may miss it by this
/// much, degrees (the pipeline's dropped-tilt warning threshold, docs).
pub const REALISE_SLACK_DEG: f64 = 1.0;
/// The anchor rule's least first-layer area, mm² (README "The anchor").
pub const MIN_FIRST_LAYER_MM2: f64 = 25.0;

/// The fitted field's g at (x, y) from its `--grid` text `x0,y0,dx,dy,nx,ny:c…` (x fastest):
/// the uniform cubic B-spline in its segment form — in the cell k = ⌊u⌋, t = u − k of
/// u = (x − x0)/dx, the weights of coefficients k−1 … k+2 are (1−t)³/6, (3t³ − 6t² + 4)/6,
/// (−3t³ + 3t² + 3t + 1)/6, t³/6 (the same in y); coefficients outside the grid count 0.
pub fn uniform_bspline(grid: &str, x: f64, y: f64) -> f64 {
    let (head, body) = grid.split_once(':').expect("grid head:coefficients");
    let h: Vec<f64> = head.split(',').map(|v| v.parse().unwrap()).collect();
    let c: Vec<f64> = body.split(',').map(|v| v.parse().unwrap()).collect();
    let (nx, ny) = (h[4] as i64, h[5] as i64);
    assert_eq!(c.len() as i64, nx * ny, "coefficients");
    let weights = |t: f64| {
        [
            (1.0 - t).powi(3) / 6.0,
            (3.0 * t.powi(3) - 6.0 * t * t + 4.0) / 6.0,
            (-3.0 * t.powi(3) + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
            t.powi(3) / 6.0,
        ]
    };
    let (u, v) = ((x - h[0]) / h[2], (y - h[1]) / h[3]);
    let (ku, kv) = (u.floor(), v.floor());
    let (wu, wv) = (weights(u - ku), weights(v - kv));
    let mut g = 0.0;
    for (b, wy) in wv.iter().enumerate() {
        let j = kv as i64 - 1 + b as i64;
        for (a, wx) in wu.iter().enumerate() {
            let i = ku as i64 - 1 + a as i64;
            if (0..nx).contains(&i) && (0..ny).contains(&j) {
                g += c[(j * nx + i) as usize] * wx * wy;
            }
        }
    }
    g
}

/// T_z of a warp given by its flags, model frame (README's table).
pub struct Tz {
    kind: String,
    /// The fitted field's `--grid` text (README: `x0,y0,dx,dy,nx,ny:c00,c10,…`).
    grid: Option<String>,
    /// The field's family part (`--over kind:name=value:…`, README), read as its own flags.
    over: Option<Box<Tz>>,
    num: std::collections::HashMap<String, Vec<f64>>,
    outward: bool,
    base: Option<[f64; 2]>,
    width: f64,
}

impl Tz {
    /// Read `--warp K --param v …` for a model of width `width` in x (mm).
    pub fn from_flags(flags: &str, width: f64) -> Tz {
        let words: Vec<&str> = flags.split_whitespace().collect();
        let mut t = Tz {
            kind: String::new(),
            grid: None,
            over: None,
            num: Default::default(),
            outward: true,
            base: None,
            width,
        };
        for pair in words.chunks(2) {
            let (k, v) = (pair[0].trim_start_matches("--"), pair[1]);
            match k {
                "warp" => t.kind = v.to_string(),
                "direction" => t.outward = v == "outward",
                "grid" => t.grid = Some(v.to_string()),
                // `conic:angle=30:direction=outward:center=0,0` → `--warp conic --angle 30 …`
                "over" => {
                    let mut parts = v.split(':');
                    let mut f = format!("--warp {}", parts.next().unwrap());
                    for p in parts {
                        let (name, value) = p.split_once('=').expect("over: name=value");
                        f.push_str(&format!(" --{name} {value}"));
                    }
                    t.over = Some(Box::new(Tz::from_flags(&f, width)));
                }
                _ => {
                    let vals: Vec<f64> = v.split(',').map(|x| x.parse().unwrap()).collect();
                    if k == "base" {
                        t.base = Some([vals[0], vals[1]]);
                    } else {
                        t.num.insert(k.to_string(), vals);
                    }
                }
            }
        }
        t
    }

    fn n(&self, k: &str) -> Vec<f64> {
        self.num
            .get(k)
            .cloned()
            .unwrap_or_else(|| panic!("{k} missing"))
    }

    /// g(x, y), mm: the field's family part (`--over`) plus its own.
    pub fn g(&self, x: f64, y: f64) -> f64 {
        self.over.as_ref().map_or(0.0, |o| o.g(x, y)) + self.own_g(x, y)
    }

    /// g(x, y) without the family part, mm.
    fn own_g(&self, x: f64, y: f64) -> f64 {
        let c = if self.outward { 1.0 } else { -1.0 };
        match self.kind.as_str() {
            "curved" => {
                let (s, a) = (self.n("strength")[0], self.n("offset")[0]);
                // the README's w: the model's width, or the one written with the warp
                let w = self.num.get("width").map_or(self.width, |v| v[0]);
                s * c * (x + a).powi(2) / (w / 2.0 + a.abs())
            }
            "tilted" => {
                let (s, a) = (self.n("strength")[0], self.n("offset")[0]);
                s * c * (x + a).abs()
            }
            "conic" => {
                let (al, ce) = (self.n("angle")[0], self.n("center"));
                c * ((x - ce[0]).powi(2) + (y - ce[1]).powi(2)).sqrt() * al.to_radians().tan()
            }
            "belt" => {
                let (al, d) = (self.n("angle")[0], self.n("toward"));
                let l = (d[0] * d[0] + d[1] * d[1]).sqrt();
                (d[0] * x + d[1] * y) / l * al.to_radians().tan()
            }
            "field" => uniform_bspline(self.grid.as_deref().expect("--grid"), x, y),
            k => panic!("not a family: {k}"),
        }
    }

    /// w(z): 0 below z0, 1 above z1, smoothstep between (no base: 1).
    pub fn w(&self, z: f64) -> f64 {
        match self.base {
            None => 1.0,
            Some([z0, z1]) => {
                let t = ((z - z0) / (z1 - z0)).clamp(0.0, 1.0);
                t * t * (3.0 - 2.0 * t)
            }
        }
    }

    /// T_z(p).
    pub fn tz(&self, p: DVec3) -> f64 {
        p.z + self.w(p.z) * self.g(p.x, p.y)
    }

    /// ∇T_z by central differences.
    pub fn grad(&self, p: DVec3) -> DVec3 {
        let d = |e: DVec3| (self.tz(p + e * FD_STEP) - self.tz(p - e * FD_STEP)) / (2.0 * FD_STEP);
        DVec3::new(d(DVec3::X), d(DVec3::Y), d(DVec3::Z))
    }

    /// The tool axis ∇T_z/|∇T_z|.
    pub fn axis(&self, p: DVec3) -> DVec3 {
        self.grad(p).normalize()
    }

    /// Whether p lies within two FD steps of a kink of g (the conic apex, the crease) or of
    /// an end of the base blend, where the differences straddle it.
    pub fn near_kink(&self, p: DVec3) -> bool {
        // w″ jumps at the blend's ends: central differences in z err by O(h·g) there
        if let Some([z0, z1]) = self.base {
            if (p.z - z0).abs() < 2.0 * FD_STEP || (p.z - z1).abs() < 2.0 * FD_STEP {
                return true;
            }
        }
        if self.over.as_ref().is_some_and(|o| o.near_kink(p)) {
            return true;
        }
        match self.kind.as_str() {
            "conic" => {
                let ce = self.n("center");
                ((p.x - ce[0]).powi(2) + (p.y - ce[1]).powi(2)).sqrt() < 2.0 * FD_STEP
            }
            "tilted" => (p.x + self.n("offset")[0]).abs() < 2.0 * FD_STEP,
            _ => false,
        }
    }
}

/// A preset's tilt rules, read from its JSON text.
pub struct Limits {
    /// `max_tilt_deg` (or the A/B table's `a_limit_deg`, the B head's `b_limit_deg`).
    pub max_tilt_deg: Option<f64>,
    /// The B head: (b₀, z_clip) of its collision clip, and its XZ plane.
    pub b_head_clip: Option<(f64, f64)>,
    /// The rotating nozzle's fixed tilt.
    pub fixed_tilt_deg: Option<f64>,
}

impl Limits {
    /// From a preset's JSON.
    pub fn of_preset(json: &str) -> Limits {
        let v: serde_json::Value = serde_json::from_str(json).unwrap();
        let f = |k: &str| v.get(k).and_then(|x| x.as_f64());
        match v["kind"].as_str().unwrap() {
            "b-head" => Limits {
                max_tilt_deg: f("b_limit_deg"),
                b_head_clip: (v["clip"].as_bool() == Some(true))
                    .then(|| (f("clip_b0_deg").unwrap(), f("clip_z_mm").unwrap())),
                fixed_tilt_deg: None,
            },
            "rtn" => Limits {
                max_tilt_deg: f("tilt_deg"),
                b_head_clip: None,
                fixed_tilt_deg: f("tilt_deg"),
            },
            "ab-table" => Limits {
                max_tilt_deg: f("a_limit_deg"),
                b_head_clip: None,
                fixed_tilt_deg: None,
            },
            _ => Limits {
                max_tilt_deg: f("max_tilt_deg"),
                b_head_clip: None,
                fixed_tilt_deg: None,
            },
        }
    }
}

/// Why `flags` is not admissible on `limits` for `mesh` (model frame), or `Ok(largest tilt)`.
pub fn check(flags: &str, mesh: &Mesh, limits: &Limits, layer_height: f64) -> Result<f64, String> {
    let bb = mesh.bbox();
    let t = Tz::from_flags(flags, bb.size().x);
    let mut samples: Vec<DVec3> = mesh.vertices.clone();
    for tri in &mesh.triangles {
        let [a, b, c] = tri.map(|i| mesh.vertices[i as usize]);
        samples.push((a + b + c) / 3.0);
    }
    let mut largest: f64 = 0.0;
    for &p in &samples {
        // monotonic: ∂T_z/∂z > 0 here and at the blend's steepest height
        let mut heights = vec![p.z];
        if let Some([z0, z1]) = t.base {
            heights.push(0.5 * (z0 + z1));
        }
        for z in heights {
            let q = DVec3::new(p.x, p.y, z);
            let dz = t.grad(q).z;
            if dz.is_nan() || dz <= 0.0 {
                return Err(format!("{flags}: ∂T_z/∂z = {dz} ≤ 0 at {q}"));
            }
        }
        if t.near_kink(p) {
            continue;
        }
        let n = t.axis(p);
        let tilt = n.z.clamp(-1.0, 1.0).acos().to_degrees();
        largest = largest.max(tilt);
        if let Some(max) = limits.max_tilt_deg {
            if tilt > max + TILT_SLACK_DEG {
                return Err(format!("{flags}: tilt {tilt}° > {max}° at {p}"));
            }
        }
        if let Some((b0, zc)) = limits.b_head_clip {
            let clip = b0 + (90.0 - b0) * (p.z.max(0.0) / zc).min(1.0);
            if tilt > clip + REALISE_SLACK_DEG {
                return Err(format!(
                    "{flags}: tilt {tilt}° > the B head's clip {clip}° at {p}"
                ));
            }
            let off_plane = n.y.abs().asin().to_degrees();
            if off_plane > REALISE_SLACK_DEG {
                return Err(format!(
                    "{flags}: the axis leaves the B head's XZ plane by {off_plane}° at {p}"
                ));
            }
        }
        if let Some(fixed) = limits.fixed_tilt_deg {
            let exact_vertical = t.base.is_none() && tilt < 1e-6;
            if !exact_vertical && (tilt - fixed).abs() > REALISE_SLACK_DEG {
                return Err(format!(
                    "{flags}: tilt {tilt}° on a nozzle fixed at {fixed}° at {p}"
                ));
            }
        }
    }
    // the anchor rule: the slab under the part is its footprint's convex hull, which holds
    // the quadrilateral of the footprint's extreme points (leftmost, lowest, rightmost,
    // highest, in that order around it)
    let pick = |key: &dyn Fn(&DVec3) -> f64, most: bool| -> DVec3 {
        *mesh
            .vertices
            .iter()
            .max_by(|a, b| {
                let o = key(a).total_cmp(&key(b));
                if most {
                    o
                } else {
                    o.reverse()
                }
            })
            .unwrap()
    };
    let quad = [
        pick(&|p| p.x, false),
        pick(&|p| p.y, false),
        pick(&|p| p.x, true),
        pick(&|p| p.y, true),
    ];
    let footprint: f64 = 0.5
        * (0..4)
            .map(|i| {
                let (a, b) = (quad[i], quad[(i + 1) % 4]);
                a.x * b.y - b.x * a.y
            })
            .sum::<f64>()
            .abs();
    if footprint.is_nan() || footprint <= 0.0 {
        let w: Vec<DVec3> = mesh
            .vertices
            .iter()
            .map(|&p| DVec3::new(p.x, p.y, t.tz(p)))
            .collect();
        let zmin = w.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
        let first: f64 = mesh
            .triangles
            .iter()
            .map(|tri| tri.map(|i| w[i as usize]))
            .filter(|v| v.iter().all(|p| p.z <= zmin + 0.5 * layer_height))
            .map(|[a, b, c]| 0.5 * ((b - a).x * (c - a).y - (b - a).y * (c - a).x).abs())
            .sum();
        if first < MIN_FIRST_LAYER_MM2 {
            return Err(format!(
                "{flags}: footprint {footprint} mm² and warped first layer {first} mm² < {MIN_FIRST_LAYER_MM2}"
            ));
        }
    }
    Ok(largest)
}

/// The overhang area of `mesh` under `flags` by finite-difference tool axes: facets with
/// m·n(c) < −cos θ, not on the bed. Returns (area, area of facets within 1e-6 of the
/// threshold, where finite differences may decide either way).
pub fn overhang_area(flags: &str, mesh: &Mesh, theta_deg: f64) -> (f64, f64) {
    let t = Tz::from_flags(flags, mesh.bbox().size().x);
    let limit = -theta_deg.to_radians().cos();
    let (mut area, mut borderline) = (0.0, 0.0);
    for tri in &mesh.triangles {
        let [a, b, c] = tri.map(|i| mesh.vertices[i as usize]);
        if [a, b, c].iter().all(|p| p.z.abs() <= 0.05) {
            continue;
        }
        let cr = (b - a).cross(c - a);
        if cr.length() == 0.0 {
            continue;
        }
        let m = cr.normalize();
        let centroid = (a + b + c) / 3.0;
        let d = m.dot(t.axis(centroid)) - limit;
        let s = 0.5 * cr.length();
        if d < 0.0 {
            area += s;
        }
        if d.abs() < 1e-6 || t.near_kink(centroid) {
            borderline += s;
        }
    }
    (area, borderline)
}
