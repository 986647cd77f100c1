//! A machine's axes: each axis's letter, kind and travel ([`AxisLimit`]), and the machine's name
//! with its axes in output order ([`AxisSet`]), which every [`super::Machine`] holds and uses
//! for the checks all machines share: the input `(p, n)` of `inverse`, its output against the
//! travel, and the axis values given to `forward`.

use glam::DVec3;

use super::{MachineError, LIMIT_SLACK_DEG, POLE_EPSILON};

/// What [`super::Machine::inverse`] returns: axis values in output order (mm, degrees).
pub type InverseResult = Result<Vec<f64>, MachineError>;

/// `[min, max]` of an axis without travel limits (e.g. a rotary axis that is unwrapped).
pub const UNLIMITED: (f64, f64) = (f64::NEG_INFINITY, f64::INFINITY);

/// One axis: its letter, whether it is rotary (degrees) and its travel.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisLimit {
    /// The output letter (G-code word), e.g. `"X"`, `"B"`, `"U"`.
    pub name: String,
    /// Rotary axis (degrees) rather than linear (mm).
    pub rotary: bool,
    /// Lowest allowed value (mm or degrees; `-inf` when unlimited).
    pub min: f64,
    /// Highest allowed value.
    pub max: f64,
}

impl AxisLimit {
    /// A linear axis without travel limits.
    pub fn linear(name: &str) -> AxisLimit {
        AxisLimit {
            name: name.to_string(),
            rotary: false,
            min: f64::NEG_INFINITY,
            max: f64::INFINITY,
        }
    }
    /// A rotary axis limited to `[min, max]` degrees.
    pub fn rotary(name: &str, min: f64, max: f64) -> AxisLimit {
        AxisLimit {
            name: name.to_string(),
            rotary: true,
            min,
            max,
        }
    }
}

/// A machine's name (for messages) and its axes in output order.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisSet {
    name: String,
    limits: Vec<AxisLimit>,
}

impl AxisSet {
    /// The machine `name` with these axes.
    pub fn new(name: &str, limits: Vec<AxisLimit>) -> AxisSet {
        AxisSet {
            name: name.to_string(),
            limits,
        }
    }

    /// The machine `name` with unlimited linear axes lettered `names`.
    pub fn linear(name: &str, names: &[String]) -> AxisSet {
        AxisSet::linear_then_rotary(name, names, &[])
    }

    /// The machine `name` with axes lettered `names`: the last `rotary.len()` are rotary with
    /// these `[min, max]` (degrees), the ones before them linear and unlimited.
    pub fn linear_then_rotary(name: &str, names: &[String], rotary: &[(f64, f64)]) -> AxisSet {
        let k = names.len().saturating_sub(rotary.len());
        let linear = names[..k].iter().map(|n| AxisLimit::linear(n));
        let rotary = names[k..]
            .iter()
            .zip(rotary)
            .map(|(n, &(min, max))| AxisLimit::rotary(n, min, max));
        AxisSet::new(name, linear.chain(rotary).collect())
    }

    /// The machine name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The axes, in output order.
    pub fn limits(&self) -> &[AxisLimit] {
        &self.limits
    }

    /// Validate `(p, n)` given to `inverse` and return `n` normalised.
    pub fn check_input(&self, p: DVec3, n: DVec3) -> Result<DVec3, MachineError> {
        let len = n.length();
        if !(p.is_finite() && n.is_finite() && len > POLE_EPSILON) {
            return Err(MachineError::InvalidInput {
                machine: self.name.clone(),
                p,
                n,
            });
        }
        Ok(n / len)
    }

    /// `axes` (computed by `inverse` for tip `p`) when they are within the travel; the first
    /// violation is the error.
    pub fn check_limits(&self, axes: Vec<f64>, p: DVec3) -> InverseResult {
        check_limits(&self.name, &self.limits, &axes, p)?;
        Ok(axes)
    }

    /// Check the axis values given to `forward`: `expected` of them, all finite.
    pub fn check_count(&self, expected: usize, axes: &[f64]) -> Result<(), MachineError> {
        if axes.len() != expected {
            return Err(MachineError::WrongAxisCount {
                machine: self.name.clone(),
                expected,
                got: axes.len(),
            });
        }
        if axes.iter().any(|v| !v.is_finite()) {
            return Err(MachineError::InvalidAxes {
                machine: self.name.clone(),
                axes: axes.to_vec(),
            });
        }
        Ok(())
    }

