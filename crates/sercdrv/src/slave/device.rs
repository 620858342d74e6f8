//! What the slave driver needs from the device behind it (a drive): its IDN store, its
//! cyclic data and its consent to phase changes.
//!
//! The driver knows the chip and the telegrams; the device knows the meaning of the data.
//! `sercos-drive` implements this for its emulated drive, a real drive's firmware would
//! implement it for its own database and control loops.

use sercos_wire::telegram::CommunicationPhase;
use sercos_wire::time::Instant;

use crate::idn_store::IdnStore;

/// The device refused something, in its own words.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct DeviceRefusal(pub String);

/// Bytes of cyclic data in the device's records (after the control/status word and the
/// service info, sercos-telegrams.md "Data Record").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CyclicLengths {
    /// Command data bytes in the MDT record.
    pub mdt_data_bytes: u16,
    /// Feedback data bytes in the AT record.
    pub at_data_bytes: u16,
}

/// The device behind a slave: a drive or an I/O module.
pub trait SlaveDevice {
    /// The IDN store the service channel is served from.
    fn idn_store(&mut self) -> &mut dyn IdnStore;

    /// The cyclic data lengths the current configuration gives (S-0-0015, S-0-0016,
    /// S-0-0024 for a drive), asked before the step to phase 3.
    fn cyclic_lengths(&self) -> Result<CyclicLengths, DeviceRefusal>;

    /// The master switched to `phase` (the chip already follows it); the device takes it or
    /// says why not.
    fn enter_phase(&mut self, now: Instant, phase: CommunicationPhase)
    -> Result<(), DeviceRefusal>;

    /// One MDT record received in phase 3 or 4: control word, service info and command data,
    /// little endian as on the line.
    fn command_record(&mut self, now: Instant, record: &[u8]) -> Result<(), DeviceRefusal>;

    /// The status word at `now` (sercos-telegrams.md, AT status word). The driver leaves
    /// bits 0–2 to the chip's service container and sends bit 5 through CMD_AT.
    fn status_word(&mut self, now: Instant) -> u16;

    /// The feedback data of the AT record at `now` (after status word and service info),
    /// little endian, into `out` (cleared first; the driver reuses it every cycle); the
    /// driver pads or cuts it to the configured length.
    fn feedback_data(&mut self, now: Instant, out: &mut Vec<u8>);
}
