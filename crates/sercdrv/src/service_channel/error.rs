//! Why a service-channel request failed, naming the drive, the IDN and the element.

use sercos_wire::address::DriveAddress;
use sercos_wire::idn::{Element, Idn};
use sercos_wire::service_error::ServiceError;

/// What went wrong.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
pub enum ErrorKind {
    /// The drive answered with ERR_AT and this error code (410B §4.2.4 INT_ERR; codes from
    /// sercos-facts.md, "Service channel errors").
    #[error("{0}")]
    Drive(ServiceError),
    /// The chip counted HS_TIMEOUT cycles without an answer (410B §4.1 0DH, §4.2.4
    /// INT_HS_TIMEOUT).
    #[error("handshake timeout: the drive does not answer")]
    HandshakeTimeout,
    /// The chip counted BUSY_TIMEOUT cycles of BUSY (410B §4.1 0DH, §4.2.4
    /// INT_BUSY_TIMEOUT).
    #[error("busy timeout: the drive stays busy")]
    BusyTimeout,
    /// The slave broke the handshake (410B §4.2.4 INT_SC_ERR).
    #[error("service channel protocol error")]
    ProtocolError,
    /// The driver's own time limit for the request ran out.
    #[error("no answer within the time limit")]
    Timeout,
    /// The request can't be carried out as asked.
    #[error("invalid request: {0}")]
    InvalidRequest(&'static str),
    /// The attribute read before the data gives no length (data length 0, reserved).
    #[error("attribute {0:#010X} gives no data length")]
    NoDataLength(u32),
    /// Variable-length data longer than the service channel's length word can say.
    #[error("data of {0} words is too long for the service channel")]
    TooLong(usize),
}

/// A failed service-channel request.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[error("drive {}, {idn} {}: {kind}", drive.get(), element.name())]
pub struct ServiceChannelError {
    /// The drive.
    pub drive: DriveAddress,
    /// The IDN of the request.
    pub idn: Idn,
    /// The element of the step that failed (element 1 while opening the IDN, element 3
    /// while reading the attribute first, else the requested element).
    pub element: Element,
    /// What went wrong.
    pub kind: ErrorKind,
}

impl ServiceChannelError {
    /// The drive's error code, when the drive refused.
    pub fn service_error(&self) -> Option<ServiceError> {
        match self.kind {
            ErrorKind::Drive(error) => Some(error),
            _ => None,
        }
    }
}
