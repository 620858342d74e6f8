//! Settings of the serial interface, derived without state from the variant, the strap pins,
//! the SCLK frequency and the control registers 1H and 2H.
//!
//! Every function here is pure: the chip model (and anyone else, e.g. a ring simulation that
//! needs the bit time of a node) calls them with the current register values. Registers are
//! passed as raw 16-bit words so the functions work on a value read from any [`SerconBus`].
//!
//! Sources: 410B datasheet §2 (pins SREGEN, SBAUD, TM0/TM1, TxD1–6, SCLKO2/4, L_ERRN) and §4.1
//! (registers 1H, 2H); 816 delta specification §2.2, §2.3.1–§2.3.3; ERRATA.md (1H.6 SWBAUD,
//! 1H.10 ENTSBAUD, 1H.12 RXDNRZ, 1H.15 SWBAUD16). Readings chosen where the documents are
//! silent are in `docs/spec-notes.md`, "Serial interface settings".
//!
//! [`SerconBus`]: sercon_regs::SerconBus

use sercon_regs::Variant;
use sercos_wire::time::{BitRate, Duration};

use crate::config::Straps;

/// Bit positions of register 1H (410B §4.1; 816 §2.3.1 for SWBAUD16).
mod reg1 {
    /// 1H.6 SWBAUD (ERRATA 1H.6): 0 = f_SCLK/16, 1 = f_SCLK/32 when ENTSBAUD = 1.
    pub const SWBAUD: u16 = 1 << 6;
    /// 1H.7 POLRXD: 0 = "light on" when RxD = 0.
    pub const POLRXD: u16 = 1 << 7;
    /// 1H.9 POLTXD: 0 = "light on" when TxD = 0.
    pub const POLTXD: u16 = 1 << 9;
    /// 1H.10 ENTSBAUD (ERRATA 1H.10): 0 = rate from pin SBAUD, 1 = from bit SWBAUD.
    pub const ENTSBAUD: u16 = 1 << 10;
    /// 1H.12 RXDNRZ (ERRATA 1H.12): 0 = NRZI, 1 = NRZ.
    pub const RXDNRZ: u16 = 1 << 12;
    /// 1H.15 SWBAUD16 (816 §2.3.1; ERRATA 1H.15).
    pub const SWBAUD16: u16 = 1 << 15;
}

/// Bit positions of register 2H (410B §4.1).
mod reg2 {
    /// 2H.0–5 ENTXD1–6.
    pub const ENTXD_MASK: u16 = 0x003F;
    /// 2H.6 TXDMODE.
    pub const TXDMODE: u16 = 1 << 6;
    /// 2H.7–9 TMODE0–2.
    pub const TMODE_SHIFT: u16 = 7;
    /// 2H.14–15 LMODE0–1.
    pub const LMODE_SHIFT: u16 = 14;
}

/// Errors of the serial settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
pub enum SerialSettingsError {
    /// The bit clock comes from the RxC/TxC inputs (410B with SREGEN = 0), so the chip's
    /// settings do not determine it.
    #[error("the bit clock is external (SERCON410B with SREGEN = 0: RxC/TxC are inputs)")]
    ExternalClock,
    /// The clock source frequency is 0 Hz.
    #[error("the clock frequency is 0 Hz")]
    ZeroFrequency,
    /// The period is not a whole number of picoseconds.
    #[error("{source_hz} Hz / {divisor} has no period of a whole number of picoseconds")]
    NotWholePicoseconds {
        /// The source frequency in Hz.
        source_hz: u64,
        /// The divisor.
        divisor: u32,
    },
    /// The bit clock is exact but is none of 2, 4, 8, 16 Mbit/s (SCLK is not 64 MHz).
    #[error("{source_hz} Hz / {divisor} is not one of the SERCOS bit rates 2, 4, 8, 16 Mbit/s")]
    NonStandardRate {
        /// The source frequency in Hz.
        source_hz: u64,
        /// The divisor.
        divisor: u32,
    },
}

/// A clock derived from a source frequency by an integer divisor, kept exact as the pair
/// (no floating point): e.g. the bit clock f_SCLK / 4 or the output SCLKO4 = f_SCLK / 4.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct DividedClock {
    /// The source frequency in Hz (f_SCLK).
    pub source_hz: u64,
    /// The divisor (≥ 1).
    pub divisor: u32,
}

impl DividedClock {
    /// The frequency in Hz if it is a whole number of Hz.
    pub const fn hz_exact(self) -> Option<u64> {
        let d = self.divisor as u64;
        if d != 0 && self.source_hz % d == 0 {
            Some(self.source_hz / d)
        } else {
            None
        }
    }

