//! Deterministic event simulation of a SERCOS ring (or RS-485 bus) of controller models,
//! fibres, faults and traces.
//!
//! A [`sim::Simulation`] is built from a [`config::SimConfig`] (topology, nodes, faults,
//! seed, traces) and one [`host::HostProgram`] per node; [`static_ring::StaticRing`] builds
//! a configured phase-4 ring with static RAM images, and [`scenario`] the benchmark
//! scenarios of `sercon bench`.

pub mod clock;
pub mod config;
pub mod error;
pub mod event_queue;
pub mod fault;
pub mod host;
mod host_coroutine;
mod node;
pub mod recorder;
pub mod scenario;
pub mod sim;
pub mod static_ring;
pub mod topology;
pub mod trace;

pub use config::{Delivery, NodeConfig, SimConfig, TraceConfig};
pub use error::SimError;
pub use fault::{Fault, FaultKind};
pub use host::{HostProgram, NodeBus, Wake};
pub use sim::{SimStats, Simulation};
pub use topology::{Fibre, Topology};
