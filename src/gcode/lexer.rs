//! Bytes → words of one line. STUB: being written.
