//! The slave's fixed configuration: controller, address, clocks, bit rate, the master's
//! phase 0–2 cycle and the buffering of cyclic data; and the register bits it gives.

use sercon_regs::ram::header::Buffering;
use sercon_regs::{Ctrl1, MclkDiv, Variant};
use sercos_wire::time::BitRate;

use super::error::SlaveError;
use crate::ram_layout::DEFAULT_SERVICE_BUFFER_WORDS;

/// Cycle time of phases 0–2 assumed until the master writes S-0-0002: 2 ms, customary in
/// phases 1–2 (sercos-facts.md, Kollmorgen S300/S700; the captures' master uses 2 ms).
pub const DEFAULT_NONCYCLIC_CYCLE_US: u32 = 2000;

/// The SCLK of the boards in the documents: 64 MHz (410B §3.2 f_SCLK max; 816 §2.3.1).
pub const DEFAULT_SCLK_HZ: u64 = 64_000_000;

/// Everything about a slave that does not come from its IDN store.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SlaveConfig {
    /// The controller on the board.
    pub variant: Variant,
    /// The drive address, 1–254 (sercos-telegrams.md: set by a selector on the drive).
    pub address: u8,
    /// MCLK frequency in Hz (410B §3.4.1: 12–20 MHz; 816 §2.4.1).
    pub mclk_hz: u32,
    /// SCLK frequency in Hz (410B §3.4.2).
    pub sclk_hz: u64,
    /// The line's bit rate (a switch on the drive).
    pub bit_rate: BitRate,
    /// The master's cycle in phases 0–2, µs: only sets TSCYC0 and the phase 0–2 slots, whose
    /// AT slot (right after the MST) does not depend on it (spec-notes "Driver slave").
    pub noncyclic_cycle_us: u32,
    /// Buffering of the cyclic data in phases 3–4 (single or double; DMA is refused).
    pub buffering: Buffering,
    /// Words of the service container's buffer.
    pub service_buffer_words: u16,
}

impl SlaveConfig {
    /// A slave at `address` with the variant's usual clocks (816: MCLK 32 MHz, 410B:
    /// 20 MHz; SCLK 64 MHz), 2 Mbit/s, a 2 ms phase 0–2 cycle, single buffer, 32-word
    /// service buffer.
    pub fn new(variant: Variant, address: u8) -> SlaveConfig {
        SlaveConfig {
            variant,
            address,
            mclk_hz: match variant {
                Variant::Sercon816 => 32_000_000,
                Variant::Sercon410b => 20_000_000,
            },
            sclk_hz: DEFAULT_SCLK_HZ,
            bit_rate: BitRate::Mbit2,
            noncyclic_cycle_us: DEFAULT_NONCYCLIC_CYCLE_US,
            buffering: Buffering::Single,
            service_buffer_words: DEFAULT_SERVICE_BUFFER_WORDS,
        }
    }

    /// Checks what can be checked without the chip.
    pub fn validate(&self) -> Result<(), SlaveError> {
        // sercos-telegrams.md ADR: drive addresses 1-254.
        if self.address == 0 || self.address == 255 {
            return Err(SlaveError::InvalidAddress(self.address));
        }
        if self.buffering == Buffering::Dma {
            return Err(SlaveError::DmaNotSupported);
        }
        self.mclkdiv()?;
        Ok(())
    }

    /// 0EH: MCLKDIV = f_MCLK / 1 MHz − 1 and MCLKST the same (410B §4.1 0EH).
    pub fn mclkdiv(&self) -> Result<MclkDiv, SlaveError> {
        let err = SlaveError::Predivider {
            mclk_hz: self.mclk_hz,
        };
        // 410B §4.1 0EH MCLKDIV "fMCLK/1 MHz - 1"; a predivider of 0 would be 1 MHz MCLK.
        if self.mclk_hz < 1_000_000 || self.mclk_hz % 1_000_000 != 0 {
            return Err(err);
        }
        let div = MclkDiv::for_mclk(self.variant, self.mclk_hz).map_err(|_| err.clone())?;
        MclkDiv(0)
            .with_mclkdiv(self.variant, div)
            .and_then(|m| m.with_mclkst(self.variant, div))
            .map_err(|_| err)
    }

