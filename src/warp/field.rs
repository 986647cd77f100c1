//! The typed field warp (issue 15 item 3b): T_z = z + w(z)·g(x, y) with g an expression of x
//! and y the user types (`--warp field --expr "2*sin(x/5)*cos(y/7)"`), or the B-spline
//! `suggest` fits (`--grid`, [`super::spline`]).
//!
//! x and y are mm in the **model frame** (the STL moved so the centre of its XY bounding box is
//! at the origin), like the other warps' centres and offsets, and g is in mm. The warp is the
//! same z-shear as the seed warps ([`super::Shear`]), so it takes `--base` and obeys the same
//! laws.
//!
//! **The expression crate: `exmex`.** Of the pure-Rust expression crates that build for wasm32,
//! `evalexpr` is AGPL (this crate is MIT/Apache), `meval` and `fasteval` are unmaintained
//! since 2017/2020 and have no derivatives; `exmex` (MIT/Apache, maintained) parses to a flat
//! expression that evaluates without allocation and gives **symbolic partial derivatives**, so
//! ∇g is exact wherever its operators are differentiable (+ − · / ^, sqrt, exp, ln, the
//! trigonometric and hyperbolic functions and their inverses).
//!
//! **∇g for the rest** (`abs`, `min`, `max`, `signum`, …, which exmex cannot differentiate):
//! central differences ∂g/∂x ≈ (g(x+h) − g(x−h))/2h with h = [`NUMERIC_STEP_MM`]. Their error
//! is at most h²/6·|g‴| (truncation) + ε·|g|/h (rounding): for |g| ≤ 10³ mm and |g‴| ≤ 1 /mm²
//! that is ≤ 2·10⁻¹³ + 2·10⁻⁷, below the law test's 10⁻⁶ ([`super::laws::FD_TOLERANCE`]). On a
//! kink (|x| at 0) the central difference is the mean of the one-sided slopes, the same rule
//! as the tilted warp's crease.
//!
//! **Checked over the footprint** ([`check_over`]): g and ∇g must be finite and |∇g| at most
//! tan [`MAX_FIELD_TILT_DEG`] at every point of a grid over the model's XY box, else the warp is
//! refused with the point and the value.

use exmex::prelude::*;
use glam::DVec2;

use super::{Height, WarpError};
use crate::mesh::Aabb;
use crate::schema::{Param, ParamType, WarpInfo};

/// The step of the central differences used for ∂g/∂x, ∂g/∂y when exmex cannot differentiate
/// the expression, mm (the bound it gives: see the module documentation).
pub const NUMERIC_STEP_MM: f64 = 1e-6;

/// The steepest layer a field may make, degrees from horizontal: |∇g| ≤ tan 80° ≈ 5.7 (layers
/// steeper than this are ≤ cos 80° ≈ 0.17 of the layer height thick along the tool axis, and
/// no preset tilts this far).
pub const MAX_FIELD_TILT_DEG: f64 = 80.0;

/// Samples per side of the footprint grid [`check_over`] evaluates g and ∇g on (65 × 65 points,
/// corners included).
pub const CHECK_SAMPLES: usize = 64;

/// The variables an expression may use.
pub const VARIABLES: [&str; 2] = ["x", "y"];

/// How one partial derivative is computed.
#[derive(Clone)]
enum Partial {
    /// g does not depend on the variable.
    Zero,
    /// exmex's symbolic derivative.
    Exact(Box<FlatEx<f64>>),
    /// Central differences with [`NUMERIC_STEP_MM`].
    Numeric,
}

/// g(x, y) given as text.
#[derive(Clone)]
pub struct Expression {
    g: FlatEx<f64>,
    /// Where x and y go in exmex's variable slice (alphabetical order of the names used).
    slot: [Option<usize>; 2],
    partial: [Partial; 2],
}

/// Longest expression accepted, characters (a page's text box; a formula a teacher types is a
/// line, not a page).
pub const MAX_EXPRESSION_LEN: usize = 1000;
/// Deepest nesting of parentheses accepted: the parser and its symbolic derivatives recurse
/// once per level (in a debug wasm build a few levels of `sin(x/5)*cos(y/7)` already take
/// more than wasm's default 1 MiB stack).
pub const MAX_EXPRESSION_DEPTH: usize = 32;

