//! The AT status word, the first word of the data record in an AT.
//!
//! Bit layout from sercos-telegrams.md, "Amplifier Telegram", status word table.

use core::fmt;

use super::operation_mode::OperationMode;
use super::word_format::NameList;

/// Status word bits 15–14, "ready to operate" (sercos-telegrams.md, AT status word bits 15, 14).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[repr(u8)]
pub enum ReadyToOperate {
    /// 00: drive not ready for power-up.
    #[default]
    NotReadyForPowerUp = 0,
    /// 01: drive ready for power-up.
    ReadyForPowerUp = 1,
    /// 10: drive power ready.
    PowerReady = 2,
    /// 11: drive ready to operate.
    ReadyToOperate = 3,
}

impl ReadyToOperate {
    /// All four states, by their bit value.
    pub const ALL: [ReadyToOperate; 4] = [
        ReadyToOperate::NotReadyForPowerUp,
        ReadyToOperate::ReadyForPowerUp,
        ReadyToOperate::PowerReady,
        ReadyToOperate::ReadyToOperate,
    ];

    /// The state from its two bits; higher bits are ignored.
    pub const fn from_bits(bits: u8) -> ReadyToOperate {
        match bits & 0b11 {
            0 => ReadyToOperate::NotReadyForPowerUp,
            1 => ReadyToOperate::ReadyForPowerUp,
            2 => ReadyToOperate::PowerReady,
            _ => ReadyToOperate::ReadyToOperate,
        }
    }

    /// The two bits, 0–3.
    pub const fn bits(self) -> u8 {
        self as u8
    }
}

impl fmt::Display for ReadyToOperate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ReadyToOperate::NotReadyForPowerUp => "not ready for power-up",
            ReadyToOperate::ReadyForPowerUp => "ready for power-up",
            ReadyToOperate::PowerReady => "power ready",
            ReadyToOperate::ReadyToOperate => "ready to operate",
        })
    }
}

/// The 16-bit AT status word. Every `u16` is representable; reserved bits 10, 4 and 3 are kept.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(from = "u16", into = "u16")
)]
pub struct StatusWord(u16);

const fn with_bit(raw: u16, mask: u16, set: bool) -> u16 {
    if set { raw | mask } else { raw & !mask }
}

impl StatusWord {
    /// Bits 15–14: ready to operate (sercos-telegrams.md, AT status word bits 15, 14).
    pub const READY_TO_OPERATE: u16 = 0b11 << 14;
    const READY_TO_OPERATE_SHIFT: u32 = 14;
    /// Bit 13: drive shutdown error; the document says "Class 3 Diags" (sercos-telegrams.md,
    /// AT status word bit 13). In SERCOS this bit usually reports class 1 diagnostics
    /// (S-0-0011); see docs/spec-notes.md.
    pub const SHUTDOWN_ERROR: u16 = 1 << 13;
    /// Bit 12: change bit for class 2 diagnostics (sercos-telegrams.md, AT status word bit 12).
    pub const CHANGE_BIT_CLASS_2: u16 = 1 << 12;
    /// Bit 11: change bit for class 3 diagnostics (sercos-telegrams.md, AT status word bit 11).
    pub const CHANGE_BIT_CLASS_3: u16 = 1 << 11;
    /// Bits 10, 4 and 3: not described by sercos-telegrams.md (bit 10 is missing from the
    /// table, bits 4–3 are "Reserved"); kept as reserved.
    pub const RESERVED: u16 = (1 << 10) | (0b11 << 3);
    /// Bits 9–8: actual operation mode (sercos-telegrams.md, AT status word bits 9, 8).
    pub const ACTUAL_OPERATION_MODE: u16 = 0b11 << 8;
    const ACTUAL_OPERATION_MODE_SHIFT: u32 = 8;
    /// Bit 7: real-time status bit 2, S-0-0306 (sercos-telegrams.md, AT status word bit 7).
    pub const REAL_TIME_STATUS_BIT_2: u16 = 1 << 7;
    /// Bit 6: real-time status bit 1, S-0-0304 (sercos-telegrams.md, AT status word bit 6).
    pub const REAL_TIME_STATUS_BIT_1: u16 = 1 << 6;
    /// Bit 5: 0 no change in command status, 1 changing command status (sercos-telegrams.md,
    /// AT status word bit 5).
    pub const COMMAND_CHANGE: u16 = 1 << 5;
    /// Bit 2: 0 no error, 1 error in service channel (sercos-telegrams.md, AT status word bit 2).
    pub const SERVICE_CHANNEL_ERROR: u16 = 1 << 2;
    /// Bit 1: 0 step finished, 1 step in progress (sercos-telegrams.md, AT status word bit 1).
    pub const BUSY: u16 = 1 << 1;
    /// Bit 0: AHS, the drive's service transport handshake, a toggle bit (sercos-telegrams.md,
    /// AT status word bit 0).
    pub const AHS: u16 = 1;

