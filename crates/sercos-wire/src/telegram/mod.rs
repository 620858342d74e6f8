//! Telegram formats: MST, MDT, AT, data records, control and status words.
//!
//! Views (`*Packet`, [`DataRecord`]) wrap telegram bytes without copying; representations
//! (`*Repr`) are the parsed values with `parse`, `emit` and `buffer_len`, in the manner of
//! smoltcp's `wire` module. "Telegram bytes" are the ADR byte followed by the message field,
//! as they are between the flags, without FCS and flags (the line layer adds and strips
//! those). 16-bit words are little endian (ERRATA.md, Telegrams).
//!
//! Classify bytes with [`classify`] or [`Telegram::new_checked`], given their [`Origin`].
//!
//! ```
//! use sercos_wire::telegram::{CommunicationPhase, Origin, TelegramRepr};
//!
//! let repr = TelegramRepr::parse_bytes(&[0xFF, 0x02], Origin::Master)?;
//! let TelegramRepr::Mst(mst) = repr else { panic!("not an MST") };
//! assert_eq!(mst.phase()?, CommunicationPhase::Phase2);
//! # Ok::<(), sercos_wire::telegram::TelegramError>(())
//! ```

mod at;
mod classify;
mod control_word;
mod data_record;
mod error;
mod field;
mod mdt;
mod mst;
mod operation_mode;
mod status_word;
mod word_format;

pub use at::{AtPacket, AtRepr};
pub use classify::{Origin, Telegram, TelegramKind, TelegramRepr, classify};
pub use control_word::ControlWord;
pub use data_record::{AtRecordRepr, DataRecord, DataRecordRepr, MdtRecordRepr};
pub use error::TelegramError;
pub use mdt::{MdtPacket, MdtRepr};
pub use mst::{CommunicationPhase, MstPacket, MstRepr};
pub use operation_mode::OperationMode;
pub use status_word::{ReadyToOperate, StatusWord};
