//! Axis speeds: how long the firmware takes for each written move, and whether an axis would
//! exceed its largest feed ([`super::travel::AxisBounds::max_feed`]).
//!
//! ## The firmware's duration at the written F (minutes)
//! With `Δᵢ` the change of axis i, `L_lin = √(Σ_linear Δᵢ²)`, `L_all = √(Σ_all Δᵢ²)` (degrees
//! counted as mm) and F the feed in force (the written one, else the modal one):
//! - [`FeedMode::Xyz`]: the firmware counts only the linear axes (rotary `S1`):
//!   `T = L_lin / F`, or `L_all / F` for a pure rotation (`L_lin = 0`);
//! - [`FeedMode::AllAxes`]: `T = L_all / F`;
//! - [`FeedMode::InverseTime`] (`G93`): `T = 1 / F`.
//!
//! A move of the extruder alone (a retraction) takes `|ΔE| / F`, or `1 / F` in inverse time.
//!
//! ## The slow-down
//! Axis i moves at `vᵢ = |Δᵢ| / T`. When `k = maxᵢ vᵢ / max_feedᵢ > 1` the firmware scales the
//! whole move so the fastest axis is at its limit (RepRapFirmware and Marlin limit each axis'
//! speed this way, seed 001 §4.8 for the triple-Z bed's 1900 mm/min Z axes): the move takes
//! `k·T`, and it is counted as limited (by the axis of largest ratio). Acceleration is not
//! modelled: the estimate is of the feed-rate-limited time.
//!
//! In `tip` mode the feed rule itself lowers F so the fastest axis runs at its limit
//! ([`super::feed`]): the emitter counts those moves here ([`AxisSpeeds::add_slowed`]), and the
//! firmware has nothing left to slow.

use super::feed::FeedMode;

/// A move is limited when some axis' speed exceeds its largest feed by more than this
/// fraction (the written F and axes are rounded; a move computed exactly at the limit is not).
pub const SPEED_SLACK: f64 = 1e-9;

/// The firmware's duration (minutes) of a move from `from` to `to` (raw axes; `rotary` per
/// axis) at feed `f`, in feed mode `mode` (see the module documentation); in `tip` mode the
/// firmware's own move length `firmware_length` (the flavour's length rule,
/// [`super::length_rule`]) over F. Zero when F is not a positive number or nothing moves.
pub fn move_minutes(
    mode: FeedMode,
    rotary: &[bool],
    from: &[f64],
    to: &[f64],
    f: f64,
    firmware_length: f64,
) -> f64 {
    if !(f.is_finite() && f > 0.0) {
        return 0.0;
    }
    let (mut lin, mut all) = (0.0, 0.0);
    for ((a, b), &r) in from.iter().zip(to).zip(rotary) {
        let d2 = (b - a) * (b - a);
        all += d2;
        if !r {
            lin += d2;
        }
    }
    match mode {
        FeedMode::InverseTime if all > 0.0 => 1.0 / f,
        FeedMode::InverseTime => 0.0,
        FeedMode::Xyz if lin > 0.0 => lin.sqrt() / f,
        FeedMode::Xyz | FeedMode::AllAxes => all.sqrt() / f,
        FeedMode::Tip => firmware_length / f,
    }
}

/// A move an axis' largest feed slows: the axis (machine order), its speed at the written F
/// (mm/min or °/min, `|Δᵢ| / T`), its largest feed, and the move's time T at the written F
/// (minutes; the firmware takes `T · speed / max_feed`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limited {
    /// The axis of largest speed ratio.
    pub axis: usize,
    /// Its speed at the written F.
    pub speed: f64,
    /// Its largest feed.
    pub max_feed: f64,
    /// The move's time at the written F, minutes.
    pub minutes: f64,
}

/// The speed accounting of a file.
#[derive(Clone, Debug, Default)]
pub struct AxisSpeeds {
    max_feed: Vec<f64>,
    rotary: Vec<bool>,
    /// Moves limited, per axis (the axis of largest speed ratio).
    pub limited_by: Vec<u64>,
    /// Moves limited.
    pub limited: u64,
    /// Estimated time, slow-down included, minutes.
    pub minutes: f64,
    /// The slow-down's part of `minutes`.
    pub slowdown_minutes: f64,
}

