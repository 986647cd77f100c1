//! Every warp in closed form, written from the README's warp table and the warp modules' doc
//! formulas (seed 000 Eqs. 1–2, seed 002 conic/belt/mandrel/sphere, CurviSlicer's blend),
//! never by calling the crate's `Warp`: the layer surface T_z, its gradient, the inverse of a
//! T-space point and det J. Only the job's parameters (plain data) are read from the crate.
//!
//! Model frame (the README): the STL moved so its XY bounding-box centre is at the origin and
//! its lowest point at z = 0. "Outward": T_z = z + g with g ≥ 0 growing away from the centre.

use glam::{DVec2, DVec3};
use warpslice::job::Job;
use warpslice::warp::{Direction, WarpSpec};

/// The shears' height function g(x, y) (T_z = z + w(z)·g).
#[derive(Clone, Copy, Debug)]
enum G {
    /// Seed 000 Eq. 1: g = s·c·(x + a)²/(w/2 + |a|); here k = s·c/(w/2 + |a|).
    Curved { k: f64, a: f64 },
    /// Seed 000 Eq. 2: g = s·c·|x + a|; here k = s·c.
    Tilted { k: f64, a: f64 },
    /// Seed 002 conic: g = ±r·tan α, r = |(x, y) − centre|; here k = ±tan α.
    Conic { k: f64, c: DVec2 },
    /// Seed 002 tilted planes: g = (d̂·(x, y))·tan α; here d = d̂·tan α.
    Belt { d: DVec2 },
    /// The matrix's typed field ([`super::acceptance::FIELD_RIPPLE_EXPR`]):
    /// g = a·sin(x/bx)·cos(y/by).
    Ripple { a: f64, bx: f64, by: f64 },
}

impl G {
    fn g(&self, x: f64, y: f64) -> f64 {
        match *self {
            G::Curved { k, a } => k * (x + a) * (x + a),
            G::Tilted { k, a } => k * (x + a).abs(),
            G::Conic { k, c } => k * (DVec2::new(x, y) - c).length(),
            G::Belt { d } => d.dot(DVec2::new(x, y)),
            G::Ripple { a, bx, by } => a * (x / bx).sin() * (y / by).cos(),
        }
    }
    /// ∇g; 0 at the tilted crease and the cone's axis (the tool axis is vertical there).
    fn grad(&self, x: f64, y: f64) -> DVec2 {
        match *self {
            G::Curved { k, a } => DVec2::new(2.0 * k * (x + a), 0.0),
            G::Tilted { k, a } => {
                let s = x + a;
                DVec2::new(if s == 0.0 { 0.0 } else { k * s.signum() }, 0.0)
            }
            G::Conic { k, c } => {
                let v = DVec2::new(x, y) - c;
                let r = v.length();
                if r == 0.0 {
                    DVec2::ZERO
                } else {
                    v * (k / r)
                }
            }
            G::Belt { d } => d,
            G::Ripple { a, bx, by } => DVec2::new(
                a / bx * (x / bx).cos() * (y / by).cos(),
                -a / by * (x / bx).sin() * (y / by).sin(),
            ),
        }
    }
}

/// CurviSlicer's planar-base blend (README): w = 0 below z0, 1 above z1, the smoothstep
/// 3t² − 2t³ of t = (z − z0)/(z1 − z0) between.
#[derive(Clone, Copy, Debug)]
struct Blend {
    z0: f64,
    z1: f64,
}

impl Blend {
    fn t(&self, z: f64) -> f64 {
        ((z - self.z0) / (self.z1 - self.z0)).clamp(0.0, 1.0)
    }
    fn w(&self, z: f64) -> f64 {
        let t = self.t(z);
        t * t * (3.0 - 2.0 * t)
    }
    /// dw/dz = 6t(1 − t)/(z1 − z0).
    fn dw(&self, z: f64) -> f64 {
        let t = self.t(z);
        6.0 * t * (1.0 - t) / (self.z1 - self.z0)
    }
}

#[derive(Clone, Copy, Debug)]
enum Kind {
    Shear {
        g: G,
        blend: Option<Blend>,
    },
    /// Coaxial cylinders about the axis ∥ X through (0, ay, az), first radius r.
    Cylindrical {
        r: f64,
        ay: f64,
        az: f64,
    },
    /// Concentric spheres about c, first radius r.
    Spherical {
        r: f64,
        c: DVec3,
    },
}

/// A job's warp in closed form.
#[derive(Clone, Copy, Debug)]
pub struct Closed {
    kind: Kind,
}

fn sign(d: Direction) -> f64 {
    match d {
        Direction::Outward => 1.0,
        Direction::Inward => -1.0,
    }
}

