//! A timing-accurate model of the SERCON816 controller and its SERCON410B-compatible
//! variant: registers, dual-port RAM, interrupts, timers, telegram processing.
//!
//! Time is injected: the model is advanced with `advance_to(t)` and says when it next needs to
//! run with `next_deadline()`; it never reads a clock (DESIGN.md).

pub mod chip;
pub mod config;
mod cycle;
mod cycle_plan;
mod deadline;
mod engine;
mod first_queue;
mod interrupts;
mod mclk;
mod mst;
pub mod pins;
mod reciprocal;
mod register_access;
mod register_file;
mod reset;
pub mod serial_port;
pub mod serial_settings;
pub mod service_container;
mod settings;
pub mod telegram_processor;
mod time_base;
mod timing_outputs;
pub mod vcd_trace;
mod watchdog;

pub use chip::Chip;
pub use config::{ChipConfig, ConfigError, Straps};