impl Expression {
    /// Parse `text` as g(x, y): refuses text that does not parse and names other than x and y.
    pub fn parse(text: &str) -> Result<Expression, WarpError> {
        let unparsable = |message: String| WarpError::ExpressionUnparsable {
            expr: text.to_string(),
            message,
        };
        // the parser and its derivatives recurse with the nesting: bounded before parsing, so
        // that no typed text can exhaust the stack (wasm's is 8 MiB, .cargo/config.toml)
        if text.len() > MAX_EXPRESSION_LEN {
            return Err(unparsable(format!(
                "{} characters, at most {MAX_EXPRESSION_LEN}",
                text.len()
            )));
        }
        let depth = text
            .chars()
            .scan(0i64, |d, c| {
                *d += match c {
                    '(' => 1,
                    ')' => -1,
                    _ => 0,
                };
                Some(*d)
            })
            .max()
            .unwrap_or(0);
        if depth > MAX_EXPRESSION_DEPTH as i64 {
            return Err(unparsable(format!(
                "parentheses nested {depth} deep, at most {MAX_EXPRESSION_DEPTH}"
            )));
        }
        let g = exmex::parse::<f64>(text).map_err(|e| WarpError::ExpressionUnparsable {
            expr: text.to_string(),
            message: e.to_string(),
        })?;
        if let Some(name) = g
            .var_names()
            .iter()
            .find(|n| !VARIABLES.contains(&n.as_str()))
        {
            return Err(WarpError::ExpressionUnknownVariable {
                expr: text.to_string(),
                name: name.clone(),
            });
        }
        let slot = VARIABLES.map(|v| g.var_names().iter().position(|n| n == v));
        let partial = slot.map(|s| match s {
            None => Partial::Zero,
            Some(i) => g
                .clone()
                .partial(i)
                .map_or(Partial::Numeric, |d| Partial::Exact(Box::new(d))),
        });
        Ok(Expression { g, slot, partial })
    }

    /// Evaluate `e` (g or a partial, which take the same variables) at (x, y); NaN if exmex
    /// fails (it does not for a parsed expression given its own variables).
    fn eval(&self, e: &FlatEx<f64>, x: f64, y: f64) -> f64 {
        let mut vars = [0.0; 2];
        let mut n = 0;
        for (s, v) in self.slot.iter().zip([x, y]) {
            if s.is_some() {
                vars[n] = v;
                n += 1;
            }
        }
        e.eval(&vars[..n]).unwrap_or(f64::NAN)
    }

    /// Whether ∂g/∂x and ∂g/∂y are both exact (symbolic or zero).
    pub fn exact_gradient(&self) -> bool {
        !self.partial.iter().any(|p| matches!(p, Partial::Numeric))
    }
}

/// The expression as typed (exmex's own Debug lists every node).
impl std::fmt::Debug for Expression {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Expression({:?})", self.g.unparse())
    }
}

impl Height for Expression {
    fn into_shear(self: Box<Self>, blend: Option<super::BaseBlend>) -> Box<dyn super::Warp> {
        Box::new(super::Shear::new(self, blend))
    }

    fn g(&self, x: f64, y: f64) -> f64 {
        self.eval(&self.g, x, y)
    }
    fn grad(&self, x: f64, y: f64) -> DVec2 {
        let h = NUMERIC_STEP_MM;
        let d = |k: usize| match &self.partial[k] {
            Partial::Zero => 0.0,
            Partial::Exact(e) => self.eval(e, x, y),
            Partial::Numeric if k == 0 => (self.g(x + h, y) - self.g(x - h, y)) / (2.0 * h),
            Partial::Numeric => (self.g(x, y + h) - self.g(x, y - h)) / (2.0 * h),
        };
        DVec2::new(d(0), d(1))
    }
}

