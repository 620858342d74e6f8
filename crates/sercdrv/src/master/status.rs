//! What the master reports about itself: phase, progress, each drive, counters.

use sercos_wire::address::DriveAddress;

use super::error::MasterError;

/// Where the phase-up stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Progress {
    /// Not started (no [`Wake::Start`](sercon_regs::host::Wake::Start) yet).
    Idle,
    /// Phase 0: waiting for the ring to close.
    WaitingForRing,
    /// Phase 1: addressing every drive, noting which answer.
    DetectingDrives,
    /// Phase 2: reading the drives' timing parameters.
    ReadingParameters,
    /// Phase 2: writing the cycle's timing and telegram layout, running S-0-0099 and
    /// S-0-0127.
    Configuring,
    /// Phase 2: configured and held there as asked
    /// ([`MasterConfig::hold_in_phase2`](super::MasterConfig::hold_in_phase2)); tool
    /// requests are served.
    HeldInPhase2,
    /// Phase 3: running S-0-0128.
    CheckingPhase4,
    /// Phase 4: cyclic operation.
    Cyclic,
    /// Stopped by an error that a restart of the phase-up would not cure (see
    /// [`MasterStatus::last_error`]).
    Halted,
}

/// What the master knows of one drive.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct DriveStatus {
    /// The drive's address.
    pub address: DriveAddress,
    /// It answered an MDT in phase 1.
    pub answered: bool,
    /// ATs received in phases 3-4 without error.
    pub ats_received: u64,
    /// ATs missing or errored in phases 3-4.
    pub ats_missed: u64,
}

/// A snapshot of the master.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MasterStatus {
    /// The communication phase sent in the MST (PHAS0, 410B §4.1 0AH).
    pub phase: u8,
    /// Where the phase-up stands.
    pub progress: Progress,
    /// Every configured drive.
    pub drives: Vec<DriveStatus>,
    /// Cycles seen (INT_COMEND).
    pub cycles: u64,
    /// Service-channel requests completed.
    pub service_requests: u64,
    /// Times the master fell back to phase 0.
    pub restarts: u32,
    /// Cycles in which the receive line lost its edges (INT_FIBBR, 410B §4.1 4H.1); zero on
    /// an intact ring.
    pub dark_cycles: u64,
    /// The most recent error.
    pub last_error: Option<MasterError>,
}
