//! One request carried out through one master-mode service container, stage by stage.
//!
//! The sequence is the captures' master's (`sercon capture transcript`): open the IDN by
//! writing element 1, read the attribute (element 3, two words) before operation data whose
//! length it gives, read or write the element, and close by leaving element 0 in the MDT.
//! Variable-length data is read as the two length words first (SETEND = 0) and then the
//! current length (SETEND = 1) (sercos-facts.md, "Variable-length data"; spec-notes
//! "Service containers", END_MDT and SETEND). Data longer than the buffer goes through it in
//! chunks: the chip stops at the buffer's end with INT_END_WRBUF / INT_END_RDBUF and M_BUSY,
//! the driver refills or empties the buffer and clears M_BUSY (410B §4.2.4).

use sercon_regs::SerconBus;
use sercon_regs::ram::service::ScMaster;
use sercos_wire::attribute::Attribute;
use sercos_wire::idn::{Element, Idn};
use sercos_wire::service_error::ServiceError;

use super::container::{BUF, ContainerSlot};
use super::error::ErrorKind;
use super::request::{ReadLength, Request, Response};

/// Words a variable-length element can hold: the two length words and 65 535 bytes.
pub(super) const MAX_VARIABLE_WORDS: usize = 2 + 0xFFFF / 2 + 1;

/// What to do when a read stage has all its words.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum AfterRead {
    /// The request is done.
    Finish,
    /// These were the two length words: read the current length next.
    Rest,
    /// This was the attribute: read `Element` with the length it gives.
    Attribute(Element),
}

/// The step sequence a transfer is in.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Stage {
    /// Writing `words` to `element`.
    Write {
        element: Element,
        words: Vec<u16>,
        /// Where the next stage goes after the write (`None`: finish).
        then: Option<Box<Stage>>,
    },
    /// Reading `total` words of `element`.
    Read {
        element: Element,
        total: usize,
        /// SETEND on the final chunk.
        end: bool,
        then: AfterRead,
    },
}

/// How a container event left the transfer.
#[derive(Debug)]
pub(super) enum Progress {
    /// Steps still run.
    Running,
    /// Done: the data, or the element of the failing step and what went wrong.
    Done(Result<Response, (Element, ErrorKind)>),
}

/// A request in a container.
#[derive(Debug)]
pub(super) struct Transfer {
    stage: Stage,
    /// Words of the present stage already through the buffer.
    done: usize,
    /// Words loaded into the buffer for the present chunk.
    chunk: usize,
    /// Data read so far (not the attribute read first).
    words: Vec<u16>,
    attribute: Option<Attribute>,
    /// The element the request reads or writes.
    target: Element,
    /// Words read for the length words of variable data (a whole step).
    header: usize,
    /// Words variable data has in all (length words and current length), once known.
    expected: Option<usize>,
}

/// The stage that reads `element` as `length` says (after the IDN is open).
fn read_stage(element: Element, length: ReadLength, header: usize) -> Result<Stage, ErrorKind> {
    let (total, then) = match (length, element) {
        (_, Element::ServiceChannelClosed) => {
            return Err(ErrorKind::InvalidRequest("element 0 has no data"));
        }
        (ReadLength::Words(0), _) => {
            return Err(ErrorKind::InvalidRequest("a read of zero words"));
        }
        (ReadLength::Words(n), _) => (usize::from(n), AfterRead::Finish),
        (ReadLength::Variable, _) => (header, AfterRead::Rest),
        // sercos-facts.md "IDNs": element 1 is the IDN (one word), 3 the attribute (32 bit),
        // 2 and 4 text (variable-length data).
        (ReadLength::Auto, Element::Idn) => (1, AfterRead::Finish),
        (ReadLength::Auto, Element::Attribute) => (2, AfterRead::Finish),
        (ReadLength::Auto, Element::Name | Element::Unit) => (header, AfterRead::Rest),
        (ReadLength::Auto, Element::Minimum | Element::Maximum | Element::OperationData) => {
            return Ok(Stage::Read {
                element: Element::Attribute,
                total: 2,
                end: true,
                then: AfterRead::Attribute(element),
            });
        }
    };
    Ok(Stage::Read {
        element,
        total,
        // 410B §4.2.4 SETEND; the length words of variable data are read without END
        // (spec-notes "Service containers").
        end: then != AfterRead::Rest,
        then,
    })
}

