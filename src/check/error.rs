//! Errors of `warpslice check`: the input cannot be read as a G-code of the machine (exit code
//! 2 of the CLI). Findings in a readable file are not errors: they are the report.

use core::fmt;

use crate::machine::MachineError;

/// Why a G-code cannot be checked.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum CheckError {
    /// A word of a `G` line whose number does not parse (`X1.2.3`, `XNaN`, `E-`): the move
    /// cannot be read, so nothing after it can be judged.
    BadNumber {
        /// 1-based line of the file.
        line: u64,
        /// The word as written.
        word: String,
    },
    /// No `G0`/`G1` in the file names any of the machine's axes: not a G-code of this machine
    /// (another file, a binary, or the wrong machine).
    NoMoves {
        /// Name of the machine (preset or JSON `name`).
        machine: String,
        /// The machine's axis letters.
        axes: Vec<String>,
        /// Lines read.
        lines: u64,
    },
    /// The machine is unusable (its JSON, its parameters).
    Machine(MachineError),
}

impl fmt::Display for CheckError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CheckError::BadNumber { line, word } => write!(
                f,
                "line {line}: '{word}' is not a G-code number; correct the word (a number like 12.5 or -0.8) so the move can be read"
            ),
            CheckError::NoMoves { machine, axes, lines } => write!(
                f,
                "no G0/G1 move in the {lines} lines names an axis of machine {machine} ({}): this is not a G-code for this machine; check the file, or pick the machine the file was written for",
                axes.join(" ")
            ),
            CheckError::Machine(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for CheckError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            CheckError::Machine(e) => Some(e),
            _ => None,
        }
    }
}

impl From<MachineError> for CheckError {
    fn from(e: MachineError) -> CheckError {
        CheckError::Machine(e)
    }
}

crate::error_codes!(CheckError, ERROR_CODES, "check" {
    BadNumber => "check.bad-number", "a word of a G line is not a number";
    NoMoves => "check.no-moves", "no move names an axis of the machine: not its G-code";
} wraps { Machine });
