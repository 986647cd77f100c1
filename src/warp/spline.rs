//! The fitted field's height (issue 15 item 3a): a uniform bicubic B-spline over the footprint,
//!
//! g(x, y) = Σᵢ Σⱼ c[i, j] · B((x − x0)/dx − i) · B((y − y0)/dy − j),  0 ≤ i < nx, 0 ≤ j < ny,
//!
//! with B the centred cubic B-spline (support [−2, 2]):
//! B(t) = 2/3 − t² + |t|³/2 for |t| < 1, (2 − |t|)³/6 for 1 ≤ |t| < 2, 0 beyond. g is C² (its
//! gradient and tool axis are continuous), ∇g is the same sum with B′ in one factor (divided by
//! dx or dy), and where all four neighbours' coefficients are given (1 ≤ (x − x0)/dx ≤ nx − 2)
//! the bases sum to 1, so constant coefficients give a constant g. `suggest` lays the grid so
//! that the model's XY box is inside that range ([`Spline::over`]).
//!
//! **As text** (the job's `grid` and the `--grid` flag; no spaces, so a suggestion's flags are
//! one shell word each): `x0,y0,dx,dy,nx,ny:c00,c10,…` — the first knot's (x, y) and the knot
//! spacing (mm, model frame), the counts, then the nx·ny coefficients (mm), x fastest.

use glam::DVec2;

use super::{Height, WarpError};
use crate::mesh::Aabb;

/// The fewest knots per side (one cell with its three neighbouring bases).
pub const MIN_KNOTS: usize = 4;
/// The most coefficients a grid may hold (a 64 × 64 grid; `suggest` uses far fewer).
pub const MAX_COEFFICIENTS: usize = 4096;

/// A uniform bicubic B-spline height, mm.
#[derive(Clone, Debug, PartialEq)]
pub struct Spline {
    /// (x, y) of knot (0, 0), model frame, mm.
    pub origin: [f64; 2],
    /// Knot spacing in x and y, mm (> 0).
    pub step: [f64; 2],
    /// Knots in x and y.
    pub size: [usize; 2],
    /// nx·ny coefficients, mm, x fastest.
    pub c: Vec<f64>,
}

/// B(t), the centred cubic B-spline.
fn basis(t: f64) -> f64 {
    let a = t.abs();
    if a < 1.0 {
        2.0 / 3.0 - a * a + 0.5 * a * a * a
    } else if a < 2.0 {
        let u = 2.0 - a;
        u * u * u / 6.0
    } else {
        0.0
    }
}

/// B′(t).
fn basis_slope(t: f64) -> f64 {
    let a = t.abs();
    let s = t.signum();
    if a < 1.0 {
        s * (-2.0 * a + 1.5 * a * a)
    } else if a < 2.0 {
        let u = 2.0 - a;
        -s * 0.5 * u * u
    } else {
        0.0
    }
}

impl Spline {
    /// A grid of `cells` × `cells`-ish cells over `bbox`'s XY (the longer side gets `cells`
    /// cells, the shorter as many of the same size as cover it, at least one), every
    /// coefficient 0: knot i at x0 + i·dx with x0 = min.x − dx, so the box spans the bases'
    /// full range 1 ≤ u ≤ nx − 2.
    pub fn over(bbox: &Aabb, cells: usize) -> Spline {
        let s = bbox.size();
        let h = (s.x.max(s.y) / cells.max(1) as f64).max(1e-3);
        let n = |w: f64| ((w / h).ceil() as usize).max(1) + 3;
        let size = [n(s.x), n(s.y)];
        // centre the grid on the box
        let origin = [
            0.5 * (bbox.min.x + bbox.max.x) - 0.5 * (size[0] - 1) as f64 * h,
            0.5 * (bbox.min.y + bbox.max.y) - 0.5 * (size[1] - 1) as f64 * h,
        ];
        Spline {
            origin,
            step: [h, h],
            size,
            c: vec![0.0; size[0] * size[1]],
        }
    }

    /// (x, y) of knot (i, j), mm.
    pub fn knot(&self, i: usize, j: usize) -> [f64; 2] {
        [
            self.origin[0] + i as f64 * self.step[0],
            self.origin[1] + j as f64 * self.step[1],
        ]
    }

    /// The grid as text (coefficients to 0.001 mm: the text is the warp, so a spline is
    /// rounded with [`Spline::rounded`] before it is measured).
    pub fn to_text(&self) -> String {
        let f = crate::num::fmt_shortest;
        let mut s = format!(
            "{},{},{},{},{},{}:",
            f(self.origin[0]),
            f(self.origin[1]),
            f(self.step[0]),
            f(self.step[1]),
            self.size[0],
            self.size[1]
        );
        let cs: Vec<String> = self.c.iter().map(|&v| f(v)).collect();
        s.push_str(&cs.join(","));
        s
    }

    /// The same spline with the origin, step and coefficients rounded to 0.001 mm (what its
    /// text holds).
    pub fn rounded(&self) -> Spline {
        let r = |v: f64| {
            let x = (v * 1000.0).round() / 1000.0;
            if x == 0.0 {
                0.0
            } else {
                x
            }
        };
        Spline {
            origin: self.origin.map(r),
            step: self.step.map(r),
            size: self.size,
            c: self.c.iter().map(|&v| r(v)).collect(),
        }
    }

