//! The MDT control word, the first word of each data record in an MDT.
//!
//! Bit layout from sercos-telegrams.md, "Master Data Telegram", control word table.

use core::fmt;

use crate::idn::Element;

use super::operation_mode::OperationMode;
use super::word_format::NameList;

/// The 16-bit MDT control word. Every `u16` is representable; reserved bits 12–11 are kept.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(from = "u16", into = "u16")
)]
pub struct ControlWord(u16);

const fn with_bit(raw: u16, mask: u16, set: bool) -> u16 {
    if set { raw | mask } else { raw & !mask }
}

impl ControlWord {
    /// Bit 15: 0 drive OFF, 1 drive ON (sercos-telegrams.md, MDT control word bit 15).
    pub const DRIVE_ON: u16 = 1 << 15;
    /// Bit 14: 0 drive disable, 1 drive enable (sercos-telegrams.md, MDT control word bit 14).
    pub const DRIVE_ENABLE: u16 = 1 << 14;
    /// Bit 13: 0 drive halt, 1 drive restart (sercos-telegrams.md, MDT control word bit 13).
    pub const DRIVE_HALT_RESTART: u16 = 1 << 13;
    /// Bits 12–11: reserved (sercos-telegrams.md, MDT control word bits 12, 11).
    pub const RESERVED: u16 = 0b11 << 11;
    /// Bit 10: control unit synchronisation bit (sercos-telegrams.md, MDT control word bit 10).
    pub const CONTROL_UNIT_SYNC: u16 = 1 << 10;
    /// Bits 9–8: operation mode (sercos-telegrams.md, MDT control word bits 9, 8).
    pub const OPERATION_MODE: u16 = 0b11 << 8;
    const OPERATION_MODE_SHIFT: u32 = 8;
    /// Bit 7: real-time control bit 2, S-0-0302 (sercos-telegrams.md, MDT control word bit 7).
    pub const REAL_TIME_CONTROL_BIT_2: u16 = 1 << 7;
    /// Bit 6: real-time control bit 1, S-0-0300 (sercos-telegrams.md, MDT control word bit 6).
    pub const REAL_TIME_CONTROL_BIT_1: u16 = 1 << 6;
    /// Bits 5–3: data block element (sercos-telegrams.md, MDT control word bits 5, 4, 3).
    pub const DATA_BLOCK_ELEMENT: u16 = 0b111 << 3;
    const DATA_BLOCK_ELEMENT_SHIFT: u32 = 3;
    /// Bit 2: 0 transmission in progress, 1 last transmission (sercos-telegrams.md, MDT
    /// control word bit 2).
    pub const LAST_TRANSMISSION: u16 = 1 << 2;
    /// Bit 1: 0 read service info, 1 write service info (sercos-telegrams.md, MDT control word
    /// bit 1).
    pub const WRITE: u16 = 1 << 1;
    /// Bit 0: master service transport handshake, a toggle bit (sercos-telegrams.md, MDT
    /// control word bit 0).
    pub const MHS: u16 = 1;

    /// The word with every bit 0: drive off, disabled, halt, primary mode, service channel
    /// closed, read, MHS 0.
    pub const fn new() -> ControlWord {
        ControlWord(0)
    }

    /// The control word from its 16-bit value, reserved bits included.
    pub const fn from_raw(raw: u16) -> ControlWord {
        ControlWord(raw)
    }

    /// The 16-bit value, reserved bits included.
    pub const fn raw(self) -> u16 {
        self.0
    }

    /// Bit 15, drive ON. With bits 15–13 = 111 the drive follows command values; 1→0 removes
    /// torque and lets the motor spin down.
    pub const fn drive_on(self) -> bool {
        self.0 & Self::DRIVE_ON != 0
    }

    /// Bit 14, drive enable. 1→0 disables torque immediately, independent of bits 15 and 13.
    pub const fn drive_enable(self) -> bool {
        self.0 & Self::DRIVE_ENABLE != 0
    }

    /// Bit 13, drive halt/restart: `true` = 1 = drive restart, `false` = 0 = drive halt.
    #[doc(alias = "drive_halt")]
    pub const fn drive_restart(self) -> bool {
        self.0 & Self::DRIVE_HALT_RESTART != 0
    }

    /// Bits 12–11, reserved, in place (the value masked with [`ControlWord::RESERVED`]).
    pub const fn reserved_bits(self) -> u16 {
        self.0 & Self::RESERVED
    }

    /// Bit 10, control unit synchronisation bit.
    #[doc(alias = "control_unit_synchronization_bit")]
    pub const fn control_unit_sync(self) -> bool {
        self.0 & Self::CONTROL_UNIT_SYNC != 0
    }

    /// Bits 9–8, commanded operation mode.
    pub const fn operation_mode(self) -> OperationMode {
        OperationMode::from_bits((self.0 >> Self::OPERATION_MODE_SHIFT) as u8)
    }

    /// Bit 7, real-time control bit 2 (S-0-0302).
    pub const fn real_time_control_bit_2(self) -> bool {
        self.0 & Self::REAL_TIME_CONTROL_BIT_2 != 0
    }

    /// Bit 6, real-time control bit 1 (S-0-0300).
    pub const fn real_time_control_bit_1(self) -> bool {
        self.0 & Self::REAL_TIME_CONTROL_BIT_1 != 0
    }

    /// Bits 5–3, data block element addressed through the service channel.
    pub const fn data_block_element(self) -> Element {
        Element::from_bits((self.0 >> Self::DATA_BLOCK_ELEMENT_SHIFT) as u8)
    }

