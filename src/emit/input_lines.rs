//! Which input line each output line came from: the machine emitter records it while the
//! collision check runs, so a finding's output line can be traced back to the slicer's line.
//!
//! The check walks the output as it streams and resolves its findings as it goes
//! (`crate::pipeline::checked_unwarp`), so the record only has to reach back to the first line
//! not yet walked: [`InputLines::forget_before`] drops the rest. Kept whole, it held a run per
//! output line of a tessellated file: 105 MB of G-code in, 4.4 M runs, ≈ 70 MB, and a copy of
//! it in the report.

/// Runs `(first output line, input line)`, output lines increasing; an output line belongs to
/// the last run starting at or before it. One entry per change of the input line.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InputLines(Vec<(u64, u64)>);

impl InputLines {
    /// The input line of output line `line` (None: before the first run, none recorded, or
    /// forgotten).
    pub fn of(&self, line: u64) -> Option<u64> {
        let k = self.0.partition_point(|(o, _)| *o <= line);
        k.checked_sub(1).map(|k| self.0[k].1).filter(|&l| l > 0)
    }

    /// Record that the lines from output line `output` on come from input line `input`.
    pub fn push(&mut self, output: u64, input: u64) {
        match self.0.last_mut() {
            Some((_, i)) if *i == input => {}
            Some((o, i)) if *o == output => *i = input,
            _ => self.0.push((output, input)),
        }
    }

    /// Forget what only output lines before `line` need: [`InputLines::of`] of every line from
    /// `line` on answers as before (the run holding `line` and the later ones are kept).
    pub fn forget_before(&mut self, line: u64) {
        let k = self.0.partition_point(|(o, _)| *o <= line);
        if k > 1 {
            self.0.drain(..k - 1);
        }
    }

    /// The runs held.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// No run held.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The oracle: a table of every output line's input line, built by the rule of the type's
    /// documentation (a line's input is the one recorded last at or before it, a later record
    /// for the same output line replacing it).
    #[test]
    fn forgetting_before_a_line_keeps_every_answer_from_that_line_on() {
        let mut rng = crate::test_rng::Lcg(18);
        for case in 0..200 {
            let mut rec = InputLines::default();
            let mut table: Vec<Option<u64>> = vec![None; 400];
            let (mut out, mut input) = (1u64, 1u64);
            while out < 380 {
                if rng.range(0.0, 1.0) < 0.3 {
                    input += 1 + (rng.range(0.0, 3.0) as u64);
                }
                rec.push(out, input);
                for t in table.iter_mut().skip(out as usize) {
                    *t = Some(input);
                }
                out += rng.range(0.0, 3.0) as u64;
            }
            let cut = rng.range(0.0, 400.0) as u64;
            let before = rec.len();
            rec.forget_before(cut);
            for line in cut..400 {
                assert_eq!(
                    rec.of(line),
                    table[line as usize],
                    "case {case}: line {line} after forgetting before {cut}"
                );
            }
            assert!(rec.len() <= before);
            if cut > 300 {
                assert!(
                    rec.len() <= 2 + (400 - cut as usize),
                    "case {case}: {} runs kept",
                    rec.len()
                );
            }
        }
    }
}
