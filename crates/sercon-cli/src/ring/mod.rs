//! `sercon ring`: a full-stack simulated SERCOS ring — a [`sercdrv::master::Master`] and
//! emulated drives ([`sercos_drive::node::DriveNode`]) on SERCON models joined by fibres
//! ([`sercos_sim`]) — brought up through phases 0–4, run in cyclic operation with a motion
//! profile, with faults injected, and summed up in a [`RingReport`].
//!
//! ```no_run
//! use sercon_cli::ring::{self, RingSpec};
//! let spec = RingSpec::default(); // a master and 4 drives, SERCON816, 16 Mbit/s, 1 ms
//! let outcome = ring::run(&spec, &mut |_progress| {})?;
//! println!("{}", outcome.report.to_text());
//! # Ok::<(), sercon_cli::ring::RingError>(())
//! ```
//!
//! Readings chosen where the documents are silent: `docs/spec-notes.md`, "The ring command".

mod config_file;
mod error;
mod fault_spec;
mod motion_profile;
mod probes;
mod report;
mod runner;
mod setup;
mod spec;
mod time_text;
mod traces;

pub use config_file::{ConfigError, load_config, parse_config};
pub use error::RingError;
pub use fault_spec::{FaultSpec, FaultSpecError, FaultWhat, NodeRef};
pub use motion_profile::MotionProfile;
pub use report::{
    AxisReport, DriveReport, MasterEvent, RingEvent, RingEventKind, RingReport, RunResult,
};
pub use runner::{RingOutcome, RunProgress, run};
pub use setup::{BuiltRing, build, databases, master_config, pin_named, pin_names};
pub use spec::{DriveSpec, RingSpec, TraceSpec};
pub use time_text::{format_duration, parse_duration};
pub use traces::write_traces;
