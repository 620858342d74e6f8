//! What the slave driver did, for logs and tests.

use sercos_wire::idn::Idn;
use sercos_wire::telegram::CommunicationPhase;

use super::device::DeviceRefusal;
use super::error::SlaveError;
use crate::service_channel::SlaveEvent;

/// Why the slave did not follow a phase the master announced.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PhaseRefusal {
    /// The procedure command checking this step (S-0-0127, S-0-0128) has not been executed.
    TransitionCheckNotExecuted(Idn),
    /// S-0-0127 was executed but the phase 3–4 RAM could not be laid out.
    CyclicSetUpFailed,
    /// Phases step up one at a time (or drop to 0).
    NotTheNextPhase,
    /// The MST carried a phase above 4 (sercos-telegrams.md: phases 0–4).
    NoSuchPhase,
}

/// One thing the slave driver did or saw.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SlaveDriverEvent {
    /// The chip was initialised.
    Started,
    /// Initialisation failed; the driver is stopped.
    Failed(SlaveError),
    /// The slave follows `phase` now.
    PhaseChanged(CommunicationPhase),
    /// The MST carried `requested` and the slave did not follow (410B §4.1 4H.6
    /// INT_PHASERR). Reported once until the phase changes or another one is asked.
    PhaseRefused {
        /// The phase the slave stays in.
        from: CommunicationPhase,
        /// PHASREC.
        requested: u8,
        /// Why.
        reason: PhaseRefusal,
    },
    /// The phase 3–4 RAM was laid out (S-0-0127 executed); the step to phase 3 is armed.
    CyclicSetUp,
    /// The phase 3–4 RAM could not be laid out.
    CyclicSetUpFailed(SlaveError),
    /// The service-channel server did something.
    Service(SlaveEvent),
    /// The MST was missing twice in a row (410B §4.1 4H.9 INT_MSTMIS) in `phase`: the slave
    /// shut down and fell back to phase 0.
    MstLost {
        /// The phase the slave was in.
        phase: CommunicationPhase,
    },
    /// No valid MDT record arrived in a phase 3–4 cycle (RERR, or VAL = 0).
    CommandMissing,
    /// The device refused a record or a phase.
    DeviceRefused(DeviceRefusal),
}
