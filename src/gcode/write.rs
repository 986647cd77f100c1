//! Deterministic number formatting for output G-code. STUB: being written.

/// Append a coordinate in mm (3 decimals, trailing zeros trimmed, no `-0`).
pub fn push_mm(out: &mut Vec<u8>, v: f64) {
    out.extend_from_slice(format!("{v:.3}").as_bytes());
}
/// Append an E value (5 decimals, trailing zeros trimmed, no `-0`).
pub fn push_e(out: &mut Vec<u8>, v: f64) {
    out.extend_from_slice(format!("{v:.5}").as_bytes());
}
/// Append a feed rate in mm/min (at most 3 decimals, trimmed).
pub fn push_feed(out: &mut Vec<u8>, v: f64) {
    out.extend_from_slice(format!("{v:.3}").as_bytes());
}