    /// The period, exact in picoseconds: `divisor × 10¹² / source_hz`.
    pub const fn period(self) -> Result<Duration, SerialSettingsError> {
        if self.source_hz == 0 || self.divisor == 0 {
            return Err(SerialSettingsError::ZeroFrequency);
        }
        let num = self.divisor as u128 * 1_000_000_000_000u128;
        let den = self.source_hz as u128;
        if num % den != 0 {
            return Err(SerialSettingsError::NotWholePicoseconds {
                source_hz: self.source_hz,
                divisor: self.divisor,
            });
        }
        // num / den ≤ u32::MAX × 10¹², which fits in u64.
        Ok(Duration::from_picos((num / den) as u64))
    }

    /// The SERCOS bit rate this clock equals exactly, if any.
    pub fn bit_rate(self) -> Result<BitRate, SerialSettingsError> {
        let hz = self
            .hz_exact()
            .ok_or(SerialSettingsError::NonStandardRate {
                source_hz: self.source_hz,
                divisor: self.divisor,
            })?;
        BitRate::ALL
            .into_iter()
            .find(|r| r.bits_per_second() == hz)
            .ok_or(SerialSettingsError::NonStandardRate {
                source_hz: self.source_hz,
                divisor: self.divisor,
            })
    }
}

/// Where the bit clock of the serial receiver and transmitter comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BitClock {
    /// Internal clock regeneration from SCLK: the bit clock is f_SCLK / divisor.
    Internal(DividedClock),
    /// External clock regeneration (410B with SREGEN = 0): RxC and TxC are clock inputs
    /// (410B §2, SREGEN; §3.4.3, at most 10 MHz). The chip's settings do not fix the rate;
    /// whoever drives RxC/TxC (the ring simulation) supplies it.
    External,
}

impl BitClock {
    /// The bit time (duration of one line bit), exact.
    pub fn bit_time(self) -> Result<Duration, SerialSettingsError> {
        match self {
            BitClock::Internal(c) => c.period(),
            BitClock::External => Err(SerialSettingsError::ExternalClock),
        }
    }

    /// The SERCOS bit rate, if the bit clock is internal and exactly one of 2/4/8/16 Mbit/s.
    pub fn bit_rate(self) -> Result<BitRate, SerialSettingsError> {
        match self {
            BitClock::Internal(c) => c.bit_rate(),
            BitClock::External => Err(SerialSettingsError::ExternalClock),
        }
    }
}

/// Whether a SERCON816 runs in its SERCON410B compatible mode (pin 28 SBAUD16 = 1): only
/// 2 and 4 Mbit/s, and the 410B's SCLKO2/SCLKO4 frequencies. Always true for the 410B itself.
// 816 §2.3.2: SREGEN (new SBAUD16) tied to '1' forces the compatible mode.
pub const fn is_410b_compatible_mode(variant: Variant, straps: &Straps) -> bool {
    match variant {
        Variant::Sercon410b => true,
        Variant::Sercon816 => straps.sbaud16,
    }
}

/// The bit clock selected by the pins and bits, for an SCLK of `sclk_hz`.
///
/// * SERCON410B: SREGEN (pin 28, [`Straps::sbaud16`]) = 0 gives [`BitClock::External`];
///   otherwise the rate is f_SCLK/16 (select 0) or f_SCLK/32 (select 1), where the select is
///   pin SBAUD when ENTSBAUD (1H.10) = 0 and bit SWBAUD (1H.6) when ENTSBAUD = 1.
/// * SERCON816: table 2.3.1. The DPLL runs at 4 × f_SCLK and 16 × the bit rate, so the bit
///   clock is f_SCLK / 4, 8, 16 or 32 for 16, 8, 4, 2 Mbit/s at SCLK = 64 MHz.
pub const fn bit_clock(
    variant: Variant,
    straps: &Straps,
    sclk_hz: u64,
    reg1_value: u16,
) -> BitClock {
    let entsbaud = reg1_value & reg1::ENTSBAUD != 0;
    let swbaud = reg1_value & reg1::SWBAUD != 0;
    // ERRATA 1H.10: ENTSBAUD = 0 takes the rate from pin SBAUD, 1 from bit SWBAUD.
    let slow = if entsbaud { swbaud } else { straps.sbaud };
    let divisor = match variant {
        Variant::Sercon410b => {
            // 410B §2 SREGEN: 0 = clock and data regeneration off, RxC/TxC are clock inputs.
            if !straps.sbaud16 {
                return BitClock::External;
            }
            // 410B §2 SBAUD and 1H.6 (ERRATA): 0 = f_SCLK/16, 1 = f_SCLK/32.
            if slow { 32 } else { 16 }
        }
        Variant::Sercon816 => {
            if straps.sbaud16 {
                // 816 §2.3.1 rows 1–4 (SBAUD16 = 1): 2 or 4 Mbit/s; SWBAUD16 is ignored.
                if slow { 32 } else { 16 }
            } else {
                // 816 §2.3.1 rows 5–10 (SBAUD16 = 0). With ENTSBAUD = 0 the pin SBAUD picks
                // 8 (1) or 16 (0) Mbit/s; with ENTSBAUD = 1, SWBAUD16 = 1 picks 2/4 and
                // SWBAUD16 = 0 picks 8/16 Mbit/s, SWBAUD choosing the slower one.
                let low_range = entsbaud && reg1_value & reg1::SWBAUD16 != 0;
                match (low_range, slow) {
                    (true, true) => 32,
                    (true, false) => 16,
                    (false, true) => 8,
                    (false, false) => 4,
                }
            }
        }
    };
    BitClock::Internal(DividedClock {
        source_hz: sclk_hz,
        divisor,
    })
}