/// Check a field height over the model's XY box: g and ∇g finite and |∇g| ≤ tan
/// [`MAX_FIELD_TILT_DEG`] at every point of a ([`CHECK_SAMPLES`] + 1)² grid, corners included.
/// `expr` names the field in the errors (the expression, or `grid`).
pub fn check_over(height: &dyn Height, bbox: &Aabb, expr: &str) -> Result<(), WarpError> {
    let limit = crate::num::tan(crate::num::rad(MAX_FIELD_TILT_DEG));
    let n = CHECK_SAMPLES;
    for i in 0..=n {
        for j in 0..=n {
            let x = bbox.min.x + (bbox.max.x - bbox.min.x) * (i as f64 / n as f64);
            let y = bbox.min.y + (bbox.max.y - bbox.min.y) * (j as f64 / n as f64);
            let g = height.g(x, y);
            let d = height.grad(x, y);
            for (what, v) in [("g", g), ("∂g/∂x", d.x), ("∂g/∂y", d.y)] {
                if !v.is_finite() {
                    return Err(WarpError::FieldNotFinite {
                        expr: expr.to_string(),
                        what,
                        at: [x, y],
                        value: v,
                    });
                }
            }
            let slope = d.length();
            if slope > limit {
                return Err(WarpError::FieldTooSteep {
                    expr: expr.to_string(),
                    at: [x, y],
                    slope,
                    limit,
                });
            }
        }
    }
    Ok(())
}

/// `--expr`: the field's g(x, y).
pub const EXPR: Param = Param::number("expr", "--expr", "g(x, y)")
    .of(ParamType::Text)
    .unit("mm")
    .help(
        "the layers' height over the bed as an expression of x and y (mm, model frame: the centre \
         of the model's XY box at 0,0), e.g. 2*sin(x/5)*cos(y/7) or 0.01*(x^2+y^2)",
    );

/// `--grid`: the fitted field's B-spline ([`super::spline`]), as `suggest` writes it.
pub const GRID: Param = Param::number("grid", "--grid", "B-spline grid")
    .of(ParamType::Text)
    .optional()
    .help(
        "instead of --expr: a bicubic B-spline height x0,y0,dx,dy,nx,ny:c00,c10,… (knots and \
         coefficients in mm, x fastest), as `suggest` fits it",
    );

/// `--over`: the family warp the field is added to ([`super::over`]).
pub const OVER: Param = Param::number("over", "--over", "Over family warp")
    .of(ParamType::Text)
    .optional()
    .help(
        "add the field to a family warp (g = g_family + g_field), written kind:name=value:…, \
         e.g. conic:angle=30:direction=outward:center=0,0, as `suggest` writes its fit",
    );

/// What the field warp says of itself ([`crate::describe`]).
pub const INFO: WarpInfo = WarpInfo {
    name: "field",
    title: "Field (typed height g(x, y))",
    help: "any smooth height field over the footprint, typed as an expression of x and y; the tool tilts along ∇g",
    formula: "T_z = z + g(x, y)",
    seed: "issue 15",
    base: true,
    params: &[EXPR, GRID, OVER],
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn symbolic_gradient_of_a_paraboloid_and_variables_in_either_order() {
        // g = 0.01·(x² + 2y²): ∇g = (0.02x, 0.04y)
        let e = Expression::parse("0.01*(y^2*2 + x^2)").unwrap();
        assert!(e.exact_gradient());
        assert!((e.g(3.0, -2.0) - 0.01 * (9.0 + 8.0)).abs() < 1e-15);
        let d = e.grad(3.0, -2.0);
        assert!(
            (d.x - 0.06).abs() < 1e-15 && (d.y + 0.08).abs() < 1e-15,
            "{d}"
        );
        // only y used: x's partial is zero, y goes in the first slot
        let e = Expression::parse("3*y").unwrap();
        assert_eq!(e.g(100.0, 2.0), 6.0);
        assert_eq!(e.grad(100.0, 2.0), DVec2::new(0.0, 3.0));
    }

    #[test]
    fn abs_falls_back_to_central_differences() {
        let e = Expression::parse("0.5*abs(x - 1)").unwrap();
        assert!(!e.exact_gradient());
        assert!((e.grad(4.0, 0.0).x - 0.5).abs() < 1e-8);
        assert!((e.grad(-4.0, 0.0).x + 0.5).abs() < 1e-8);
        // on the kink: the mean of the one-sided slopes
        assert!(e.grad(1.0, 0.0).x.abs() < 1e-8);
    }

    #[test]
    fn bad_expressions_get_named_errors() {
        assert!(matches!(
            Expression::parse("sin(x"),
            Err(WarpError::ExpressionUnparsable { .. })
        ));
        match Expression::parse("x + z*2") {
            Err(WarpError::ExpressionUnknownVariable { name, .. }) => assert_eq!(name, "z"),
            other => panic!("{other:?}"),
        }
    }
}
