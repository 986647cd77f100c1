//! E words without drift.

/// Writes E words in the file's own mode, without drift: in relative mode each value is the
/// difference of the rounded running totals, so the sum of the written values equals the
/// rounded exact total; in absolute mode the running total is written.
#[derive(Clone, Debug, Default)]
pub struct EWriter {
    /// Exact running total since the last reset, mm.
    exact: f64,
    /// The firmware's E after the last written value (absolute) / the rounded total (relative).
    written: f64,
}

/// E words are written with 5 decimals.
pub const E_QUANTUM: f64 = 1e-5;

fn round_e(v: f64) -> f64 {
    crate::num::round(v / E_QUANTUM) * E_QUANTUM
}

impl EWriter {
    /// `G92 E v`: the firmware's E is now v.
    pub fn reset(&mut self, v: f64) {
        self.exact = v;
        self.written = v;
    }
    /// The firmware's current E (absolute mode).
    pub fn current(&self) -> f64 {
        self.written
    }
    /// Add `de` and return the value to write: the delta (relative) or the total (absolute).
    pub fn advance(&mut self, de: f64, relative: bool) -> f64 {
        self.exact += de;
        let r = round_e(self.exact);
        let out = if relative { r - self.written } else { r };
        self.written = r;
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_e_does_not_drift() {
        let mut w = EWriter::default();
        let mut sum = 0.0;
        for _ in 0..100_000 {
            sum += w.advance(0.0123456789, true);
        }
        assert!((sum - 1234.56789).abs() < 1e-6, "{sum}");
    }
}
