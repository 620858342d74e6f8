//! An emulated SERCOS servo drive: IDN database, procedure commands and motion model.
//!
//! * [`database::IdnDatabase`]: the IDNs with elements 1–7, checked writes returning the
//!   standard service-channel errors, procedure commands; implements
//!   [`sercdrv::idn_store::IdnStore`] for the slave driver;
//! * [`config_file`]: loading a database from a TOML file;
//! * [`telegram_layout`]: the cyclic data of MDT and AT records from S-0-0015/16/24;
//! * [`motion`]: the axis (first-order velocity loop, integrated position);
//! * [`drive::EmulatedDrive`]: all of it driven by the control word, with time injected;
//! * [`node::DriveNode`]: the drive behind a SERCDRV slave, a `HostProgram` for the ring.

mod command_inputs;
pub mod config_file;
pub mod database;
pub mod drive;
pub mod motion;
pub mod node;
pub mod parameter;
pub mod procedure;
pub mod telegram_layout;
