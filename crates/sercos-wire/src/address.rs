//! Telegram addresses (the ADR byte).
//!
//! sercos-telegrams.md, "ADR Target Addresses": address 0 is the "no station" address,
//! drive addresses are valid if greater than 0 and less than 255, and 255 is the broadcast
//! (global) address used by the MST and by the MDT in phases 3 and 4 (ERRATA.md, Telegrams:
//! "0 = no station, 1–254 = drives, 255 = broadcast").

use core::fmt;

/// Why a byte is not a [`DriveAddress`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
pub enum AddressError {
    /// The byte is 0, the "no station" address, not a drive.
    #[error("address 0 is the \"no station\" address, not a drive address (1-254)")]
    NoStation,
    /// The byte is 255, the broadcast address, not a drive.
    #[error("address 255 is the broadcast address, not a drive address (1-254)")]
    Broadcast,
}

/// A drive (slave) address, 1–254.
///
/// sercos-telegrams.md, "ADR Target Addresses": "The target addresses for the drives are valid
/// if greater than 0 and less than 255."
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(try_from = "u8", into = "u8")
)]
pub struct DriveAddress(u8);

impl DriveAddress {
    /// The lowest drive address.
    pub const MIN: DriveAddress = DriveAddress(1);
    /// The highest drive address.
    pub const MAX: DriveAddress = DriveAddress(254);

    /// Makes a drive address from a byte, `None` unless it is 1–254.
    pub const fn new(address: u8) -> Option<DriveAddress> {
        // sercos-telegrams.md, ADR: drive addresses are > 0 and < 255.
        match address {
            1..=254 => Some(DriveAddress(address)),
            _ => None,
        }
    }

    /// The address as a byte (1–254).
    pub const fn get(self) -> u8 {
        self.0
    }

    /// All drive addresses, 1 to 254, in order.
    pub fn all() -> impl Iterator<Item = DriveAddress> {
        (1..=254u8).map(DriveAddress)
    }
}

impl TryFrom<u8> for DriveAddress {
    type Error = AddressError;

    fn try_from(address: u8) -> Result<Self, Self::Error> {
        match Address::from(address) {
            Address::Drive(drive) => Ok(drive),
            Address::NoStation => Err(AddressError::NoStation),
            Address::Broadcast => Err(AddressError::Broadcast),
        }
    }
}

impl From<DriveAddress> for u8 {
    fn from(address: DriveAddress) -> u8 {
        address.0
    }
}

impl fmt::Display for DriveAddress {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.0, f)
    }
}

/// The ADR byte of a telegram: no station, one drive, or broadcast.
///
/// Every byte value is one of the three, so `From<u8>` is total and `u8::from` gives the byte
/// back unchanged.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(from = "u8", into = "u8")
)]
pub enum Address {
    /// Address 0, "no station" (sercos-telegrams.md, ADR: sometimes used to remove a drive from
    /// the ring logically).
    NoStation,
    /// A drive address, 1–254.
    Drive(DriveAddress),
    /// Address 255, all drives (MST; MDT in phases 3 and 4).
    Broadcast,
}

impl Address {
    /// The "no station" byte, 0.
    pub const NO_STATION_BYTE: u8 = 0;
    /// The broadcast byte, 255.
    pub const BROADCAST_BYTE: u8 = 255;

    /// Classifies an ADR byte.
    pub const fn from_byte(byte: u8) -> Address {
        // ERRATA.md, Telegrams: 0 = no station, 1–254 = drives, 255 = broadcast.
        match byte {
            Self::NO_STATION_BYTE => Address::NoStation,
            Self::BROADCAST_BYTE => Address::Broadcast,
            other => Address::Drive(DriveAddress(other)),
        }
    }

    /// The ADR byte.
    pub const fn to_byte(self) -> u8 {
        match self {
            Address::NoStation => Self::NO_STATION_BYTE,
            Address::Drive(drive) => drive.0,
            Address::Broadcast => Self::BROADCAST_BYTE,
        }
    }

    /// The drive address, if this is one.
    pub const fn drive(self) -> Option<DriveAddress> {
        match self {
            Address::Drive(drive) => Some(drive),
            _ => None,
        }
    }

    /// Whether this is the broadcast address 255.
    pub const fn is_broadcast(self) -> bool {
        matches!(self, Address::Broadcast)
    }
}

impl From<u8> for Address {
    fn from(byte: u8) -> Address {
        Address::from_byte(byte)
    }
}

impl From<Address> for u8 {
    fn from(address: Address) -> u8 {
        address.to_byte()
    }
}

impl From<DriveAddress> for Address {
    fn from(drive: DriveAddress) -> Address {
        Address::Drive(drive)
    }
}

impl TryFrom<Address> for DriveAddress {
    type Error = AddressError;

    fn try_from(address: Address) -> Result<Self, Self::Error> {
        DriveAddress::try_from(address.to_byte())
    }
}

/// Shows drives as their number, and `0 (no station)`, `255 (broadcast)`.
impl fmt::Display for Address {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Address::NoStation => f.write_str("0 (no station)"),
            Address::Drive(drive) => fmt::Display::fmt(drive, f),
            Address::Broadcast => f.write_str("255 (broadcast)"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_byte_round_trips() {
        // ERRATA.md, Telegrams: 0 = no station, 1–254 = drives, 255 = broadcast.
        for byte in 0..=255u8 {
            let address = Address::from(byte);
            assert_eq!(u8::from(address), byte);
            match byte {
                0 => assert_eq!(address, Address::NoStation),
                255 => assert_eq!(address, Address::Broadcast),
                _ => assert_eq!(address.drive().map(DriveAddress::get), Some(byte)),
            }
            assert_eq!(DriveAddress::new(byte).is_some(), (1..=254).contains(&byte));
        }
    }

    #[test]
    fn drive_address_rejects_0_and_255_with_reason() {
        // sercos-telegrams.md, ADR: drive addresses are > 0 and < 255.
        assert_eq!(DriveAddress::try_from(0), Err(AddressError::NoStation));
        assert_eq!(DriveAddress::try_from(255), Err(AddressError::Broadcast));
        assert_eq!(DriveAddress::try_from(254).map(u8::from), Ok(254));
        assert_eq!(DriveAddress::all().count(), 254);
    }
}