    /// Read the text form; names what is wrong.
    pub fn parse(text: &str) -> Result<Spline, WarpError> {
        let bad = |why: &str| WarpError::BadParameter {
            name: "grid",
            value: if text.chars().count() > 60 {
                format!("{}…", text.chars().take(60).collect::<String>())
            } else {
                text.to_string()
            },
            allowed: format!(
                "x0,y0,dx,dy,nx,ny:c00,c10,… (knot origin and spacing in mm, dx, dy > 0, \
                 {MIN_KNOTS} ≤ nx, ny, nx·ny ≤ {MAX_COEFFICIENTS} finite coefficients in mm): {why}"
            ),
        };
        let (head, body) = text
            .split_once(':')
            .ok_or_else(|| bad("no ':' before the coefficients"))?;
        let h: Vec<&str> = head.split(',').map(str::trim).collect();
        if h.len() != 6 {
            return Err(bad("the head needs six numbers"));
        }
        let num = |s: &str| -> Result<f64, WarpError> {
            s.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(&format!("'{s}' is not a finite number")))
        };
        let count = |s: &str| -> Result<usize, WarpError> {
            s.parse::<usize>()
                .ok()
                .filter(|&n| n >= MIN_KNOTS)
                .ok_or_else(|| bad(&format!("'{s}' is not a knot count ≥ {MIN_KNOTS}")))
        };
        let origin = [num(h[0])?, num(h[1])?];
        let step = [num(h[2])?, num(h[3])?];
        if !(step[0] > 0.0 && step[1] > 0.0) {
            return Err(bad("the spacing must be > 0"));
        }
        let size = [count(h[4])?, count(h[5])?];
        if size[0].saturating_mul(size[1]) > MAX_COEFFICIENTS {
            return Err(bad("too many coefficients"));
        }
        let c = body
            .split(',')
            .map(|s| num(s.trim()))
            .collect::<Result<Vec<f64>, _>>()?;
        if c.len() != size[0] * size[1] {
            return Err(bad(&format!(
                "{} coefficients for {} × {} knots",
                c.len(),
                size[0],
                size[1]
            )));
        }
        Ok(Spline {
            origin,
            step,
            size,
            c,
        })
    }

    /// Σ c·Bx·By with `fx`, `fy` the factors in x and y (B or B′), over the ≤ 4 × 4 knots
    /// whose bases are non-zero at (x, y).
    fn sum(&self, x: f64, y: f64, fx: fn(f64) -> f64, fy: fn(f64) -> f64) -> f64 {
        let u = (x - self.origin[0]) / self.step[0];
        let v = (y - self.origin[1]) / self.step[1];
        let range = |t: f64, n: usize| {
            let lo = (t.floor() - 1.0).max(0.0);
            let hi = (t.floor() + 2.0).min(n as f64 - 1.0);
            (lo, hi)
        };
        let (ilo, ihi) = range(u, self.size[0]);
        let (jlo, jhi) = range(v, self.size[1]);
        if !(ilo <= ihi && jlo <= jhi) {
            return 0.0;
        }
        let mut total = 0.0;
        for j in jlo as usize..=jhi as usize {
            let by = fy(v - j as f64);
            if by == 0.0 {
                continue;
            }
            let row = &self.c[j * self.size[0]..(j + 1) * self.size[0]];
            let mut acc = 0.0;
            for (i, c) in row
                .iter()
                .enumerate()
                .take(ihi as usize + 1)
                .skip(ilo as usize)
            {
                acc += c * fx(u - i as f64);
            }
            total += acc * by;
        }
        total
    }
}

impl Height for Spline {
    fn into_shear(self: Box<Self>, blend: Option<super::BaseBlend>) -> Box<dyn super::Warp> {
        Box::new(super::Shear::new(self, blend))
    }

    fn g(&self, x: f64, y: f64) -> f64 {
        self.sum(x, y, basis, basis)
    }
    fn grad(&self, x: f64, y: f64) -> DVec2 {
        DVec2::new(
            self.sum(x, y, basis_slope, basis) / self.step[0],
            self.sum(x, y, basis, basis_slope) / self.step[1],
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn bbox() -> Aabb {
        Aabb {
            min: DVec3::new(-10.0, -6.0, 0.0),
            max: DVec3::new(10.0, 6.0, 10.0),
        }
    }

    #[test]
    fn constant_and_linear_coefficients_give_a_constant_and_a_plane_over_the_box() {
        // B-splines reproduce linear functions: c = a + b·x_i gives g = a + b·x inside
        let mut s = Spline::over(&bbox(), 5);
        for j in 0..s.size[1] {
            for i in 0..s.size[0] {
                let [x, y] = s.knot(i, j);
                s.c[j * s.size[0] + i] = 1.5 + 0.2 * x - 0.1 * y;
            }
        }
        for (x, y) in [(-10.0, -6.0), (3.3, 1.7), (10.0, 6.0), (0.0, 0.0)] {
            assert!(
                (s.g(x, y) - (1.5 + 0.2 * x - 0.1 * y)).abs() < 1e-12,
                "{x},{y}"
            );
            let d = s.grad(x, y);
            assert!((d - DVec2::new(0.2, -0.1)).length() < 1e-12, "{d}");
        }
    }

    #[test]
    fn text_round_trips_and_bad_text_is_named() {
        let mut s = Spline::over(&bbox(), 4);
        s.c[5] = 0.25;
        let s = s.rounded();
        assert_eq!(Spline::parse(&s.to_text()).unwrap(), s);
        for bad in ["1,2,3", "0,0,1,1,4,4:1,2", "0,0,0,1,4,4:", "0,0,1,1,2,4:0"] {
            let e = Spline::parse(bad).unwrap_err();
            assert!(e.to_string().contains("grid"), "{e}");
        }
    }
}