    /// The bits ENTSBAUD, SWBAUD and SWBAUD16 of register 1H that select the bit rate from
    /// SCLK. `pin28` is the level of pin 28 (1H.4: SREGEN on the 410B, SBAUD16 on the 816).
    /// `Ok(None)`: the 410B with SREGEN = 0 takes its clock from RxC/TxC (410B §2 SREGEN),
    /// the bits do not matter.
    pub fn bit_rate_bits(&self, pin28: bool) -> Result<Option<Ctrl1>, SlaveError> {
        let err = SlaveError::BitRate {
            variant: self.variant,
            rate: self.bit_rate,
            sclk_hz: self.sclk_hz,
        };
        let bps = self.bit_rate.bits_per_second();
        if self.sclk_hz % bps != 0 {
            return Err(err);
        }
        let divisor = self.sclk_hz / bps;
        // ERRATA 1H.10: ENTSBAUD = 1 takes the rate from the control bits.
        let low_range = |slow: bool| {
            let mut bits = Ctrl1::ENTSBAUD;
            if slow {
                bits |= Ctrl1::SWBAUD;
            }
            bits
        };
        match (self.variant, pin28, divisor) {
            // 410B §2 SREGEN = 0: RxC/TxC are clock inputs.
            (Variant::Sercon410b, false, _) => Ok(None),
            // 410B §2 SBAUD, ERRATA 1H.6: SWBAUD 0 = f_SCLK/16, 1 = f_SCLK/32; the same on
            // the 816 with SBAUD16 = 1 (816 §2.3.1 rows 1-4).
            (_, true, 16) => Ok(Some(low_range(false))),
            (_, true, 32) => Ok(Some(low_range(true))),
            // 816 §2.3.1 rows 5-10 (SBAUD16 = 0): SWBAUD16 = 1 picks /16 and /32,
            // SWBAUD16 = 0 picks /4 and /8, SWBAUD the slower one.
            (Variant::Sercon816, false, 16) => Ok(Some(low_range(false) | Ctrl1::SWBAUD16)),
            (Variant::Sercon816, false, 32) => Ok(Some(low_range(true) | Ctrl1::SWBAUD16)),
            (Variant::Sercon816, false, 4) => Ok(Some(low_range(false))),
            (Variant::Sercon816, false, 8) => Ok(Some(low_range(true))),
            _ => Err(err),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // 816 §2.3.1: at SCLK = 64 MHz with SBAUD16 = 0, 16 Mbit/s is SCLK/4 (SWBAUD16 = 0,
    // SWBAUD = 0) and 2 Mbit/s is SCLK/32 (SWBAUD16 = 1, SWBAUD = 1).
    #[test]
    fn bit_rate_bits_follow_the_816_table() {
        let mut c = SlaveConfig::new(Variant::Sercon816, 1);
        c.bit_rate = BitRate::Mbit16;
        assert_eq!(c.bit_rate_bits(false), Ok(Some(Ctrl1::ENTSBAUD)));
        c.bit_rate = BitRate::Mbit2;
        assert_eq!(
            c.bit_rate_bits(false),
            Ok(Some(Ctrl1::ENTSBAUD | Ctrl1::SWBAUD | Ctrl1::SWBAUD16))
        );
        // SBAUD16 = 1: only 2 and 4 Mbit/s.
        c.bit_rate = BitRate::Mbit8;
        assert!(c.bit_rate_bits(true).is_err());
    }

    // 410B §2 SREGEN = 0: external clock; SREGEN = 1: SCLK/16 or /32 only.
    #[test]
    fn bit_rate_bits_on_the_410b() {
        let mut c = SlaveConfig::new(Variant::Sercon410b, 1);
        c.bit_rate = BitRate::Mbit4;
        assert_eq!(c.bit_rate_bits(true), Ok(Some(Ctrl1::ENTSBAUD)));
        assert_eq!(c.bit_rate_bits(false), Ok(None));
        c.bit_rate = BitRate::Mbit16;
        assert!(c.bit_rate_bits(true).is_err());
    }

    // 410B §4.1 0EH: MCLKDIV = fMCLK / 1 MHz - 1 (19 at 20 MHz).
    #[test]
    fn predivider_and_address_checks() {
        let c = SlaveConfig::new(Variant::Sercon410b, 7);
        assert_eq!(c.mclkdiv().map(|m| m.mclkdiv()), Ok(19));
        assert_eq!(
            SlaveConfig::new(Variant::Sercon410b, 0).validate(),
            Err(SlaveError::InvalidAddress(0))
        );
        let mut odd = c;
        odd.mclk_hz = 12_500_000;
        assert!(odd.validate().is_err());
    }
}
