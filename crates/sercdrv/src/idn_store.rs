//! The slave side of the service channel: what a drive's IDN database offers the driver.
//!
//! The slave driver serves the service channel (sercos-telegrams.md, MDT control word bits
//! 5–0: element, read/write, last transmission, MHS) from an [`IdnStore`]; the emulated drive
//! (`sercos-drive`) implements it. Errors are the standard service-channel error codes
//! (sercos-facts.md, "Service channel errors").

use sercos_wire::idn::{Element, Idn};
use sercos_wire::service_error::ServiceError;
use sercos_wire::telegram::CommunicationPhase;

/// A drive's IDN database as the service channel sees it.
pub trait IdnStore {
    /// Reads data block element `element` (1–7) of `idn` as service-channel words: element 1
    /// is the IDN, 2 and 4 are text (current length, maximum length, bytes), 3 the attribute
    /// (two words, low first), 5–7 data as the attribute describes it.
    fn read_element(&self, idn: Idn, element: Element) -> Result<Vec<u16>, ServiceError>;

    /// Writes data block element `element` of `idn` from service-channel words, checked
    /// against the attribute, limits, write protection in the current phase and, for
    /// procedure commands, the command values 3 (set and enable) and 0 (cancel).
    fn write_element(
        &mut self,
        idn: Idn,
        element: Element,
        words: &[u16],
    ) -> Result<(), ServiceError>;

    /// Tells the store the communication phase the master announced in the MST; write
    /// protection (attribute bits 30–28) depends on it.
    fn set_phase(&mut self, phase: CommunicationPhase);
}
