//! The operation mode field shared by the MDT control word and the AT status word (bits 9–8).

use core::fmt;

/// Operation mode, control word bits 9–8 (commanded) and status word bits 9–8 (actual).
///
/// sercos-telegrams.md, MDT control word and AT status word bits 9, 8: "00 primary op mode,
/// 01 secondary op mode 1, 10 secondary op mode 2, 11 secondary op mode 3", defined by
/// S-0-0032 to S-0-0035.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[repr(u8)]
pub enum OperationMode {
    /// 00: primary operation mode (S-0-0032).
    #[default]
    Primary = 0,
    /// 01: secondary operation mode 1 (S-0-0033).
    Secondary1 = 1,
    /// 10: secondary operation mode 2 (S-0-0034).
    Secondary2 = 2,
    /// 11: secondary operation mode 3 (S-0-0035).
    Secondary3 = 3,
}

impl OperationMode {
    /// All four modes, by their bit value.
    pub const ALL: [OperationMode; 4] = [
        OperationMode::Primary,
        OperationMode::Secondary1,
        OperationMode::Secondary2,
        OperationMode::Secondary3,
    ];

    /// The mode from its two bits; higher bits are ignored.
    pub const fn from_bits(bits: u8) -> OperationMode {
        match bits & 0b11 {
            0 => OperationMode::Primary,
            1 => OperationMode::Secondary1,
            2 => OperationMode::Secondary2,
            _ => OperationMode::Secondary3,
        }
    }

    /// The two bits, 0–3.
    pub const fn bits(self) -> u8 {
        self as u8
    }
}

impl fmt::Display for OperationMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            OperationMode::Primary => "primary",
            OperationMode::Secondary1 => "secondary 1",
            OperationMode::Secondary2 => "secondary 2",
            OperationMode::Secondary3 => "secondary 3",
        })
    }
}
