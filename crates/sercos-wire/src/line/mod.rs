//! Line coding of SERCOS II telegrams (SERCON410B datasheet §1, §2; `ERRATA.md`, Telegrams).
//!
//! A telegram on the line is an HDLC-style frame: flag 7EH, the telegram bytes (ADR and data),
//! the 16-bit FCS, then flag 7EH. Between the flags a 0 is inserted after every five
//! consecutive 1s; bytes go least significant bit first. The bit stream is then NRZI-coded
//! (0 = change of level, 1 = no change) or, with RXDNRZ / TxDNRZ, NRZ-coded, and the light
//! polarity (POLRXD / POLTXD) decides which pin level means "light on".
//!
//! Conventions used by every type here:
//!
//! * **Telegram bytes** are the ADR byte followed by the data, without FCS and flags; the line
//!   layer adds and strips FCS and flags.
//! * **Line bits** are pin levels, one per bit time, packed most significant bit first in each
//!   byte with an explicit bit length ([`Bits`], [`BitVec`], [`BitWriter`]); positions are
//!   absolute bit indices in the stream since the coder was created.
//!
//! Two implementations live side by side and are proven equal by property tests: the fast,
//! table-driven [`Encoder`] / [`Decoder`] and the plain bit-serial
//! [`reference`](mod@reference) coder (with the `alloc` feature).

mod bits;
mod capture;
mod config;
mod decoder;
mod encoder;
mod error;
mod fcs;
mod frame;
mod nrzi;
#[cfg(feature = "alloc")]
pub mod reference;
mod timing;

#[cfg(feature = "alloc")]
pub use bits::BitVec;
pub use bits::{BitSink, BitWriter, Bits, SinkFull};
pub use capture::{CaptureError, CaptureFile};
pub use config::{Coding, LineConfig, Polarity};
pub use decoder::Decoder;
#[cfg(feature = "alloc")]
pub use decoder::decode_all;
pub use encoder::{Encoder, frame_bit_len};
pub use error::{EncodeError, LineError};
pub use fcs::{FCS_LEN, fcs};
#[cfg(feature = "alloc")]
pub use frame::OwnedDecoded;
pub use frame::{Decoded, Frame};
pub use timing::frame_duration;

/// Flag that opens and closes every frame (ERRATA, Telegrams: BOF / EOF 7EH).
pub const FLAG: u8 = 0x7E;

/// Line bits of one flag.
pub const FLAG_BITS: u64 = 8;

/// Fewest bytes between the flags that the decoder accepts as a telegram: ADR and the two FCS
/// bytes (ERRATA, Telegrams: frame = ADR, data, FCS; see `docs/spec-notes.md`, "Line coding").
pub const MIN_FRAME_BYTES: usize = 1 + FCS_LEN;

/// Most bytes between the flags (telegram bytes and FCS) that the decoder accepts.
///
/// The SERCON816 dual-port RAM holds 2048 words (4096 bytes), so no telegram the chip sends or
/// stores can be longer (816 spec, RAM size; see `docs/spec-notes.md`, "Line coding").
pub const MAX_FRAME_BYTES: usize = 4096;

/// Most telegram bytes (ADR and data, without FCS) the [`Encoder`] accepts.
pub const MAX_TELEGRAM_BYTES: usize = MAX_FRAME_BYTES - FCS_LEN;
