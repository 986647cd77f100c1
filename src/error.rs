//! Stable error codes.
//!
//! Every area has one `#[non_exhaustive]` error enum with `Display` (what went wrong and what to
//! fix), `source()` (the error it wraps, if any) and a **stable code** per variant
//! (`"area.what"`, e.g. `"unwarp.relative-positioning"`), given by [`Coded`]. Messages may be
//! reworded; codes do not change: the web page keys its advice by code, and the wasm layer
//! hands the code to JavaScript beside the message. An error that wraps another one reports
//! the wrapped error's code (the cause is what the user can fix).
//!
//! [`error_codes!`](crate::error_codes) writes an area's `code()` match and its catalogue
//! ([`ErrorCode`] list, for [`crate::describe`]) from one table, so the two cannot disagree,
//! and the match is exhaustive: a new variant without a code does not compile.

/// An error with a stable, machine-readable code.
pub trait Coded: std::error::Error {
    /// The stable code of this error (`"area.what"`).
    fn code(&self) -> &'static str;
}

/// One entry of an area's error catalogue.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct ErrorCode {
    /// The stable code.
    pub code: &'static str,
    /// The area (the part before the dot).
    pub area: &'static str,
    /// What the error means, in one line (the message itself says what to fix).
    pub summary: &'static str,
}

/// `error_codes!(Type, CATALOGUE, "area" { Variant => "code", "summary"; … } wraps { Variant, … })`
/// implements [`Coded`] for `Type` and defines `pub const CATALOGUE: &[ErrorCode]`. Variants
/// listed after `wraps` are tuple variants holding one [`Coded`] error whose code they report.
#[macro_export]
#[doc(hidden)]
macro_rules! error_codes {
    ($ty:ident, $list:ident, $area:literal {
        $($variant:ident => $code:literal, $summary:literal;)*
    } wraps { $($wrap:ident),* $(,)? }) => {
        impl $crate::error::Coded for $ty {
            fn code(&self) -> &'static str {
                match self {
                    $($ty::$variant { .. } => $code,)*
                    $($ty::$wrap(e) => $crate::error::Coded::code(e),)*
                }
            }
        }
        /// The codes of this area's errors (see [`crate::error`]).
        pub const $list: &[$crate::error::ErrorCode] = &[
            $($crate::error::ErrorCode { code: $code, area: $area, summary: $summary },)*
        ];
    };
}
