//! What a machine file says of each axis beyond its kinematics: the travel of the linear axes
//! (JSON `"travel": {"X": [min, max], …}`) and the largest feed of every axis (JSON
//! `"max_feed": {"X": 12000, "B": 3600, …}`), resolved per axis in the machine's axis order
//! ([`AxisBounds`]).
//!
//! ## Units and frame
//! Machine coordinates, the values the emitter writes: linear axes in mm, rotary axes in
//! degrees; feeds in mm/min (linear) and °/min (rotary). For the triple-Z bed the Z axes'
//! travel is of the motor heights.
//!
//! ## Defaults
//! Both keys are optional and so is every axis in them: an axis without a travel is unlimited
//! (as every linear axis was before `travel` existed), an axis without a largest feed is never
//! slowed. The presets give both for every axis, with their sources in docs/machines.md.
//!
//! ## What a rotary axis' range is
//! A rotary axis' range belongs to its kinematics (`b_limit_deg`, `a_limit_deg`,
//! `rotation_range_deg`, …): `travel` refuses a rotary letter rather than keep two values of
//! one limit. A linear axis the kinematics already limits (the polar machine's radius) keeps
//! the narrower of the two ranges.

use std::collections::BTreeMap;

use super::{AxisLimit, MachineError};

/// One axis as the output checks see it.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisBounds {
    /// The output letter.
    pub name: String,
    /// Rotary axis (degrees) rather than linear (mm).
    pub rotary: bool,
    /// Lowest allowed raw value, mm or degrees (`-inf`: unlimited).
    pub min: f64,
    /// Highest allowed raw value, mm or degrees (`+inf`: unlimited).
    pub max: f64,
    /// Largest feed, mm/min or °/min (`+inf`: no limit).
    pub max_feed: f64,
}

/// Join the kinematic `limits` of machine `machine` with the file's `travel` and `max_feed`;
/// an entry naming no axis, a travel of a rotary axis, `min ≥ max`, a non-finite bound or a
/// feed that is not a positive number is a [`MachineError::BadSpec`] saying which.
pub fn resolve(
    machine: &str,
    limits: &[AxisLimit],
    travel: Option<&BTreeMap<String, [f64; 2]>>,
    max_feed: Option<&BTreeMap<String, f64>>,
) -> Result<Vec<AxisBounds>, MachineError> {
    let bad = |message: String| MachineError::BadSpec {
        machine: machine.to_string(),
        message,
    };
    let letters = || {
        limits
            .iter()
            .map(|l| l.name.as_str())
            .collect::<Vec<_>>()
            .join(" ")
    };
    let find = |key: &str, what: &str| {
        limits.iter().position(|l| l.name == key).ok_or_else(|| {
            bad(format!(
                "{what} names axis '{key}', which this machine does not have (its axes: {})",
                letters()
            ))
        })
    };
    let mut out: Vec<AxisBounds> = limits
        .iter()
        .map(|l| AxisBounds {
            name: l.name.clone(),
            rotary: l.rotary,
            min: l.min,
            max: l.max,
            max_feed: f64::INFINITY,
        })
        .collect();
    for (key, &[lo, hi]) in travel.into_iter().flatten() {
        let i = find(key, "travel")?;
        if limits[i].rotary {
            return Err(bad(format!(
                "travel names the rotary axis '{key}': travel is for linear axes, a rotary axis' range is a parameter of the machine's kind"
            )));
        }
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return Err(bad(format!(
                "travel of axis '{key}' is [{lo}, {hi}]: it must be two finite numbers [min, max] with min < max (mm)"
            )));
        }
        out[i].min = out[i].min.max(lo);
        out[i].max = out[i].max.min(hi);
    }
    for (key, &f) in max_feed.into_iter().flatten() {
        let i = find(key, "max_feed")?;
        if !(f.is_finite() && f > 0.0) {
            return Err(bad(format!(
                "max_feed of axis '{key}' is {f}: it must be a positive number ({}/min)",
                if limits[i].rotary { "°" } else { "mm" }
            )));
        }
        out[i].max_feed = f;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limits() -> Vec<AxisLimit> {
        vec![
            AxisLimit::linear("X"),
            AxisLimit {
                name: "Z".into(),
                rotary: false,
                min: f64::NEG_INFINITY,
                max: 150.0,
            },
            AxisLimit::rotary("B", -90.0, 90.0),
        ]
    }

    #[test]
    fn travel_and_feeds_join_the_kinematic_limits_and_keep_the_narrower_range() {
        let travel = BTreeMap::from([("X".to_string(), [0.0, 230.0]), ("Z".into(), [-2.0, 210.0])]);
        let feed = BTreeMap::from([("B".to_string(), 3600.0)]);
        let b = resolve("m", &limits(), Some(&travel), Some(&feed)).unwrap();
        assert_eq!(
            (b[0].min, b[0].max, b[0].max_feed),
            (0.0, 230.0, f64::INFINITY)
        );
        assert_eq!((b[1].min, b[1].max), (-2.0, 150.0));
        assert_eq!((b[2].min, b[2].max, b[2].max_feed), (-90.0, 90.0, 3600.0));
        let none = resolve("m", &limits(), None, None).unwrap();
        assert_eq!(none[0].min, f64::NEG_INFINITY);
    }

    type Travel = Option<BTreeMap<String, [f64; 2]>>;
    type Feeds = Option<BTreeMap<String, f64>>;

    #[test]
    fn bad_entries_are_refused_by_name() {
        let cases: [(Travel, Feeds, &str); 5] = [
            (
                Some(BTreeMap::from([("Q".into(), [0.0, 1.0])])),
                None,
                "names axis 'Q'",
            ),
            (
                Some(BTreeMap::from([("B".into(), [0.0, 1.0])])),
                None,
                "rotary axis 'B'",
            ),
            (
                Some(BTreeMap::from([("X".into(), [5.0, 1.0])])),
                None,
                "min < max",
            ),
            (
                None,
                Some(BTreeMap::from([("X".into(), 0.0)])),
                "positive number (mm/min)",
            ),
            (
                None,
                Some(BTreeMap::from([("B".into(), f64::NAN)])),
                "positive number (°/min)",
            ),
        ];
        for (t, f, want) in cases {
            let e = resolve("m", &limits(), t.as_ref(), f.as_ref()).unwrap_err();
            assert!(e.to_string().contains(want), "{e} lacks {want}");
            assert!(matches!(e, MachineError::BadSpec { .. }));
        }
    }
}
