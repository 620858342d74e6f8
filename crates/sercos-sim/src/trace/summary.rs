//! The fields of a record that the log shows: kind, address, phase or control/status word,
//! FCS verdict and line error.

use sercos_wire::telegram::{
    AtPacket, ControlWord, MdtPacket, MstPacket, StatusWord, Telegram, TelegramKind, classify,
};

use super::record::{LineErrorKind, Seen, TraceRecord};

/// The FCS verdict on a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FcsVerdict {
    /// The FCS matched (ERRATA, Telegrams: ISO/IEC 3309 FCS over ADR and data).
    Ok,
    /// The FCS did not match.
    Bad {
        /// As received.
        received: u16,
        /// As computed over the received telegram bytes.
        computed: u16,
    },
    /// The frame broke before an FCS could be checked (abort, length errors).
    NotChecked,
}

/// The telegram fields the log shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Detail {
    /// An MST: its phase byte; bits 2–0 are the phase (sercos-telegrams.md, MST).
    Mst {
        /// The whole byte after ADR.
        phase_byte: u8,
    },
    /// An MDT: the data record at message-field offset 0 (the only record of a single-drive
    /// MDT, the first of a broadcast one; sercos-telegrams.md, Master Data Telegram).
    Mdt {
        /// Its control word.
        control_word: ControlWord,
        /// Its service info.
        service_info: u16,
    },
    /// An AT: its data record (sercos-telegrams.md, Amplifier Telegram).
    At {
        /// The status word.
        status_word: StatusWord,
        /// The service info.
        service_info: u16,
    },
    /// Bytes too short for the kind their origin and address give them.
    Malformed,
    /// A frame broken before its end: the bytes are not a whole telegram and are not decoded.
    Broken,
}

/// A record reduced to what the log prints.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Summary {
    /// MST, MDT or AT; `None` for a broken frame (or an empty one).
    pub kind: Option<TelegramKind>,
    /// The ADR byte, if any byte was received.
    pub address: Option<u8>,
    /// The decoded fields.
    pub detail: Detail,
    /// Bytes carried (telegram bytes, without FCS and flags).
    pub len: usize,
    /// The FCS verdict.
    pub fcs: FcsVerdict,
    /// The line error, if the frame was in error.
    pub line_error: Option<LineErrorKind>,
}

impl Summary {
    /// Decodes a record. Never fails: what cannot be decoded is [`Detail::Malformed`] or
    /// [`Detail::Broken`].
    pub fn of(record: &TraceRecord<'_>) -> Summary {
        let bytes = record.bytes();
        let line_error = record.line_error_kind();
        let fcs = match record.fcs_pair() {
            Some((received, computed)) if received == computed && line_error.is_none() => {
                FcsVerdict::Ok
            }
            Some((received, computed)) => FcsVerdict::Bad { received, computed },
            None => FcsVerdict::NotChecked,
        };
        // An FCS mismatch still delivers the whole telegram bytes, which can be decoded;
        // the other line errors leave a partial frame.
        let complete = matches!(
            record.seen,
            Seen::Telegram(_)
                | Seen::LineError {
                    error: sercos_wire::line::LineError::FcsMismatch { .. },
                    ..
                }
        );
        let kind = if complete {
            classify(bytes, record.origin).ok()
        } else {
            None
        };
        let detail = if complete {
            decode(bytes, record.origin)
        } else {
            Detail::Broken
        };
        Summary {
            kind,
            address: bytes.first().copied(),
            detail,
            len: bytes.len(),
            fcs,
            line_error,
        }
    }
}

/// The fields of whole telegram bytes.
fn decode(bytes: &[u8], origin: sercos_wire::telegram::Origin) -> Detail {
    match Telegram::new_checked(bytes, origin) {
        Ok(Telegram::Mst(packet)) => mst(&packet),
        Ok(Telegram::Mdt(packet)) => mdt(&packet),
        Ok(Telegram::At(packet)) => at(&packet),
        Err(_) => Detail::Malformed,
    }
}

/// sercos-telegrams.md, MST: one 8-bit word after ADR.
fn mst(packet: &MstPacket<&[u8]>) -> Detail {
    Detail::Mst {
        phase_byte: packet.phase_byte(),
    }
}

/// sercos-telegrams.md, MDT: the control word and service info open the data record.
fn mdt(packet: &MdtPacket<&[u8]>) -> Detail {
    match packet.record() {
        Ok(record) => Detail::Mdt {
            control_word: record.control_word(),
            service_info: record.service_info(),
        },
        Err(_) => Detail::Malformed,
    }
}

/// sercos-telegrams.md, AT: the status word and service info open the data record.
fn at(packet: &AtPacket<&[u8]>) -> Detail {
    Detail::At {
        status_word: packet.status_word(),
        service_info: packet.service_info(),
    }
}
