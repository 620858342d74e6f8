//! The slave's service-channel server: answers the master from an [`IdnStore`] through the
//! slave's own service container (410B §4.2.4, slave table), event-driven.
//!
//! What the chip does and leaves to the microprocessor is the reading of spec-notes "Service
//! containers": in slave mode the read buffer takes what the master writes and the write
//! buffer holds what the slave sends. The server
//!
//! * on INT_ELEM_CHANGE starts a new transmission of ELEM / L/S: for a read it fetches the
//!   element from the store and offers its first words in the write buffer, for a write it
//!   empties the read buffer; then it clears BUSY_AT so the chip takes the held step;
//! * on INT_END_RDBUF (read buffer full) collects the words and empties the buffer;
//! * on INT_END_MDT of a write applies the collected words to the store (element 1 opens
//!   the IDN), and on a refusal sets ERR_AT with the error code as the answer's info word;
//! * on INT_END_WRBUF (write buffer exhausted) offers the next words;
//! * clears each interrupt bit and BUSY_AT.

use sercon_regs::ram::service::ScSlave;
use sercon_regs::{IntFlagsHi, SerconBus, SerconBusExt};
use sercos_wire::idn::{Element, Idn};
use sercos_wire::service_error::{DescriptiveElement, ElementFault, ServiceError};

use super::container::{BUF, ContainerSlot};
use super::transfer::MAX_VARIABLE_WORDS;
use crate::idn_store::IdnStore;

/// What the server did, for logs and tests.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SlaveEvent {
    /// The master opened `idn` (element 1 written).
    Opened(Idn),
    /// The master began reading `element` of `idn`.
    ReadStarted {
        /// The open IDN.
        idn: Idn,
        /// The element.
        element: Element,
    },
    /// The master wrote `element` of `idn` and the store took it.
    Written {
        /// The open IDN.
        idn: Idn,
        /// The element.
        element: Element,
    },
    /// The server refused the transmission with `error` (ERR_AT).
    Refused {
        /// The open IDN, if any.
        idn: Option<Idn>,
        /// The element.
        element: Element,
        /// The code sent.
        error: ServiceError,
    },
    /// The master toggled MHS out of turn (410B §4.2.4 INT_SC_ERR); the server released
    /// the container.
    ProtocolError,
}

/// The present transmission (one element, one direction).
#[derive(Debug, Default)]
struct Transmission {
    element: u8,
    /// Words the master wrote so far.
    received: Vec<u16>,
    /// Words to send for a read.
    outgoing: Vec<u16>,
    /// Words of `outgoing` put into the write buffer so far.
    offered: usize,
}

/// The slave's service-channel server over its service container.
#[derive(Debug)]
pub struct ServiceChannelSlave {
    slot: ContainerSlot,
    open: Option<Idn>,
    transmission: Transmission,
}

impl ServiceChannelSlave {
    /// A server on the slave-mode container `slot`.
    pub fn new(slot: ContainerSlot) -> ServiceChannelSlave {
        ServiceChannelSlave {
            slot,
            open: None,
            transmission: Transmission::default(),
        }
    }

    /// The container.
    pub fn slot(&self) -> &ContainerSlot {
        &self.slot
    }

    /// The IDN the master opened last (element 1), while the channel is open.
    pub fn open_idn(&self) -> Option<Idn> {
        self.open
    }

    /// Writes SCPTn and leaves the container ready: BUSY_AT = 0, NINFO, buffers at offset 5
    /// (410B §4.2, §4.2.4 slave table).
    pub fn init<B: SerconBus + ?Sized>(&mut self, bus: &mut B) {
        self.open = None;
        self.transmission = Transmission::default();
        self.slot.install(bus);
        let mut s = ScSlave {
            ninfo_write: self.slot.ninfo(),
            ninfo_read: self.slot.ninfo(),
            ..ScSlave::default()
        };
        s.pointers.wrdatpt = BUF;
        s.pointers.wrdatlast = BUF;
        s.pointers.rddatpt = BUF;
        s.pointers.rddatlast = self.slot.step_last();
        self.slot.store_all(bus, s.to_words());
    }

    /// Sets or clears the command change bit the AT carries (CMD_AT, slave word 0.3; AT
    /// status word bit 5, ERRATA "service info in a container"; the chip never writes it in
    /// slave mode, spec-notes "Service containers").
    pub fn set_command_change<B: SerconBus + ?Sized>(&self, bus: &mut B, changed: bool) {
        let mut s = self.slot.slave(bus);
        if s.cmd_at != changed {
            s.cmd_at = changed;
            self.slot.store(bus, s.to_words(), false);
        }
    }

    /// Handles the container's interrupt (5H INT_SC_n, 410B §4.1) if `int_sc` has it:
    /// clears it (write 1 to clear, ERRATA "410B 4H/5H") and polls.
    pub fn on_interrupt<B: SerconBus + ?Sized, S: IdnStore + ?Sized>(
        &mut self,
        bus: &mut B,
        store: &mut S,
        int_sc: IntFlagsHi,
    ) -> Vec<SlaveEvent> {
        if let Some(bit) = IntFlagsHi::int_sc(self.slot.nsv()) {
            if int_sc.contains(bit) {
                bus.clear_int_hi(bit);
            }
        }
        self.poll(bus, store)
    }