/// The frequencies at the clock outputs SCLKO2 (pin 6) and SCLKO4 (pin 5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SclkOutputs {
    /// SCLKO2 (pin 6).
    #[doc(alias = "SCLKO2")]
    pub sclko2: DividedClock,
    /// SCLKO4 (pin 5).
    #[doc(alias = "SCLKO4")]
    pub sclko4: DividedClock,
}

/// SCLKO2 and SCLKO4 for an SCLK of `sclk_hz`.
// 410B §2: SCLKO2 = f_SCLK / 2, SCLKO4 = f_SCLK / 4. 816 §2.3.1 table "SCLKO2, SCLKO4":
// SBAUD16 = 1 gives 32/16 MHz at SCLK = 64 MHz (as the 410B), SBAUD16 = 0 gives 64/32 MHz.
pub const fn sclk_outputs(variant: Variant, straps: &Straps, sclk_hz: u64) -> SclkOutputs {
    let (d2, d4) = if is_410b_compatible_mode(variant, straps) {
        (2, 4)
    } else {
        (1, 2)
    };
    SclkOutputs {
        sclko2: DividedClock {
            source_hz: sclk_hz,
            divisor: d2,
        },
        sclko4: DividedClock {
            source_hz: sclk_hz,
            divisor: d4,
        },
    }
}

/// The value of REPON (1H.3) after a reset.
// 410B §4.1 1H.3: reset value 1 (repeater on). 816 §2.3.3 table: TM0/TM1 = 11 → 1, 00 → 0,
// 01 → 1, 10 → 1, i.e. REPON resets to 0 only when both pins are 0.
pub const fn repon_reset(variant: Variant, straps: &Straps) -> bool {
    match variant {
        Variant::Sercon410b => true,
        Variant::Sercon816 => straps.tm0 || straps.tm1,
    }
}

/// What the transmitter sends.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TestMode {
    /// Normal operation: telegrams, fill signal, repeated data.
    Normal,
    /// TxD1–6 send continuous light (a constant "light on" level, see [`txd_level_for_light`]).
    ContinuousLight,
    /// TxD1–6 send a zero bit stream.
    ZeroBitStream,
}

/// Who decides the test mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TestModeSource {
    /// TMODE0–2 = 0–3: the pins TM0/TM1 decide.
    Pins,
    /// TMODE0–2 = 4–7: the register overwrites the pins.
    Register,
}

/// The effective test mode from TMODE0–2 (2H.7–9) and the pins TM0/TM1, and who decided it.
// 410B §4.1 2H.7–9: 0–3 = controlled via the TM0–1 pins, 4 and 6 = continuous signal light,
// 5 = zero bit stream, 7 = normal operation. 816 §2.3.3: "TMODE2-0 can also over write the
// actual test mode. Coding for this control bits does not change."
pub const fn test_mode(
    variant: Variant,
    straps: &Straps,
    reg2_value: u16,
) -> (TestMode, TestModeSource) {
    let tmode = (reg2_value >> reg2::TMODE_SHIFT) & 0b111;
    let mode = match tmode {
        4 | 6 => TestMode::ContinuousLight,
        5 => TestMode::ZeroBitStream,
        7 => TestMode::Normal,
        _ => return (pin_test_mode(variant, straps), TestModeSource::Pins),
    };
    (mode, TestModeSource::Register)
}

/// The test mode the pins TM0/TM1 ask for.
// 410B §2 TM0, TM1: "TM0 = 0 switches TxD1-6 to continuous signal light, TM1 = 0 switch-over
// to zero bit stream". 816 §2.3.3 table: 01 → continuous light, 10 → zero bit stream, 11 and
// 00 → none (00 only turns the repeater off). On the 410B both pins 0 is read as continuous
// light (TM0 takes precedence; docs/spec-notes.md).
pub const fn pin_test_mode(variant: Variant, straps: &Straps) -> TestMode {
    match (straps.tm0, straps.tm1) {
        (true, true) => TestMode::Normal,
        (false, true) => TestMode::ContinuousLight,
        (true, false) => TestMode::ZeroBitStream,
        (false, false) => match variant {
            Variant::Sercon410b => TestMode::ContinuousLight,
            Variant::Sercon816 => TestMode::Normal,
        },
    }
}

