//! The streaming G-code reader: modal state over lines. STUB: being written.

use super::{GcodeError, Line};
use crate::toolpath::Feature;

/// Reader settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReadOptions {
    /// Largest distance between an arc and its chords, mm.
    pub arc_chord_tolerance: f64,
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions { arc_chord_tolerance: crate::tolerance::ARC_CHORD_TOLERANCE }
    }
}

/// The modal state after the last line read.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Absolute position, mm (after G92 offsets: the G-code's own coordinates).
    pub position: glam::DVec3,
    pub e_relative: bool,
    pub positioning_relative: bool,
    pub inch: bool,
    pub feed: f64,
    pub layer: u32,
    pub feature: Feature,
    /// Whether an explicit layer marker (`;LAYER_CHANGE`, `;LAYER:`) has been seen.
    pub layer_markers: bool,
}

/// Streaming reader: push byte chunks, get one [`Line`] per complete source line.
pub struct Reader {
    _opts: ReadOptions,
}

impl Reader {
    pub fn new(opts: ReadOptions) -> Reader {
        Reader { _opts: opts }
    }
    /// Feed a chunk; `sink` is called for every complete line, in order.
    pub fn push<E: From<GcodeError>>(
        &mut self,
        _chunk: &[u8],
        _sink: &mut dyn FnMut(Line<'_>, &State) -> Result<(), E>,
    ) -> Result<(), E> {
        Ok(())
    }
    /// End of input: flush a last line without terminator.
    pub fn finish<E: From<GcodeError>>(&mut self, _sink: &mut dyn FnMut(Line<'_>, &State) -> Result<(), E>) -> Result<(), E> {
        Ok(())
    }
}
