//! The `warpslice` command line. STUB: being written.
fn main() {}