    /// The machine cannot give tool axis `n` at `p`, because of `reason`.
    pub fn unreachable(&self, p: DVec3, n: DVec3, reason: String) -> MachineError {
        MachineError::UnreachableOrientation {
            machine: self.name.clone(),
            p,
            n,
            reason,
        }
    }
}

/// Check `axes` against `limits` (slack [`LIMIT_SLACK_DEG`] on rotary axes,
/// [`crate::tolerance::LENGTH_EPSILON`] on linear ones); the first violation is the error.
pub(crate) fn check_limits(
    machine: &str,
    limits: &[AxisLimit],
    axes: &[f64],
    p: DVec3,
) -> Result<(), MachineError> {
    for (l, &v) in limits.iter().zip(axes) {
        let slack = if l.rotary {
            LIMIT_SLACK_DEG
        } else {
            crate::tolerance::LENGTH_EPSILON
        };
        if !(v >= l.min - slack && v <= l.max + slack) {
            return Err(MachineError::AxisLimit {
                machine: machine.to_string(),
                axis: l.name.clone(),
                value: v,
                min: l.min,
                max: l.max,
                p,
            });
        }
    }
    Ok(())
}

/// `Ok` when `ok`, else the [`MachineError::BadSpec`] of machine `machine` saying `message`
/// (what the machine JSON must satisfy).
pub(crate) fn require(
    machine: &str,
    ok: bool,
    message: impl Into<String>,
) -> Result<(), MachineError> {
    if ok {
        Ok(())
    } else {
        Err(MachineError::BadSpec {
            machine: machine.to_string(),
            message: message.into(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn letters(s: &str) -> Vec<String> {
        s.chars().map(String::from).collect()
    }

    #[test]
    fn linear_then_rotary_puts_the_rotary_axes_last() {
        let set = AxisSet::linear_then_rotary("m", &letters("XYZAB"), &[UNLIMITED, (-90.0, 90.0)]);
        assert_eq!(set.name(), "m");
        let l = set.limits();
        assert_eq!(l.len(), 5);
        assert!(l[..3]
            .iter()
            .all(|a| !a.rotary && a.min == f64::NEG_INFINITY));
        assert_eq!(
            l[3],
            AxisLimit::rotary("A", f64::NEG_INFINITY, f64::INFINITY)
        );
        assert_eq!(l[4], AxisLimit::rotary("B", -90.0, 90.0));
    }

    #[test]
    fn too_few_letters_do_not_panic() {
        let set = AxisSet::linear_then_rotary("m", &letters("X"), &[(0.0, 1.0), (2.0, 3.0)]);
        assert_eq!(set.limits(), &[AxisLimit::rotary("X", 0.0, 1.0)]);
    }

    #[test]
    fn check_limits_returns_the_axes_or_the_first_violation() {
        let set = AxisSet::linear_then_rotary("m", &letters("XB"), &[(-10.0, 10.0)]);
        assert_eq!(
            set.check_limits(vec![5.0, 10.0], DVec3::ZERO),
            Ok(vec![5.0, 10.0])
        );
        match set.check_limits(vec![5.0, 11.0], DVec3::ZERO) {
            Err(MachineError::AxisLimit { axis, value, .. }) => {
                assert_eq!((axis.as_str(), value), ("B", 11.0));
            }
            other => panic!("expected an axis limit error, got {other:?}"),
        }
    }

    #[test]
    fn check_input_normalises_and_refuses_zero_axes() {
        let set = AxisSet::linear("m", &letters("XYZ"));
        assert_eq!(
            set.check_input(DVec3::ONE, DVec3::new(0.0, 0.0, 2.0)),
            Ok(DVec3::Z)
        );
        assert!(matches!(
            set.check_input(DVec3::ONE, DVec3::ZERO),
            Err(MachineError::InvalidInput { .. })
        ));
    }

    #[test]
    fn require_names_the_machine() {
        assert_eq!(require("m", true, "unused"), Ok(()));
        let e = require("m", false, "x must be positive").unwrap_err();
        assert_eq!(
            e.to_string(),
            "machine m: x must be positive; fix the machine JSON"
        );
    }
}