    /// The word with every bit 0.
    pub const fn new() -> StatusWord {
        StatusWord(0)
    }

    /// The status word from its 16-bit value, reserved bits included.
    pub const fn from_raw(raw: u16) -> StatusWord {
        StatusWord(raw)
    }

    /// The 16-bit value, reserved bits included.
    pub const fn raw(self) -> u16 {
        self.0
    }

    /// Bits 15–14, ready to operate.
    pub const fn ready_to_operate(self) -> ReadyToOperate {
        ReadyToOperate::from_bits((self.0 >> Self::READY_TO_OPERATE_SHIFT) as u8)
    }

    /// Bit 13, drive shutdown error (the document: class 3 diagnostics; usually class 1).
    pub const fn shutdown_error(self) -> bool {
        self.0 & Self::SHUTDOWN_ERROR != 0
    }

    /// Bit 12, change bit for class 2 diagnostics.
    pub const fn change_bit_class_2(self) -> bool {
        self.0 & Self::CHANGE_BIT_CLASS_2 != 0
    }

    /// Bit 11, change bit for class 3 diagnostics.
    pub const fn change_bit_class_3(self) -> bool {
        self.0 & Self::CHANGE_BIT_CLASS_3 != 0
    }

    /// Bits 10, 4, 3, reserved, in place (the value masked with [`StatusWord::RESERVED`]).
    pub const fn reserved_bits(self) -> u16 {
        self.0 & Self::RESERVED
    }

    /// Bits 9–8, actual operation mode.
    pub const fn actual_operation_mode(self) -> OperationMode {
        OperationMode::from_bits((self.0 >> Self::ACTUAL_OPERATION_MODE_SHIFT) as u8)
    }

    /// Bit 7, real-time status bit 2 (S-0-0306).
    pub const fn real_time_status_bit_2(self) -> bool {
        self.0 & Self::REAL_TIME_STATUS_BIT_2 != 0
    }

    /// Bit 6, real-time status bit 1 (S-0-0304).
    pub const fn real_time_status_bit_1(self) -> bool {
        self.0 & Self::REAL_TIME_STATUS_BIT_1 != 0
    }

    /// Bit 5, command change bit: `true` = changing command status.
    #[doc(alias = "CMD_AT")]
    pub const fn command_change(self) -> bool {
        self.0 & Self::COMMAND_CHANGE != 0
    }

    /// Bit 2, error in the service channel (the error message is in the service info).
    pub const fn service_channel_error(self) -> bool {
        self.0 & Self::SERVICE_CHANNEL_ERROR != 0
    }

    /// Bit 1, busy: `true` = step in progress, `false` = step finished.
    pub const fn busy(self) -> bool {
        self.0 & Self::BUSY != 0
    }

    /// Bit 0, AHS, the drive's service transport handshake (a toggle bit).
    #[doc(alias = "amplifier_service_transport_handshake")]
    pub const fn ahs(self) -> bool {
        self.0 & Self::AHS != 0
    }

    /// With bits 15–14 set to `state`.
    #[must_use]
    pub const fn with_ready_to_operate(self, state: ReadyToOperate) -> StatusWord {
        StatusWord(
            (self.0 & !Self::READY_TO_OPERATE)
                | ((state.bits() as u16) << Self::READY_TO_OPERATE_SHIFT),
        )
    }

    /// With bit 13, shutdown error, set or cleared.
    #[must_use]
    pub const fn with_shutdown_error(self, set: bool) -> StatusWord {
        StatusWord(with_bit(self.0, Self::SHUTDOWN_ERROR, set))
    }

    /// With bit 12, change bit class 2, set or cleared.
    #[must_use]
    pub const fn with_change_bit_class_2(self, set: bool) -> StatusWord {
        StatusWord(with_bit(self.0, Self::CHANGE_BIT_CLASS_2, set))
    }

