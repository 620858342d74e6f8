//! A timing-accurate model of the SERCON816 controller and its SERCON410B-compatible
//! variant: registers, dual-port RAM, interrupts, timers, telegram processing.
//!
//! Time is injected: the model is advanced with `advance_to(t)` and says when it next needs to
//! run with `next_deadline()`; it never reads a clock (DESIGN.md).

pub mod pins;
pub mod vcd_trace;
