//! The SERCON's automatic service-channel transfer: service containers (410B §1: "The
//! transmission of service channel information over several communication cycles is
//! executed automatically"; 410B §4.2.4).
//!
//! A data container with SVFL = 1 hands its record's first word (MDT control word or AT
//! status word) and the following NINFO info words to service container NSV (410B §4.2.2;
//! ERRATA "service info in a container"). The telegram processor calls three entry points:
//!
//! * [`on_transmit`] before sending a record of such a container,
//! * [`on_receive`] after receiving one (with whether it passed FCS and checks),
//! * [`on_cycle`] once per communication cycle, with HS_TIMEOUT and BUSY_TIMEOUT (0DH).
//!
//! The unit is pure: its only state is the dual-port RAM passed in. Every address is
//! SCPTn plus an 8-bit offset, reduced to the variant's RAM, and every RAM or record access
//! is bounded, so arbitrary RAM contents and records can neither panic nor loop.
//!
//! The readings chosen where 410B §4.2.4 is silent are in `docs/spec-notes.md`, section
//! "Service containers". In short:
//!
//! * Master: a new step starts on transmit when the last is acknowledged (AHS = MHS, BUSY
//!   = 0) and M_BUSY = 0: MHS toggles, END_MDT = SETEND ∧ (step reaches the buffer's last
//!   position). The acknowledgement is taken on receive: a write advances WRDATPT, a read
//!   stores the AT's info words at RDDATPT; reaching the end raises INT_END_WRBUF /
//!   INT_END_RDBUF and sets M_BUSY. ERR_AT on the acknowledgement raises INT_ERR, stores
//!   the error code at RDDATPT and sets M_BUSY. ERR_CNT counts the cycles of an
//!   unacknowledged step (handshake or, with BUSY_CNT, busy cycles) against the timeouts.
//! * Slave: a toggled MHS is a new step. A new element or read/write (or a step after
//!   END_MDT) raises INT_ELEM_CHANGE and holds BUSY_AT; otherwise a write stores the MDT's
//!   info words at RDDATPT and a read offers the words at WRDATPT, and AHS answers MHS.
//!   END_MDT on a write, and the end of the read buffer, hold BUSY_AT for the
//!   microprocessor.
//! * The write buffer always holds what the container sends, the read buffer what it
//!   receives, in both modes.

mod buffer;
mod container_ram;
mod master;
mod outcome;
mod record_bits;
mod slave;

pub use outcome::{ScInterrupts, ScOutcome};
pub use sercon_regs::Variant;

use container_ram::ContainerRam;

/// Mode of a container: SCMASTER of the data container (410B §4.2.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[doc(alias = "SCMASTER")]
pub enum ScMode {
    /// SCMASTER = 1: processing in master mode (the container sends MDT service info).
    Master,
    /// SCMASTER = 0: processing in slave mode (the container sends AT service info).
    Slave,
}

impl ScMode {
    /// The mode given by the data container's SCMASTER bit (410B §4.2.2 bit 14).
    pub const fn from_scmaster(scmaster: bool) -> ScMode {
        if scmaster {
            ScMode::Master
        } else {
            ScMode::Slave
        }
    }
}

/// The telegram processor is about to send a data record whose container has SVFL = 1 and
/// NSV = `nsv` (only its low 3 bits count).
///
/// `record` is the record's first word (MDT control word in master mode, AT status word in
/// slave mode: only the service-channel bits are touched, the rest is the host's) followed
/// by the info words; the first NINFO_WRITE of them that `record` has are filled in. Reads
/// and updates the container's words in `ram`.
pub fn on_transmit(
    ram: &mut [u16],
    variant: Variant,
    nsv: u8,
    mode: ScMode,
    record: &mut [u16],
) -> ScOutcome {
    let mut container = ContainerRam::locate(ram, variant, nsv);
    match mode {
        ScMode::Master => master::transmit(&mut container, record),
        ScMode::Slave => slave::transmit(&mut container, record),
    }
}

/// A data record with SVFL = 1 was received for container `nsv`. `ok` = FCS and checks
/// passed; on error (or an empty record) the container records RECERR and takes nothing
/// from the record.
pub fn on_receive(
    ram: &mut [u16],
    variant: Variant,
    nsv: u8,
    mode: ScMode,
    record: &[u16],
    ok: bool,
) -> ScOutcome {
    let mut container = ContainerRam::locate(ram, variant, nsv);
    let mut outcome = match mode {
        ScMode::Master => master::receive(&mut container, record, ok),
        ScMode::Slave => slave::receive(&mut container, record, ok),
    };
    // 816 §2.10.2.2: INT_RSCEND marks the end of the telegram processor's work on the
    // service containers after a receive telegram.
    outcome.rscend = matches!(variant, Variant::Sercon816);
    outcome
}

/// Once per communication cycle, with HS_TIMEOUT and BUSY_TIMEOUT from 0DH (410B §4.1),
/// both counted in communication cycles; 0 disables a timeout. Only master-mode
/// containers count (the slave table has no counter); a slave-mode call does nothing.
pub fn on_cycle(
    ram: &mut [u16],
    variant: Variant,
    nsv: u8,
    mode: ScMode,
    hs_timeout: u8,
    busy_timeout: u8,
) -> ScOutcome {
    match mode {
        ScMode::Master => {
            let mut container = ContainerRam::locate(ram, variant, nsv);
            master::cycle(&mut container, hs_timeout, busy_timeout)
        }
        ScMode::Slave => ScOutcome::default(),
    }
}
