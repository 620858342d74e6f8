//! Why a ring could not be built, run or written.

use sercdrv::master::MasterError;
use sercos_drive::config_file::ConfigError as IdnFileError;
use sercos_drive::node::NodeError;
use sercos_sim::SimError;

/// A ring error; its text is one line naming what is wrong and where.
#[derive(Debug, thiserror::Error)]
pub enum RingError {
    /// The ring description cannot run.
    #[error("{0}")]
    Spec(String),
    /// The ring configuration file is wrong (file:line:column: what).
    #[error(transparent)]
    Config(#[from] super::config_file::ConfigError),
    /// A drive's IDN file is wrong (file:line:column: what).
    #[error("IDN file {0}")]
    IdnFile(IdnFileError),
    /// The master refused its configuration.
    #[error("master: {0}")]
    Master(MasterError),
    /// A drive could not be made.
    #[error("drive {address}: {source}")]
    Drive {
        /// Its address.
        address: u8,
        /// Why.
        source: NodeError,
    },
    /// The simulation failed.
    #[error("simulation: {0}")]
    Sim(SimError),
    /// A trace file could not be written.
    #[error("cannot write {path}: {source}")]
    Write {
        /// The file.
        path: String,
        /// Why.
        source: std::io::Error,
    },
}
