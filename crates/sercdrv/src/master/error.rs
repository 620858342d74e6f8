//! Errors that name the drive, the phase and the IDN.

use sercos_wire::address::DriveAddress;
use sercos_wire::idn::Idn;

use crate::ram_layout::RamLayoutError;
use crate::service_channel::ErrorKind as ServiceErrorKind;
use crate::timing::TimingError;

/// What went wrong.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum MasterErrorKind {
    /// The configuration cannot be run.
    #[error("invalid configuration: {0}")]
    Config(&'static str),
    /// Register VERSION names another controller than configured (816 §2.11.1.1).
    #[error("chip reads VERSION {found:#06X}, expected {expected:#06X}")]
    WrongChip {
        /// The VERSION read.
        found: u16,
        /// The VERSION of the configured variant.
        expected: u16,
    },
    /// The bit rate is not available on this chip and strapping (816 §2.3.1 table).
    #[error("bit rate not available on this chip")]
    BitRate,
    /// The configured drive never answered an MDT addressed to it in phase 1.
    #[error("drive does not answer")]
    DriveMissing,
    /// The service channel failed: the drive refused (its error code) or did not answer.
    #[error("service channel: {0}")]
    ServiceChannel(ServiceErrorKind),
    /// A procedure command ended with its error bit, or never ended.
    #[error("procedure command failed (status {status:#06X})")]
    ProcedureFailed {
        /// The last command status word read (sercos-facts.md, "Procedure commands").
        status: u16,
    },
    /// A value the drive reported is unusable.
    #[error("drive reported an unusable value {0}")]
    BadValue(u64),
    /// The cycle cannot be planned with the drives' values.
    #[error("timing: {0}")]
    Timing(TimingError),
    /// The RAM layout does not fit.
    #[error("RAM layout: {0}")]
    Layout(RamLayoutError),
    /// The ring fits no RAM layout of the controller, not even DMA with one MDT container
    /// for every record and the smallest service-container buffers.
    #[error("{drives} drives need {needed} words of RAM, the controller has {available}")]
    RingDoesNotFit {
        /// Drives configured.
        drives: usize,
        /// Words the smallest layout needs.
        needed: u32,
        /// Words of the RAM (1024 or 2048).
        available: u32,
    },
    /// The ATs stopped coming in phases 3-4 while the line still carries light: the MST
    /// does not get round the ring.
    #[error("MST lost: no telegram came back")]
    MstLost,
    /// The master's receiver sees no edges (410B §4.1 4H.1 INT_FIBBR, 2H.13 FIBBR).
    #[error("ring broken: no receive signal")]
    RingBroken,
    /// The chip reports a programming error (410B §4.1 17H PROGERR_FL).
    #[error("chip programming error flags {0:#06X}")]
    ProgrammingError(u16),
}

/// An error of the master, naming the drive, phase and IDN where they apply.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("phase {phase}{}{}: {kind}",
    drive.map(|d| format!(", drive {}", d.get())).unwrap_or_default(),
    idn.map(|i| format!(", {i}")).unwrap_or_default())]
pub struct MasterError {
    /// The drive concerned, if one is.
    pub drive: Option<DriveAddress>,
    /// The communication phase the master was in.
    pub phase: u8,
    /// The IDN concerned, if one is.
    pub idn: Option<Idn>,
    /// What went wrong.
    pub kind: MasterErrorKind,
}

impl MasterError {
    /// An error without drive or IDN.
    pub(crate) fn ring(phase: u8, kind: MasterErrorKind) -> MasterError {
        MasterError {
            drive: None,
            phase,
            idn: None,
            kind,
        }
    }
}
