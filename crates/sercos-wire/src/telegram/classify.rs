//! Telling MST, MDT and AT apart, and the enums over all three.
//!
//! sercos-telegrams.md, ADR table: the master sends the MST (ADR 255, one data byte) and the
//! MDT; slaves send ATs. Given who sent the bytes: master + ADR 255 + exactly one data byte is
//! an MST, anything else from the master an MDT (its shortest form, ADR and a four-byte record,
//! is longer than an MST, so the two cannot be confused), and everything from a slave an AT.

use core::fmt;

use crate::address::Address;

use super::TelegramError;
use super::at::{AtPacket, AtRepr};
use super::field;
use super::mdt::{MdtPacket, MdtRepr};
use super::mst::{MstPacket, MstRepr};

/// Who sent the telegram bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Origin {
    /// The master (MST, MDT).
    Master,
    /// A slave (drive): AT.
    Slave,
}

/// The three telegram kinds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum TelegramKind {
    /// Master synchronisation telegram.
    #[doc(alias = "master synchronization telegram")]
    Mst,
    /// Master data telegram.
    Mdt,
    /// Amplifier telegram (drive telegram).
    At,
}

impl TelegramKind {
    /// Who sends this kind.
    pub const fn origin(self) -> Origin {
        match self {
            TelegramKind::Mst | TelegramKind::Mdt => Origin::Master,
            TelegramKind::At => Origin::Slave,
        }
    }
}

impl fmt::Display for TelegramKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            TelegramKind::Mst => "MST",
            TelegramKind::Mdt => "MDT",
            TelegramKind::At => "AT",
        })
    }
}

/// Classifies telegram bytes (ADR and message field) by who sent them: master + ADR 255 + one
/// data byte → MST, master otherwise → MDT, slave → AT. Only the empty buffer is an error;
/// the lengths are checked by the views.
pub fn classify(bytes: &[u8], origin: Origin) -> Result<TelegramKind, TelegramError> {
    let Some(&adr) = bytes.get(field::ADR) else {
        return Err(TelegramError::Truncated {
            what: "telegram",
            needed: 1,
            got: 0,
        });
    };
    Ok(match origin {
        // sercos-telegrams.md, MST: ADR 255 and one 8-bit word.
        Origin::Master if Address::from(adr).is_broadcast() && bytes.len() == field::MST_LEN => {
            TelegramKind::Mst
        }
        Origin::Master => TelegramKind::Mdt,
        Origin::Slave => TelegramKind::At,
    })
}

/// A view of any telegram.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Telegram<T: AsRef<[u8]>> {
    /// An MST.
    Mst(MstPacket<T>),
    /// An MDT.
    Mdt(MdtPacket<T>),
    /// An AT.
    At(AtPacket<T>),
}

impl<T: AsRef<[u8]>> Telegram<T> {
    /// Classifies the bytes (see [`classify`]) and wraps them in the checked view.
    pub fn new_checked(buffer: T, origin: Origin) -> Result<Telegram<T>, TelegramError> {
        Ok(match classify(buffer.as_ref(), origin)? {
            TelegramKind::Mst => Telegram::Mst(MstPacket::new_checked(buffer)?),
            TelegramKind::Mdt => Telegram::Mdt(MdtPacket::new_checked(buffer)?),
            TelegramKind::At => Telegram::At(AtPacket::new_checked(buffer)?),
        })
    }

    /// The kind.
    pub fn kind(&self) -> TelegramKind {
        match self {
            Telegram::Mst(_) => TelegramKind::Mst,
            Telegram::Mdt(_) => TelegramKind::Mdt,
            Telegram::At(_) => TelegramKind::At,
        }
    }

    /// The ADR byte.
    pub fn address(&self) -> Address {
        match self {
            Telegram::Mst(packet) => packet.address(),
            Telegram::Mdt(packet) => packet.address(),
            Telegram::At(packet) => packet.address(),
        }
    }

    /// The wrapped buffer.
    pub fn into_inner(self) -> T {
        match self {
            Telegram::Mst(packet) => packet.into_inner(),
            Telegram::Mdt(packet) => packet.into_inner(),
            Telegram::At(packet) => packet.into_inner(),
        }
    }
}

/// Any telegram, parsed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TelegramRepr<'a> {
    /// An MST.
    Mst(MstRepr),
    /// An MDT.
    Mdt(MdtRepr<'a>),
    /// An AT.
    At(AtRepr<'a>),
}

impl<'a> TelegramRepr<'a> {
    /// Parses a view.
    pub fn parse<T: AsRef<[u8]> + ?Sized>(
        telegram: &Telegram<&'a T>,
    ) -> Result<TelegramRepr<'a>, TelegramError> {
        Ok(match telegram {
            Telegram::Mst(packet) => TelegramRepr::Mst(MstRepr::parse(packet)?),
            Telegram::Mdt(packet) => TelegramRepr::Mdt(MdtRepr::parse(packet)?),
            Telegram::At(packet) => TelegramRepr::At(AtRepr::parse(packet)?),
        })
    }

    /// Classifies and parses telegram bytes in one step.
    pub fn parse_bytes(bytes: &'a [u8], origin: Origin) -> Result<TelegramRepr<'a>, TelegramError> {
        TelegramRepr::parse(&Telegram::new_checked(bytes, origin)?)
    }

    /// The kind.
    pub fn kind(&self) -> TelegramKind {
        match self {
            TelegramRepr::Mst(_) => TelegramKind::Mst,
            TelegramRepr::Mdt(_) => TelegramKind::Mdt,
            TelegramRepr::At(_) => TelegramKind::At,
        }
    }

    /// The ADR byte.
    pub fn address(&self) -> Address {
        match self {
            TelegramRepr::Mst(_) => Address::Broadcast,
            TelegramRepr::Mdt(mdt) => mdt.address(),
            TelegramRepr::At(at) => Address::Drive(at.address),
        }
    }

    /// The telegram length in bytes (ADR and message field).
    pub fn buffer_len(&self) -> usize {
        match self {
            TelegramRepr::Mst(mst) => mst.buffer_len(),
            TelegramRepr::Mdt(mdt) => mdt.buffer_len(),
            TelegramRepr::At(at) => at.buffer_len(),
        }
    }

    /// Writes the telegram bytes into a buffer of exactly [`buffer_len`](Self::buffer_len)
    /// bytes.
    pub fn emit(&self, buffer: &mut [u8]) -> Result<(), TelegramError> {
        match self {
            TelegramRepr::Mst(mst) => mst.emit(&mut MstPacket::new_unchecked(buffer)),
            TelegramRepr::Mdt(mdt) => mdt.emit(&mut MdtPacket::new_unchecked(buffer)),
            TelegramRepr::At(at) => at.emit(&mut AtPacket::new_unchecked(buffer)),
        }
    }

    /// The telegram bytes in a new vector.
    #[cfg(feature = "alloc")]
    pub fn to_vec(&self) -> alloc::vec::Vec<u8> {
        let mut bytes = alloc::vec![0; self.buffer_len()];
        // The buffer has exactly buffer_len() bytes, the only condition emit checks.
        let _ = self.emit(&mut bytes);
        bytes
    }
}
