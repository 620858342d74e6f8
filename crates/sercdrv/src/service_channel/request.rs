//! What the master asks of a drive's service channel, and what it gets back.

use sercos_wire::address::DriveAddress;
use sercos_wire::attribute::Attribute;
use sercos_wire::idn::{Element, Idn};

use super::error::ServiceChannelError;

/// How many words a read of an element takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ReadLength {
    /// As the element says: element 1 one word, element 3 two words, elements 2 and 4
    /// variable (text), elements 5–7 as the attribute (element 3) says, which is read first
    /// as the captures' master does (`sercon capture transcript`: "attribute (2 steps)"
    /// before "operation data").
    #[default]
    Auto,
    /// Exactly this many words (e.g. 1 for a procedure command's status).
    Words(u16),
    /// Variable-length data: the two length words first, then the current length in bytes
    /// (sercos-facts.md, "Variable-length data").
    Variable,
}

/// One service-channel transaction with one drive.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Request {
    /// Read element `element` of `idn`.
    Read {
        /// The IDN opened with element 1.
        idn: Idn,
        /// The data block element read (1–7).
        element: Element,
        /// How many words.
        length: ReadLength,
    },
    /// Write `words` to element `element` of `idn` (variable-length data with its two
    /// length words).
    Write {
        /// The IDN opened with element 1.
        idn: Idn,
        /// The data block element written (1–7).
        element: Element,
        /// The service-channel words.
        words: Vec<u16>,
    },
}

/// Procedure command value "set and enable" (sercos-facts.md, "Procedure commands").
pub const COMMAND_SET_AND_ENABLE: u16 = 3;
/// Procedure command value "cancel" (sercos-facts.md, "Procedure commands").
pub const COMMAND_CANCEL: u16 = 0;

impl Request {
    /// Reads `element` of `idn`, its length found as [`ReadLength::Auto`] says.
    pub fn read(idn: Idn, element: Element) -> Request {
        Request::Read {
            idn,
            element,
            length: ReadLength::Auto,
        }
    }

    /// Reads `words` words of `element` of `idn`.
    pub fn read_words(idn: Idn, element: Element, words: u16) -> Request {
        Request::Read {
            idn,
            element,
            length: ReadLength::Words(words),
        }
    }

    /// Reads the operation data (element 7) of `idn`.
    pub fn read_value(idn: Idn) -> Request {
        Request::read(idn, Element::OperationData)
    }

    /// Writes `words` to `element` of `idn`.
    pub fn write(idn: Idn, element: Element, words: Vec<u16>) -> Request {
        Request::Write {
            idn,
            element,
            words,
        }
    }

    /// Writes the operation data (element 7) of `idn`.
    pub fn write_value(idn: Idn, words: Vec<u16>) -> Request {
        Request::write(idn, Element::OperationData, words)
    }

    /// Writes a list of IDNs (or other 2-byte items) to the operation data of `idn`:
    /// current and maximum length in bytes, then the items, as the captures' writes of
    /// S-0-0016 show (sercos-facts.md, "Variable-length data"). The maximum length word
    /// is set to the current length (the drive keeps its own maximum).
    pub fn write_list(idn: Idn, items: &[u16]) -> Request {
        let bytes = u16::try_from(items.len().saturating_mul(2)).unwrap_or(u16::MAX);
        let mut words = Vec::with_capacity(items.len().saturating_add(2));
        words.push(bytes);
        words.push(bytes);
        words.extend_from_slice(items);
        Request::write_value(idn, words)
    }

    /// Starts procedure command `idn`: writes 3, "set and enable" (sercos-facts.md,
    /// "Procedure commands").
    pub fn set_command(idn: Idn) -> Request {
        Request::write_value(idn, vec![COMMAND_SET_AND_ENABLE])
    }

    /// Cancels (or acknowledges) procedure command `idn`: writes 0 (sercos-facts.md,
    /// "Procedure commands").
    pub fn cancel_command(idn: Idn) -> Request {
        Request::write_value(idn, vec![COMMAND_CANCEL])
    }

    /// Polls procedure command `idn`: reads its one-word status (element 7).
    pub fn command_status(idn: Idn) -> Request {
        Request::read_words(idn, Element::OperationData, 1)
    }

    /// The IDN this request opens.
    pub fn idn(&self) -> Idn {
        match self {
            Request::Read { idn, .. } | Request::Write { idn, .. } => *idn,
        }
    }

    /// The element it reads or writes.
    pub fn element(&self) -> Element {
        match self {
            Request::Read { element, .. } | Request::Write { element, .. } => *element,
        }
    }
}

/// What a successful request returns.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Response {
    /// Words read (with the two length words for variable-length data); empty for writes.
    pub words: Vec<u16>,
    /// The attribute, when the read fetched it first ([`ReadLength::Auto`] on elements
    /// 5–7) or the element read was the attribute; decode the words with it.
    pub attribute: Option<Attribute>,
}

/// Names a submitted request; completions carry it back.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Ticket(pub u64);

/// A finished request.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Completion {
    /// The ticket [`submit`](super::ServiceChannelMaster::submit) returned.
    pub ticket: Ticket,
    /// The drive.
    pub drive: DriveAddress,
    /// The request's IDN.
    pub idn: Idn,
    /// The request's element.
    pub element: Element,
    /// The data, or what went wrong (naming drive, IDN and the element of the failing step).
    pub result: Result<Response, ServiceChannelError>,
}