impl Transfer {
    /// The stages of `request`: open the IDN (write element 1), then the read or write.
    ///
    /// With `ninfo` info words per step the length words are read as one whole step
    /// (`max(2, NINFO)` words): the slave's chip moves on by NINFO words per step, so a
    /// read continued in the same transmission must stop on a step boundary (spec-notes
    /// "Driver service channel").
    pub(super) fn plan(request: &Request, ninfo: u8) -> Result<Transfer, ErrorKind> {
        let header = usize::from(ninfo).max(2);
        let (idn, body) = match request {
            Request::Read {
                idn,
                element,
                length,
            } => (*idn, read_stage(*element, *length, header)?),
            Request::Write {
                idn,
                element,
                words,
            } => {
                if *element == Element::ServiceChannelClosed {
                    return Err(ErrorKind::InvalidRequest("element 0 can't be written"));
                }
                if words.is_empty() {
                    return Err(ErrorKind::InvalidRequest("a write of no words"));
                }
                if words.len() > MAX_VARIABLE_WORDS {
                    return Err(ErrorKind::TooLong(words.len()));
                }
                (
                    *idn,
                    Stage::Write {
                        element: *element,
                        words: words.clone(),
                        then: None,
                    },
                )
            }
        };
        Ok(Transfer {
            stage: open_stage(idn, body),
            done: 0,
            chunk: 0,
            words: Vec::new(),
            attribute: None,
            target: request.element(),
            header,
            expected: None,
        })
    }

    /// The element of the present stage.
    pub(super) fn element(&self) -> Element {
        match &self.stage {
            Stage::Write { element, .. } | Stage::Read { element, .. } => *element,
        }
    }

    /// Sets up the container for the present stage's next chunk and releases it
    /// (M_BUSY = 0). `m` is what was just read from the container.
    pub(super) fn load<B: SerconBus + ?Sized>(
        &mut self,
        slot: &ContainerSlot,
        bus: &mut B,
        mut m: ScMaster,
    ) {
        let capacity = slot.step_capacity();
        let last_of = |count: usize| {
            // count ≤ buffer_words ≤ 251: BUF + count − 1 ≤ 255.
            let count = u8::try_from(count).unwrap_or(u8::MAX);
            BUF.saturating_add(count.saturating_sub(1))
        };
        match &self.stage {
            Stage::Write { element, words, .. } => {
                let rest = words.get(self.done..).unwrap_or_default();
                let chunk = rest.len().min(capacity);
                slot.write_buffer(bus, BUF, rest.get(..chunk).unwrap_or_default());
                // 410B §4.2.4 master table: ELEM_MDT, L/S_MDT = 1 (write), WRDATPT/WRDATLAST
                // around the words to send; SETEND on the chunk that holds the last word.
                m.elem_mdt = element.bits();
                m.ls_mdt = true;
                m.setend = self.done + chunk >= words.len();
                m.pointers.wrdatpt = BUF;
                m.pointers.wrdatlast = last_of(chunk);
                // An error code arrives at RDDATPT (spec-notes "Service containers", INT_ERR).
                m.pointers.rddatpt = BUF;
                m.pointers.rddatlast = slot.buffer_last();
                self.chunk = chunk;
            }
            Stage::Read {
                element,
                total,
                end,
                ..
            } => {
                let chunk = total.saturating_sub(self.done).min(capacity);
                // 410B §4.2.4: L/S_MDT = 0 (read), RDDATPT/RDDATLAST around the words to take.
                m.elem_mdt = element.bits();
                m.ls_mdt = false;
                m.setend = *end && self.done + chunk >= *total;
                m.pointers.rddatpt = BUF;
                m.pointers.rddatlast = last_of(chunk);
                m.pointers.wrdatpt = BUF;
                m.pointers.wrdatlast = BUF;
                self.chunk = chunk;
            }
        }
        m.ninfo_write = slot.ninfo();
        clear_interrupts(&mut m);
        // 410B §4.2.4 M_BUSY: the container no longer waits for the microprocessor.
        m.m_busy = false;
        slot.store(bus, m.to_words(), true);
    }

    /// Handles the container's state `m` after the chip set M_BUSY; `m` is what was just
    /// read. Loads the next chunk or stage when there is one.
    pub(super) fn on_event<B: SerconBus + ?Sized>(
        &mut self,
        slot: &ContainerSlot,
        bus: &mut B,
        m: ScMaster,
    ) -> Progress {
        let element = self.element();
        // 410B §4.2.4: the interrupt bits say why the container waits (M_BUSY).
        if m.int_sc_err {
            return Progress::Done(Err((element, ErrorKind::ProtocolError)));
        }
        if m.int_hs_timeout {
            return Progress::Done(Err((element, ErrorKind::HandshakeTimeout)));
        }
        if m.int_busy_timeout {
            return Progress::Done(Err((element, ErrorKind::BusyTimeout)));
        }
        if m.int_err {
            // 410B §4.2.4 INT_ERR: the error code is in the read buffer at RDDATPT
            // (spec-notes "Service containers").
            let code = slot.buffer_word(bus, m.pointers.rddatpt);
            let error = ServiceError::from_code(code);
            return Progress::Done(Err((element, ErrorKind::Drive(error))));
        }
        let stage_over = match &self.stage {
            Stage::Write { words, .. } if m.int_end_wrbuf => {
                // 410B §4.2.4 INT_END_WRBUF: the chunk went out.
                self.done += self.chunk;
                self.done >= words.len()
            }
            Stage::Read { total, then, .. } if m.int_end_rdbuf => {
                // 410B §4.2.4 INT_END_RDBUF: the chunk is in the read buffer.
                let got = slot.read_buffer(bus, BUF, self.chunk);
                if matches!(then, AfterRead::Attribute(_)) {
                    let (low, high) = (
                        got.first().copied().unwrap_or(0),
                        got.get(1).copied().unwrap_or(0),
                    );
                    self.attribute = Some(Attribute::from_words([low, high]));
                } else {
                    self.words.extend_from_slice(&got);
                }
                self.done += self.chunk;
                self.done >= *total
            }
            // M_BUSY with no reason for this stage: wait for the deadline.
            _ => return Progress::Running,
        };
        if !stage_over {
            self.load(slot, bus, m);
            return Progress::Running;
        }
        match self.next_stage() {
            Ok(Some(stage)) => {
                self.stage = stage;
                self.done = 0;
                self.load(slot, bus, m);
                Progress::Running
            }
            Ok(None) => Progress::Done(Ok(self.response())),
            Err(kind) => Progress::Done(Err((element, kind))),
        }
    }