    /// Looks at the container and serves whatever the chip raised.
    pub fn poll<B: SerconBus + ?Sized, S: IdnStore + ?Sized>(
        &mut self,
        bus: &mut B,
        store: &mut S,
    ) -> Vec<SlaveEvent> {
        let before = self.slot.slave(bus);
        let mut s = before;
        let mut events = Vec::new();

        if s.int_sc_err {
            // 410B §4.2.4 INT_SC_ERR: the chip held BUSY_AT; release it.
            s.int_sc_err = false;
            s.busy_at = false;
            events.push(SlaveEvent::ProtocolError);
        }
        if s.int_elem_change {
            // 410B §4.2.4 INT_ELEM_CHANGE: master has modified data element or read/write.
            s.int_elem_change = false;
            self.begin(bus, store, &mut s, &mut events);
            s.busy_at = false;
        }
        if s.ls && (s.int_end_rdbuf || s.int_end_mdt) {
            // 410B §4.2.4 INT_END_RDBUF: the read buffer is full; INT_END_MDT: the master
            // reports the end (last transmission). Take the words, empty the buffer.
            let count = usize::from(s.pointers.rddatpt.saturating_sub(BUF));
            let words = self.slot.read_buffer(bus, BUF, count);
            if self.transmission.received.len() < MAX_VARIABLE_WORDS {
                self.transmission.received.extend_from_slice(&words);
            }
            s.pointers.rddatpt = BUF;
            s.pointers.rddatlast = self.slot.step_last();
            if s.int_end_mdt {
                self.finish_write(bus, store, &mut s, &mut events);
            }
            s.int_end_rdbuf = false;
            s.int_end_mdt = false;
            s.busy_at = false;
        }
        if s.int_end_mdt {
            // 410B §4.2.4 INT_END_MDT on a read: nothing to check.
            s.int_end_mdt = false;
        }
        if s.int_end_wrbuf {
            // 410B §4.2.4 INT_END_WRBUF: the write buffer is exhausted; offer more.
            s.int_end_wrbuf = false;
            self.offer(bus, &mut s);
            s.busy_at = false;
        }
        if s.int_end_rdbuf {
            // A full read buffer outside a write: just empty it.
            s.int_end_rdbuf = false;
            s.pointers.rddatpt = BUF;
            s.busy_at = false;
        }
        if s.elem_mdt == 0 && s.hs_at == s.hs_mdt && !s.busy_at {
            // sercos-telegrams.md MDT element 000: "Service channel not active" — the
            // master closed the channel (the captures' master closes with element 0).
            self.open = None;
        }
        if s != before {
            self.slot.store(bus, s.to_words(), false);
        }
        events
    }

    /// A new transmission of ELEM / L/S.
    fn begin<B: SerconBus + ?Sized, S: IdnStore + ?Sized>(
        &mut self,
        bus: &mut B,
        store: &mut S,
        s: &mut ScSlave,
        events: &mut Vec<SlaveEvent>,
    ) {
        self.transmission = Transmission {
            element: s.elem & 7,

            ..Transmission::default()
        };
        // A new transmission starts without error (ERR_AT is the microprocessor's).
        s.err_at = false;
        let element = Element::from_bits(s.elem);
        if s.ls {
            s.pointers.rddatpt = BUF;
            s.pointers.rddatlast = self.slot.step_last();
            if element != Element::Idn && self.open.is_none() {
                // sercos-facts.md: 0001H service channel not open.
                self.refuse(bus, s, ServiceError::ServiceChannelNotOpen, events);
            }
            return;
        }
        let data = match self.open {
            Some(idn) => store.read_element(idn, element),
            // sercos-facts.md: 0001H service channel not open.
            None => Err(ServiceError::ServiceChannelNotOpen),
        };
        match data {
            Ok(words) => {
                if let Some(idn) = self.open {
                    events.push(SlaveEvent::ReadStarted { idn, element });
                }
                self.transmission.outgoing = words;
                s.pointers.wrdatpt = BUF;
                self.offer(bus, s);
            }
            Err(error) => self.refuse(bus, s, error, events),
        }
    }

    /// Puts the next words of the element into the write buffer. Past the end the master
    /// gets zeros (spec-notes "Driver service channel": a read longer than the element).
    fn offer<B: SerconBus + ?Sized>(&mut self, bus: &mut B, s: &mut ScSlave) {
        let capacity = self.slot.step_capacity();
        let t = &mut self.transmission;
        let rest = t.outgoing.get(t.offered..).unwrap_or_default();
        let chunk: Vec<u16> = if rest.is_empty() {
            vec![0; usize::from(self.slot.ninfo().count()).min(capacity)]
        } else {
            rest.iter().take(capacity).copied().collect()
        };
        t.offered = t.offered.saturating_add(chunk.len()).min(t.outgoing.len());
        self.slot.write_buffer(bus, BUF, &chunk);
        let count = u8::try_from(chunk.len()).unwrap_or(u8::MAX);
        s.pointers.wrdatpt = BUF;
        s.pointers.wrdatlast = BUF.saturating_add(count.saturating_sub(1));
    }