    /// Bit 2: `true` = last transmission, `false` = transmission in progress.
    pub const fn last_transmission(self) -> bool {
        self.0 & Self::LAST_TRANSMISSION != 0
    }

    /// Bit 1, read/write: `true` = write service info, `false` = read service info.
    #[doc(alias = "read_write")]
    pub const fn write(self) -> bool {
        self.0 & Self::WRITE != 0
    }

    /// Bit 0, MHS, the master service transport handshake (a toggle bit).
    #[doc(alias = "master_service_transport_handshake")]
    pub const fn mhs(self) -> bool {
        self.0 & Self::MHS != 0
    }

    /// With bit 15, drive ON, set or cleared.
    #[must_use]
    pub const fn with_drive_on(self, on: bool) -> ControlWord {
        ControlWord(with_bit(self.0, Self::DRIVE_ON, on))
    }

    /// With bit 14, drive enable, set or cleared.
    #[must_use]
    pub const fn with_drive_enable(self, enable: bool) -> ControlWord {
        ControlWord(with_bit(self.0, Self::DRIVE_ENABLE, enable))
    }

    /// With bit 13 = 1 (restart) or 0 (halt).
    #[must_use]
    pub const fn with_drive_restart(self, restart: bool) -> ControlWord {
        ControlWord(with_bit(self.0, Self::DRIVE_HALT_RESTART, restart))
    }

    /// With the reserved bits 12–11 replaced by `bits & RESERVED`.
    #[must_use]
    pub const fn with_reserved_bits(self, bits: u16) -> ControlWord {
        ControlWord((self.0 & !Self::RESERVED) | (bits & Self::RESERVED))
    }

    /// With bit 10, control unit synchronisation, set or cleared.
    #[must_use]
    pub const fn with_control_unit_sync(self, sync: bool) -> ControlWord {
        ControlWord(with_bit(self.0, Self::CONTROL_UNIT_SYNC, sync))
    }

    /// With bits 9–8 set to `mode`.
    #[must_use]
    pub const fn with_operation_mode(self, mode: OperationMode) -> ControlWord {
        ControlWord(
            (self.0 & !Self::OPERATION_MODE) | ((mode.bits() as u16) << Self::OPERATION_MODE_SHIFT),
        )
    }

    /// With bit 7, real-time control bit 2, set or cleared.
    #[must_use]
    pub const fn with_real_time_control_bit_2(self, set: bool) -> ControlWord {
        ControlWord(with_bit(self.0, Self::REAL_TIME_CONTROL_BIT_2, set))
    }

    /// With bit 6, real-time control bit 1, set or cleared.
    #[must_use]
    pub const fn with_real_time_control_bit_1(self, set: bool) -> ControlWord {
        ControlWord(with_bit(self.0, Self::REAL_TIME_CONTROL_BIT_1, set))
    }

    /// With bits 5–3 set to `element`.
    #[must_use]
    pub const fn with_data_block_element(self, element: Element) -> ControlWord {
        ControlWord(
            (self.0 & !Self::DATA_BLOCK_ELEMENT)
                | ((element.bits() as u16) << Self::DATA_BLOCK_ELEMENT_SHIFT),
        )
    }

    /// With bit 2, last transmission, set or cleared.
    #[must_use]
    pub const fn with_last_transmission(self, last: bool) -> ControlWord {
        ControlWord(with_bit(self.0, Self::LAST_TRANSMISSION, last))
    }

    /// With bit 1 = 1 (write service info) or 0 (read service info).
    #[must_use]
    pub const fn with_write(self, write: bool) -> ControlWord {
        ControlWord(with_bit(self.0, Self::WRITE, write))
    }

    /// With bit 0, MHS, set or cleared.
    #[must_use]
    pub const fn with_mhs(self, mhs: bool) -> ControlWord {
        ControlWord(with_bit(self.0, Self::MHS, mhs))
    }

    /// With MHS toggled (the master's handshake step, sercos-telegrams.md: "a toggle bit").
    #[must_use]
    pub const fn with_mhs_toggled(self) -> ControlWord {
        ControlWord(self.0 ^ Self::MHS)
    }
}

impl From<u16> for ControlWord {
    fn from(raw: u16) -> ControlWord {
        ControlWord(raw)
    }
}

impl From<ControlWord> for u16 {
    fn from(word: ControlWord) -> u16 {
        word.0
    }
}

/// `XXXXH (names of the set bits)`; the operation mode and element are named when not 0,
/// set reserved bits as `reserved XXXXH`.
impl fmt::Display for ControlWord {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut list = NameList::start(f, self.0)?;
        list.flag(self.drive_on(), "drive on")?;
        list.flag(self.drive_enable(), "drive enable")?;
        list.flag(self.drive_restart(), "drive restart")?;
        let reserved = self.reserved_bits();
        list.field(reserved != 0, "reserved", &format_args!("{reserved:04X}H"))?;
        list.flag(self.control_unit_sync(), "control unit sync")?;
        let mode = self.operation_mode();
        list.field(mode != OperationMode::Primary, "mode", &mode)?;
        list.flag(self.real_time_control_bit_2(), "RTC bit 2")?;
        list.flag(self.real_time_control_bit_1(), "RTC bit 1")?;
        let element = self.data_block_element();
        list.field(
            element != Element::ServiceChannelClosed,
            "element",
            &element,
        )?;
        list.flag(self.last_transmission(), "last transmission")?;
        list.flag(self.write(), "write")?;
        list.flag(self.mhs(), "MHS")?;
        list.finish()
    }
}

impl fmt::Debug for ControlWord {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "ControlWord({self})")
    }
}
