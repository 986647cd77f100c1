//! Machines: turn the toolpath (tip p, tool axis n) into the axes of a real printer.
//! STUB: being written (issue: machines).