    /// The master's last write step arrived: apply the words.
    fn finish_write<B: SerconBus + ?Sized, S: IdnStore + ?Sized>(
        &mut self,
        bus: &mut B,
        store: &mut S,
        s: &mut ScSlave,
        events: &mut Vec<SlaveEvent>,
    ) {
        if s.err_at {
            // Already refused at the start of the transmission.
            return;
        }
        let element = Element::from_bits(self.transmission.element);
        let words = std::mem::take(&mut self.transmission.received);
        if words.len() >= MAX_VARIABLE_WORDS {
            self.refuse(bus, s, too_long(element), events);
            return;
        }
        if element == Element::Idn {
            // sercos-facts.md "IDNs": element 1 is the IDN; writing it opens the IDN. An IDN
            // the store does not have is refused (1001H, IDN not present).
            let idn = Idn::from_raw(words.first().copied().unwrap_or(0));
            self.open = None;
            match store.read_element(idn, Element::Idn) {
                Ok(_) => {
                    self.open = Some(idn);
                    events.push(SlaveEvent::Opened(idn));
                }
                Err(error) => self.refuse(bus, s, error, events),
            }
            return;
        }
        let Some(idn) = self.open else {
            self.refuse(bus, s, ServiceError::ServiceChannelNotOpen, events);
            return;
        };
        let words = without_padding(store, idn, element, words, self.slot.ninfo().count());
        match store.write_element(idn, element, &words) {
            Ok(()) => events.push(SlaveEvent::Written { idn, element }),
            Err(error) => self.refuse(bus, s, error, events),
        }
    }

    /// ERR_AT with the error code as the answer's info word (410B §4.2.4 slave word 0.2;
    /// the master's chip stores it at RDDATPT, spec-notes "Service containers").
    fn refuse<B: SerconBus + ?Sized>(
        &mut self,
        bus: &mut B,
        s: &mut ScSlave,
        error: ServiceError,
        events: &mut Vec<SlaveEvent>,
    ) {
        s.err_at = true;
        let code = error.code();
        let words = vec![code; usize::from(self.slot.ninfo().count())];
        self.slot.write_buffer(bus, BUF, &words);
        s.pointers.wrdatpt = BUF;
        s.pointers.wrdatlast = BUF;
        self.transmission.outgoing.clear();
        self.transmission.offered = 0;
        events.push(SlaveEvent::Refused {
            idn: self.open,
            element: Element::from_bits(self.transmission.element),
            error,
        });
    }
}

/// The "too long" code for `element` (sercos-facts.md "Service channel errors").
fn too_long(element: Element) -> ServiceError {
    match DescriptiveElement::from_number(element.bits()) {
        Some(described) => ServiceError::Element(described, ElementFault::TooLong),
        None if element == Element::OperationData => ServiceError::OperationDataTooLong,
        None => ServiceError::InvalidAccessToElement1,
    }
}

/// Drops the zeros the master's chip sent after the last word when a step carries more
/// than one info word (410B §4.2.4 NINFO: the last step of a write is filled up to NINFO
/// words, spec-notes "Service containers": positions after the last are sent as 0). Only
/// trailing zeros beyond the element's length, and at most NINFO − 1 of them, are dropped,
/// so data really too long still reaches the store (and is refused there).
fn without_padding<S: IdnStore + ?Sized>(
    store: &S,
    idn: Idn,
    element: Element,
    mut words: Vec<u16>,
    ninfo: u8,
) -> Vec<u16> {
    if ninfo <= 1 {
        return words;
    }
    // sercos-facts.md "IDNs": the length of each element; "Variable-length data".
    let variable = |words: &[u16]| 2 + usize::from(words.first().copied().unwrap_or(0)).div_ceil(2);
    let expected = match element {
        Element::ServiceChannelClosed | Element::Idn => 1,
        Element::Attribute => 2,
        Element::Name | Element::Unit => variable(&words),
        Element::Minimum | Element::Maximum | Element::OperationData => {
            let attribute = store.read_element(idn, Element::Attribute).ok().map(|w| {
                sercos_wire::attribute::Attribute::from_words([
                    w.first().copied().unwrap_or(0),
                    w.get(1).copied().unwrap_or(0),
                ])
            });
            match attribute.and_then(|a| a.fixed_words()) {
                Some(n) => n,
                None => variable(&words),
            }
        }
    };
    let mut dropped = 0;
    while words.len() > expected && dropped + 1 < usize::from(ninfo) && words.last() == Some(&0) {
        words.pop();
        dropped += 1;
    }
    words
}
