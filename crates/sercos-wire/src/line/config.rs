//! Line signal options: coding and light polarity (410B §4.1, register 1H).

/// How data bits become line levels.
///
/// 410B §4.1 1H.12 RXDNRZ (ERRATA reading: 0 = NRZI, 1 = NRZ) for the receiver; 410B §2 pin
/// TxDNRZ outputs the NRZ-coded transmit data while TxD1–6 carry NRZI.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Coding {
    /// NRZI: a 0 is a change of level, a 1 no change (ERRATA, Telegrams; the captures).
    #[default]
    Nrzi,
    /// NRZ: the level is the data bit (1 = light on).
    Nrz,
}

/// Which pin level means "light on".
///
/// 410B §4.1 1H.7 POLRXD and 1H.9 POLTXD: 0 (reset) = "light on" when the pin is 0,
/// 1 = "light on" when the pin is 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Polarity {
    /// POLRXD / POLTXD = 0 (reset): light on when the pin is 0.
    #[default]
    #[doc(alias = "POLRXD")]
    #[doc(alias = "POLTXD")]
    LightOnLow,
    /// POLRXD / POLTXD = 1: light on when the pin is 1.
    LightOnHigh,
}

impl Polarity {
    /// The pin level that means "light on".
    pub const fn light_on_level(self) -> bool {
        matches!(self, Polarity::LightOnHigh)
    }

    /// The pin level of a dark fibre: the level a coder assumes before the first bit
    /// (`docs/spec-notes.md`, "Line coding").
    pub const fn dark_level(self) -> bool {
        !self.light_on_level()
    }

    /// Mask XORed onto NRZ data to get pin levels: all ones when light on is the 0 level.
    pub(crate) const fn nrz_mask(self) -> u8 {
        match self {
            Polarity::LightOnLow => 0xFF,
            Polarity::LightOnHigh => 0x00,
        }
    }
}

/// Coding and polarity of one line direction (receive: RXDNRZ, POLRXD; transmit: the pin
/// chosen, POLTXD).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct LineConfig {
    /// NRZI or NRZ.
    pub coding: Coding,
    /// Light polarity of the pin.
    pub polarity: Polarity,
}

impl LineConfig {
    /// The reset configuration: NRZI, light on when the pin is 0 (410B §4.1, 1H reset values).
    pub const RESET: LineConfig = LineConfig {
        coding: Coding::Nrzi,
        polarity: Polarity::LightOnLow,
    };

    /// A configuration from its two parts.
    pub const fn new(coding: Coding, polarity: Polarity) -> Self {
        LineConfig { coding, polarity }
    }
}