/// What one of the pins TxD1–6 outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TxdOutput {
    /// High impedance (ENTXDn = 0 while the pin carries transmit data).
    HighZ,
    /// The serial transmit data.
    TransmitData,
    /// A parallel output port at the given level (TxD2–6 with TXDMODE = 1).
    Port(bool),
}

/// What TxD1…TxD6 output (index 0 is TxD1), from ENTXD1–6 (2H.0–5) and TXDMODE (2H.6).
// 410B §2 TxD1: "can be switched to a high impedance state"; TxD6-2: "either output the serial
// data or can be used as parallel output ports. When they output transmit data, each pin can
// be switched to a high impedance state individually." §4.1 2H.0–5 ENTXD: 0 = high impedance,
// 1 = outputting transmit data; 2H.6 TXDMODE: 1 = TxD2-6 output ENTXD2-6 (docs/spec-notes.md).
pub const fn txd_outputs(reg2_value: u16) -> [TxdOutput; 6] {
    let port_mode = reg2_value & reg2::TXDMODE != 0;
    let mut out = [TxdOutput::HighZ; 6];
    let mut n = 0;
    while n < 6 {
        let en = (reg2_value & reg2::ENTXD_MASK) & (1 << n) != 0;
        out[n] = if n > 0 && port_mode {
            TxdOutput::Port(en)
        } else if en {
            TxdOutput::TransmitData
        } else {
            TxdOutput::HighZ
        };
        n += 1;
    }
    out
}

/// Whether RxD at electrical level `rxd_level` means "light on", by POLRXD (1H.7).
// 410B §4.1 1H.7 POLRXD: 0 = "light on" when RxD = 0, 1 = "light on" when RxD = 1.
pub const fn light_on_from_rxd(reg1_value: u16, rxd_level: bool) -> bool {
    rxd_level == (reg1_value & reg1::POLRXD != 0)
}

/// The electrical level of TxD for "light on" (`true`) or "light off", by POLTXD (1H.9).
// 410B §4.1 1H.9 POLTXD: 0 = "light on" when TxD = 0, 1 = "light on" when TxD = 1.
pub const fn txd_level_for_light(reg1_value: u16, light_on: bool) -> bool {
    light_on == (reg1_value & reg1::POLTXD != 0)
}

/// How the receive data is coded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RxdCoding {
    /// NRZI (reset).
    Nrzi,
    /// NRZ.
    Nrz,
}

/// The coding of the receive data, by RXDNRZ (1H.12).
// ERRATA 1H.12 (410B §4.1 prints "NRZI" for both values): 0 = NRZI (reset), 1 = NRZ.
pub const fn rxd_coding(reg1_value: u16) -> RxdCoding {
    if reg1_value & reg1::RXDNRZ != 0 {
        RxdCoding::Nrz
    } else {
        RxdCoding::Nrzi
    }
}

/// What drives the line-error output L_ERRN (pin 32), by LMODE0–1 (2H.14–15).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LErrnMode {
    /// LMODE = 0 (reset): active by FIBBR or RDIST.
    FibbrOrRdist,
    /// LMODE = 1: active by RDIST (receive data over the distortion limit).
    Rdist,
    /// LMODE = 2: active by FIBBR (no edges on the receive data).
    Fibbr,
    /// LMODE = 3: L_ERRN is inactive.
    Inactive,
}

impl LErrnMode {
    /// Whether L_ERRN is active for the status bits RDIST (2H.12) and FIBBR (2H.13).
    pub const fn is_active(self, rdist: bool, fibbr: bool) -> bool {
        match self {
            LErrnMode::FibbrOrRdist => rdist || fibbr,
            LErrnMode::Rdist => rdist,
            LErrnMode::Fibbr => fibbr,
            LErrnMode::Inactive => false,
        }
    }

    /// The electrical level of L_ERRN (active low) for RDIST and FIBBR.
    // 410B §2 L_ERRN: "Line error, active low".
    pub const fn pin_level(self, rdist: bool, fibbr: bool) -> bool {
        !self.is_active(rdist, fibbr)
    }
}

/// The L_ERRN mode programmed in LMODE0–1 (2H.14–15).
// 410B §4.1 2H.14–15: 0 = FIBBR and RDIST, 1 = RDIST, 2 = FIBBR, 3 = inactive.
pub const fn lerrn_mode(reg2_value: u16) -> LErrnMode {
    match (reg2_value >> reg2::LMODE_SHIFT) & 0b11 {
        0 => LErrnMode::FibbrOrRdist,
        1 => LErrnMode::Rdist,
        2 => LErrnMode::Fibbr,
        _ => LErrnMode::Inactive,
    }
}