    fn next_stage(&mut self) -> Result<Option<Stage>, ErrorKind> {
        let stage = std::mem::replace(
            &mut self.stage,
            Stage::Read {
                element: Element::ServiceChannelClosed,
                total: 0,
                end: false,
                then: AfterRead::Finish,
            },
        );
        match stage {
            Stage::Write { then, .. } => Ok(then.map(|next| *next)),
            Stage::Read { then, element, .. } => match then {
                AfterRead::Finish => Ok(None),
                AfterRead::Rest => {
                    // sercos-facts.md "Variable-length data": the first word is the
                    // current length in bytes.
                    let bytes = usize::from(self.words.first().copied().unwrap_or(0));
                    let expected = 2 + bytes.div_ceil(2);
                    self.expected = Some(expected);
                    let rest = expected.saturating_sub(self.words.len());
                    if rest == 0 {
                        return Ok(None);
                    }
                    Ok(Some(Stage::Read {
                        element,
                        total: rest,
                        end: true,
                        then: AfterRead::Finish,
                    }))
                }
                AfterRead::Attribute(target) => {
                    let attribute = self.attribute.unwrap_or_default();
                    // sercos-facts.md "IDNs": attribute bits 18-16, data length.
                    if attribute.data_length().is_variable() {
                        Ok(Some(Stage::Read {
                            element: target,
                            total: self.header,
                            end: false,
                            then: AfterRead::Rest,
                        }))
                    } else if let Some(words) = attribute.fixed_words() {
                        Ok(Some(Stage::Read {
                            element: target,
                            total: words,
                            end: true,
                            then: AfterRead::Finish,
                        }))
                    } else {
                        Err(ErrorKind::NoDataLength(attribute.raw()))
                    }
                }
            },
        }
    }

    fn response(&mut self) -> Response {
        let mut words = std::mem::take(&mut self.words);
        if let Some(expected) = self.expected {
            // Words of the last whole step after the variable data's end.
            words.truncate(expected);
        }
        let attribute = self.attribute.or_else(|| {
            // The element read was the attribute itself.
            (self.target == Element::Attribute && words.len() == 2).then(|| {
                Attribute::from_words([
                    words.first().copied().unwrap_or(0),
                    words.get(1).copied().unwrap_or(0),
                ])
            })
        });
        Response { words, attribute }
    }
}

/// Opening `idn`: a write of element 1 with the IDN (sercos-facts.md "IDNs": element 1 is
/// the IDN; the captures' master opens every transaction so), then `body`.
fn open_stage(idn: Idn, body: Stage) -> Stage {
    Stage::Write {
        element: Element::Idn,
        words: vec![idn.raw()],
        then: Some(Box::new(body)),
    }
}

/// Clears every interrupt bit of a master container (410B §4.2.4 words 0 and 4).
pub(super) fn clear_interrupts(m: &mut ScMaster) {
    m.int_err = false;
    m.int_end_wrbuf = false;
    m.int_end_rdbuf = false;
    m.int_sc_err = false;
    m.int_hs_timeout = false;
    m.int_busy_timeout = false;
    m.int_cmd = false;
}

/// Leaves the container idle: element 0 ("service channel not active", sercos-telegrams.md
/// MDT control word bits 5–3) and M_BUSY = 1, so no step starts (410B §4.2.4).
pub(super) fn close<B: SerconBus + ?Sized>(slot: &ContainerSlot, bus: &mut B, mut m: ScMaster) {
    m.elem_mdt = Element::ServiceChannelClosed.bits();
    m.ls_mdt = false;
    m.setend = false;
    m.m_busy = true;
    clear_interrupts(&mut m);
    slot.store(bus, m.to_words(), true);
}