impl Closed {
    /// The closed form of `job.warp`.
    pub fn of(job: &Job) -> Result<Closed, String> {
        let blend = job.warp.base.map(|[z0, z1]| Blend { z0, z1 });
        let shear = |g| Kind::Shear { g, blend };
        let kind = match job.warp.spec {
            WarpSpec::Curved {
                strength,
                direction,
                offset,
                width,
            } => {
                if width <= 0.0 {
                    return Err("the job's curved warp has no width".into());
                }
                shear(G::Curved {
                    k: strength * sign(direction) / (width / 2.0 + offset.abs()),
                    a: offset,
                })
            }
            WarpSpec::Tilted {
                strength,
                direction,
                offset,
            } => shear(G::Tilted {
                k: strength * sign(direction),
                a: offset,
            }),
            WarpSpec::Conic {
                angle,
                direction,
                center,
            } => shear(G::Conic {
                k: sign(direction) * angle.to_radians().tan(),
                c: DVec2::from_array(center),
            }),
            WarpSpec::Belt { angle, toward } => shear(G::Belt {
                d: DVec2::from_array(toward).normalize() * angle.to_radians().tan(),
            }),
            WarpSpec::Cylindrical { radius, axis } => Kind::Cylindrical {
                r: radius,
                ay: axis[0],
                az: axis[1],
            },
            WarpSpec::Spherical { radius, center } => Kind::Spherical {
                r: radius,
                c: DVec3::from_array(center),
            },
            // the one typed field the matrix uses, its closed form written here
            WarpSpec::Field { ref expr, .. } if expr == super::acceptance::FIELD_RIPPLE_EXPR => {
                shear(G::Ripple {
                    a: 1.5,
                    bx: 6.0,
                    by: 8.0,
                })
            }
            ref other => return Err(format!("no closed form for the warp {other:?}")),
        };
        Ok(Closed { kind })
    }

    /// T_z(p): the layer height (T space) of a model-frame point, mm.
    pub fn tz(&self, p: DVec3) -> f64 {
        match self.kind {
            Kind::Shear { g, blend } => {
                let w = blend.map_or(1.0, |b| b.w(p.z));
                p.z + w * g.g(p.x, p.y)
            }
            Kind::Cylindrical { r, ay, az } => DVec2::new(p.y - ay, p.z - az).length() - r,
            Kind::Spherical { r, c } => (p - c).length() - r,
        }
    }

    /// ∇T_z(p).
    pub fn grad(&self, p: DVec3) -> DVec3 {
        match self.kind {
            Kind::Shear { g, blend } => {
                let (w, dw) = blend.map_or((1.0, 0.0), |b| (b.w(p.z), b.dw(p.z)));
                let h = g.grad(p.x, p.y) * w;
                DVec3::new(h.x, h.y, 1.0 + dw * g.g(p.x, p.y))
            }
            Kind::Cylindrical { ay, az, .. } => {
                DVec3::new(0.0, p.y - ay, p.z - az).normalize_or_zero()
            }
            Kind::Spherical { c, .. } => (p - c).normalize_or_zero(),
        }
    }

    /// The distance of p from the layer surface T_z = level, to first order: |T_z(p) − level| /
    /// |∇T_z(p)|, mm.
    pub fn distance_to_level(&self, p: DVec3, level: f64) -> f64 {
        let g = self.grad(p).length();
        (self.tz(p) - level).abs() / g.max(1e-12)
    }

    /// T⁻¹(q): the model-frame point of a T-space point.
    pub fn inverse(&self, q: DVec3) -> DVec3 {
        match self.kind {
            Kind::Shear { g, blend } => {
                let gv = g.g(q.x, q.y);
                let z = match blend {
                    None => q.z - gv,
                    // z + w(z)·g = q.z, increasing in z wherever the warp was accepted
                    // (1 + w′·g > 0): bisection on a bracket that holds the root.
                    Some(b) => {
                        let f = |z: f64| z + b.w(z) * gv - q.z;
                        let (mut lo, mut hi) = (q.z - gv.abs() - 1.0, q.z + gv.abs() + 1.0);
                        for _ in 0..200 {
                            let mid = 0.5 * (lo + hi);
                            if f(mid) > 0.0 {
                                hi = mid;
                            } else {
                                lo = mid;
                            }
                        }
                        0.5 * (lo + hi)
                    }
                };
                DVec3::new(q.x, q.y, z)
            }
            // (x, a_y + (z' + R) sin(y'/R), a_z + (z' + R) cos(y'/R))
            Kind::Cylindrical { r, ay, az } => {
                let (s, c) = (q.y / r).sin_cos();
                DVec3::new(q.x, ay + (q.z + r) * s, az + (q.z + r) * c)
            }
            // c + (z' + R)(sin φ cos λ, sin φ sin λ, cos φ), φ = |(x', y')|/R, λ = atan2(y', x')
            Kind::Spherical { r, c } => {
                let phi = DVec2::new(q.x, q.y).length() / r;
                let lam = q.y.atan2(q.x);
                c + (q.z + r) * DVec3::new(phi.sin() * lam.cos(), phi.sin() * lam.sin(), phi.cos())
            }
        }
    }

    /// det J of T at a model-frame point: 1 + w′(z)·g for the shears (x and y unchanged),
    /// R/ρ for the cylinders, R²φ/(ρ² sin φ) for the spheres (R²/ρ² on the top axis).
    pub fn det(&self, p: DVec3) -> f64 {
        match self.kind {
            Kind::Shear { g, blend } => 1.0 + blend.map_or(0.0, |b| b.dw(p.z) * g.g(p.x, p.y)),
            Kind::Cylindrical { r, ay, az } => r / DVec2::new(p.y - ay, p.z - az).length(),
            Kind::Spherical { r, c } => {
                let v = p - c;
                let rho = v.length();
                let s = DVec2::new(v.x, v.y).length();
                let phi = s.atan2(v.z);
                if phi < 1e-9 {
                    r * r / (rho * rho)
                } else {
                    r * r * phi / (rho * rho * phi.sin())
                }
            }
        }
    }
}