impl AxisSpeeds {
    /// For axes with these largest feeds (`+inf`: no limit) and kinds.
    pub fn new(max_feed: Vec<f64>, rotary: Vec<bool>) -> AxisSpeeds {
        AxisSpeeds {
            limited_by: vec![0; max_feed.len()],
            max_feed,
            rotary,
            ..AxisSpeeds::default()
        }
    }

    /// A written move from `from` to `to` at feed `f` in mode `mode` (`firmware_length`: the
    /// flavour's length of the move, used in `tip` mode). When an axis limits the move, which
    /// one and by how much ([`Limited`]).
    pub fn add_move(
        &mut self,
        mode: FeedMode,
        from: &[f64],
        to: &[f64],
        f: f64,
        firmware_length: f64,
    ) -> Option<Limited> {
        let t = move_minutes(mode, &self.rotary, from, to, f, firmware_length);
        if t <= 0.0 {
            return None;
        }
        let mut worst = (1.0 + SPEED_SLACK, None);
        for (i, ((a, b), m)) in from.iter().zip(to).zip(&self.max_feed).enumerate() {
            let k = (b - a).abs() / t / m;
            if k > worst.0 {
                worst = (k, Some(i));
            }
        }
        self.minutes += t;
        let (k, i) = worst;
        let i = i?;
        self.limited += 1;
        self.limited_by[i] += 1;
        self.slowdown_minutes += (k - 1.0) * t;
        self.minutes += (k - 1.0) * t;
        Some(Limited {
            axis: i,
            speed: (to[i] - from[i]).abs() / t,
            max_feed: self.max_feed[i],
            minutes: t,
        })
    }

    /// A move whose F the feed rule lowered for axis `axis`'s largest feed, adding `minutes` to
    /// it (`tip` mode; the move's time itself is added by [`AxisSpeeds::add_move`] at that F).
    pub fn add_slowed(&mut self, axis: usize, minutes: f64) {
        self.limited += 1;
        self.limited_by[axis] += 1;
        self.slowdown_minutes += minutes;
    }

    /// A move of the extruder alone, `de` mm at feed `f` (`1/F` minutes in inverse time).
    pub fn add_extruder_move(&mut self, mode: FeedMode, de: f64, f: f64) {
        if !(f.is_finite() && f > 0.0) || de == 0.0 {
            return;
        }
        self.minutes += if mode == FeedMode::InverseTime {
            1.0 / f
        } else {
            de.abs() / f
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_move_too_fast_for_one_axis_takes_that_axis_time() {
        // X 10 mm and Z 5 mm at F 600 (xyz): L = √125, T = √125/600 min; Z moves at
        // 5/T = 268 mm/min > 200: T' = 5/200 min, limited by Z.
        let mut s = AxisSpeeds::new(vec![12000.0, 200.0, 3600.0], vec![false, false, true]);
        s.add_move(
            FeedMode::Xyz,
            &[0.0, 0.0, 0.0],
            &[10.0, 5.0, 0.0],
            600.0,
            f64::NAN,
        );
        assert_eq!((s.limited, s.limited_by.clone()), (1, vec![0, 1, 0]));
        assert!((s.minutes - 5.0 / 200.0).abs() < 1e-15);
        assert!((s.slowdown_minutes - (5.0 / 200.0 - 125f64.sqrt() / 600.0)).abs() < 1e-15);
        // a pure rotation of 90° at F 600 in xyz mode is 0.15 min, under 3600 °/min
        s.add_move(
            FeedMode::Xyz,
            &[0.0, 0.0, 0.0],
            &[0.0, 0.0, 90.0],
            600.0,
            f64::NAN,
        );
        assert_eq!(s.limited, 1);
        assert!((s.minutes - 5.0 / 200.0 - 0.15).abs() < 1e-15);
        // inverse time: F 60 = 1 s for 90°: 5400 °/min > 3600, 1.5 s
        s.add_move(
            FeedMode::InverseTime,
            &[0.0; 3],
            &[0.0, 0.0, 90.0],
            60.0,
            f64::NAN,
        );
        assert_eq!(s.limited_by, vec![0, 1, 1]);
        s.add_extruder_move(FeedMode::Xyz, -0.8, 2400.0);
        let want = 5.0 / 200.0 + 0.15 + 1.5 / 60.0 + 0.8 / 2400.0;
        assert!((s.minutes - want).abs() < 1e-15);
    }
}
