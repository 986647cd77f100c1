//! Axis values without a heap allocation: the emitter and the interpolation check make several
//! per output move (the values as the firmware reads them, interpolated samples), and a `Vec`
//! for each cost the machine output about 5 % of its time in `malloc`/`free` (issue 13's
//! profile of the cartesian preset, session 15).

use std::ops::{Deref, DerefMut};

/// Most axes held on the stack; a machine with more (a JSON machine may have any number) keeps
/// them in a `Vec`.
pub const INLINE_AXES: usize = 8;

/// A machine's axis values (mm, degrees), in output order: on the stack up to
/// [`INLINE_AXES`], else on the heap. Reads as a slice.
#[derive(Clone)]
pub struct AxisBuf {
    inline: [f64; INLINE_AXES],
    heap: Vec<f64>,
    len: usize,
}

impl AxisBuf {
    /// `f(i)` for the axes `0..len`.
    pub fn from_fn(len: usize, mut f: impl FnMut(usize) -> f64) -> AxisBuf {
        let mut out = AxisBuf {
            inline: [0.0; INLINE_AXES],
            heap: Vec::new(),
            len,
        };
        if len <= INLINE_AXES {
            for (i, o) in out.inline[..len].iter_mut().enumerate() {
                *o = f(i);
            }
        } else {
            out.heap = (0..len).map(f).collect();
        }
        out
    }

    /// A copy of `values`.
    pub fn from_slice(values: &[f64]) -> AxisBuf {
        AxisBuf::from_fn(values.len(), |i| values[i])
    }

    /// `a + (b − a)·s` per axis (the shorter's count).
    pub fn lerp(a: &[f64], b: &[f64], s: f64) -> AxisBuf {
        AxisBuf::from_fn(a.len().min(b.len()), |i| a[i] + (b[i] - a[i]) * s)
    }
}

impl Deref for AxisBuf {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        if self.len <= INLINE_AXES {
            &self.inline[..self.len]
        } else {
            &self.heap
        }
    }
}

impl DerefMut for AxisBuf {
    fn deref_mut(&mut self) -> &mut [f64] {
        if self.len <= INLINE_AXES {
            &mut self.inline[..self.len]
        } else {
            &mut self.heap
        }
    }
}

impl PartialEq for AxisBuf {
    fn eq(&self, other: &AxisBuf) -> bool {
        **self == **other
    }
}

impl std::fmt::Debug for AxisBuf {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_axis_buf_reads_as_its_values_on_the_stack_and_on_the_heap() {
        for len in [0, 3, INLINE_AXES, INLINE_AXES + 1, 12] {
            let v: Vec<f64> = (0..len).map(|i| i as f64 * 1.5 - 2.0).collect();
            let mut b = AxisBuf::from_slice(&v);
            assert_eq!(&*b, v.as_slice(), "len {len}");
            b[len.saturating_sub(1).min(len)..]
                .iter_mut()
                .for_each(|x| *x += 1.0);
            let w: Vec<f64> = v
                .iter()
                .enumerate()
                .map(|(i, x)| if i + 1 == len { x + 1.0 } else { *x })
                .collect();
            assert_eq!(&*b, w.as_slice(), "len {len} after a write");
            let l = AxisBuf::lerp(&v, &w, 0.5);
            let want: Vec<f64> = v.iter().zip(&w).map(|(a, c)| a + (c - a) * 0.5).collect();
            assert_eq!(&*l, want.as_slice());
            assert!(b == AxisBuf::from_slice(&w) && (len == 0 || b != AxisBuf::from_slice(&v)));
        }
    }
}
