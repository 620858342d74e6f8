//! Deterministic event simulation of a SERCOS ring (or RS-485 bus) of controller models,
//! fibres, faults and traces.

pub mod event_queue;
pub mod trace;
