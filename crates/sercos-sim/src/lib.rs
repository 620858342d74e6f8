//! Deterministic event simulation of a SERCOS ring (or RS-485 bus) of controller models,
//! fibres, faults and traces.