    /// With bit 11, change bit class 3, set or cleared.
    #[must_use]
    pub const fn with_change_bit_class_3(self, set: bool) -> StatusWord {
        StatusWord(with_bit(self.0, Self::CHANGE_BIT_CLASS_3, set))
    }

    /// With the reserved bits 10, 4, 3 replaced by `bits & RESERVED`.
    #[must_use]
    pub const fn with_reserved_bits(self, bits: u16) -> StatusWord {
        StatusWord((self.0 & !Self::RESERVED) | (bits & Self::RESERVED))
    }

    /// With bits 9–8 set to `mode`.
    #[must_use]
    pub const fn with_actual_operation_mode(self, mode: OperationMode) -> StatusWord {
        StatusWord(
            (self.0 & !Self::ACTUAL_OPERATION_MODE)
                | ((mode.bits() as u16) << Self::ACTUAL_OPERATION_MODE_SHIFT),
        )
    }

    /// With bit 7, real-time status bit 2, set or cleared.
    #[must_use]
    pub const fn with_real_time_status_bit_2(self, set: bool) -> StatusWord {
        StatusWord(with_bit(self.0, Self::REAL_TIME_STATUS_BIT_2, set))
    }

    /// With bit 6, real-time status bit 1, set or cleared.
    #[must_use]
    pub const fn with_real_time_status_bit_1(self, set: bool) -> StatusWord {
        StatusWord(with_bit(self.0, Self::REAL_TIME_STATUS_BIT_1, set))
    }

    /// With bit 5, command change, set or cleared.
    #[must_use]
    pub const fn with_command_change(self, set: bool) -> StatusWord {
        StatusWord(with_bit(self.0, Self::COMMAND_CHANGE, set))
    }

    /// With bit 2, error in service channel, set or cleared.
    #[must_use]
    pub const fn with_service_channel_error(self, set: bool) -> StatusWord {
        StatusWord(with_bit(self.0, Self::SERVICE_CHANNEL_ERROR, set))
    }

    /// With bit 1, busy, set or cleared.
    #[must_use]
    pub const fn with_busy(self, set: bool) -> StatusWord {
        StatusWord(with_bit(self.0, Self::BUSY, set))
    }

    /// With bit 0, AHS, set or cleared.
    #[must_use]
    pub const fn with_ahs(self, set: bool) -> StatusWord {
        StatusWord(with_bit(self.0, Self::AHS, set))
    }

    /// With AHS toggled (the drive's handshake step, sercos-telegrams.md: "a toggle bit").
    #[must_use]
    pub const fn with_ahs_toggled(self) -> StatusWord {
        StatusWord(self.0 ^ Self::AHS)
    }
}

impl From<u16> for StatusWord {
    fn from(raw: u16) -> StatusWord {
        StatusWord(raw)
    }
}

impl From<StatusWord> for u16 {
    fn from(word: StatusWord) -> u16 {
        word.0
    }
}

/// `XXXXH (names of the set bits)`; ready-to-operate and the mode are named when not 0, set
/// reserved bits as `reserved XXXXH`.
impl fmt::Display for StatusWord {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut list = NameList::start(f, self.0)?;
        let ready = self.ready_to_operate();
        list.field(ready != ReadyToOperate::NotReadyForPowerUp, "", &ready)?;
        list.flag(self.shutdown_error(), "shutdown error")?;
        list.flag(self.change_bit_class_2(), "change class 2")?;
        list.flag(self.change_bit_class_3(), "change class 3")?;
        let reserved = self.reserved_bits();
        list.field(reserved != 0, "reserved", &format_args!("{reserved:04X}H"))?;
        let mode = self.actual_operation_mode();
        list.field(mode != OperationMode::Primary, "mode", &mode)?;
        list.flag(self.real_time_status_bit_2(), "RTS bit 2")?;
        list.flag(self.real_time_status_bit_1(), "RTS bit 1")?;
        list.flag(self.command_change(), "command change")?;
        list.flag(self.service_channel_error(), "service channel error")?;
        list.flag(self.busy(), "busy")?;
        list.flag(self.ahs(), "AHS")?;
        list.finish()
    }
}

impl fmt::Debug for StatusWord {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "StatusWord({self})")
    }
}
