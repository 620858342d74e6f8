//! Programming the controller as a SERCOS master: predivider, bit rate, repeater, cycle,
//! interrupts (410B §4.1; 816 §2.3.1, §2.11.1.2).

use sercon_regs::{
    Ctrl0C, Ctrl1, Ctrl3, En0IntHi, En0IntLo, IntFlagsHi, IntFlagsLo, MclkDiv, Phas, ScTimeout,
    SerconBus, SerconBusExt, Tcycstart, Tscyc0, Tscyc1, Variant, Version,
};
use sercos_wire::time::BitRate;

use super::config::MasterConfig;
use super::error::MasterErrorKind;

/// Interrupts the master works on (INT0): the end of the transmission block (once per
/// cycle, after the MDT) and a missing receive signal (410B §4.1 4H.4 INT_COMEND, 4H.1
/// INT_FIBBR).
pub(crate) const MASTER_INTERRUPTS: IntFlagsLo =
    IntFlagsLo::INT_COMEND.union(IntFlagsLo::INT_FIBBR);

/// 1H bits ENTSBAUD, SWBAUD, SWBAUD16 for `rate` with SCLK = 64 MHz, or `None` if the
/// chip cannot run it. `sbaud16_pin` is pin 28 as read in 1H.4 (816: SBAUD16).
// 816 §2.3.1 table; 410B §2 SBAUD: f_SCLK/16 (4 Mbit/s) or /32 (2 Mbit/s); ERRATA 1H.6/1H.10.
pub(crate) fn baud_bits(variant: Variant, sbaud16_pin: bool, rate: BitRate) -> Option<Ctrl1> {
    let low_range_only = variant == Variant::Sercon410b || sbaud16_pin;
    let base = Ctrl1::ENTSBAUD;
    match (rate, low_range_only) {
        (BitRate::Mbit2, true) => Some(base | Ctrl1::SWBAUD),
        (BitRate::Mbit4, true) => Some(base),
        (_, true) => None,
        (BitRate::Mbit2, false) => Some(base | Ctrl1::SWBAUD16 | Ctrl1::SWBAUD),
        (BitRate::Mbit4, false) => Some(base | Ctrl1::SWBAUD16),
        (BitRate::Mbit8, false) => Some(base | Ctrl1::SWBAUD),
        (BitRate::Mbit16, false) => Some(base),
    }
}

/// Programs the chip for `cfg` and leaves the MST off; [`start_cycles`] starts them.
pub(crate) fn init_chip<B: SerconBus + ?Sized>(
    bus: &mut B,
    cfg: &MasterConfig,
) -> Result<(), MasterErrorKind> {
    // 816 §2.11.1.1: VERSION tells the two controllers apart.
    let found = bus.read_reg::<Version>().0;
    if found != cfg.variant.version() {
        return Err(MasterErrorKind::WrongChip {
            found,
            expected: cfg.variant.version(),
        });
    }
    // 410B §4.1 0CH: stop MST and cycles while programming.
    bus.write_reg(Ctrl0C(0));
    // 410B §4.1 0EH MCLKDIV = f_MCLK / 1 MHz − 1 (816 §2.11.1.2: one bit wider).
    let div = MclkDiv::for_mclk(cfg.variant, cfg.mclk_hz)
        .map_err(|_| MasterErrorKind::Config("MCLK gives no 1 µs predivider"))?;
    let mclkdiv = MclkDiv(0)
        .with_mclkdiv(cfg.variant, div)
        .map_err(|_| MasterErrorKind::Config("MCLK gives no 1 µs predivider"))?;
    bus.write_reg(mclkdiv);
    // 1H: bit rate by control bits; REPON = 0, the master ends the ring (410B §1: "This ring
    // starts and ends at the master").
    let c1 = bus.read_reg::<Ctrl1>();
    let sbaud16_pin = c1.contains(Ctrl1::SREGEN);
    let baud = baud_bits(cfg.variant, sbaud16_pin, cfg.bit_rate).ok_or(MasterErrorKind::BitRate)?;
    let keep = c1 & (Ctrl1::REGMODE | Ctrl1::POLRXD | Ctrl1::POLTXD | Ctrl1::RXDNRZ);
    bus.write_reg(keep | baud);
    // 410B §4.1 0FH/10H: cycle time in µs for both transmission blocks.
    let cycle = u16::try_from(cfg.cycle_us).map_err(|_| MasterErrorKind::Config("cycle time"))?;
    bus.write_reg(Tscyc0(cycle));
    bus.write_reg(Tscyc1(cycle));
    // 410B §4.1 14H TCYCSTART: the cycle starts at the trigger.
    bus.write_reg(Tcycstart(0));
    // 410B §4.1 0DH: no chip timeouts; the driver times requests itself (spec-notes).
    bus.write_reg(ScTimeout::new(0, 0));
    // 410B §4.1 0AH: phase 0 in the MST.
    bus.write_reg(Phas::new(0, 0));
    // 410B §4.1 4H/5H: clear every flag (write 1), then 6H/7H: INT0 sources.
    bus.clear_int_lo(IntFlagsLo::all());
    bus.clear_int_hi(IntFlagsHi::all());
    bus.write_reg(En0IntLo(MASTER_INTERRUPTS));
    bus.write_reg(En0IntHi(IntFlagsHi::empty()));
    // 410B §4.1 3H: INT0 enabled, 1-active (ERRATA 3H.1, 3H.2); ENTMT sends data telegrams.
    bus.write_reg(Ctrl3::ENINT0 | Ctrl3::ENTMT);
    Ok(())
}

/// Starts the MST: SERCOS master mode, block `comblk0` for PHAS0, cycles run continuously
/// from now (410B §4.1 0CH MSTEN, MSTMASTER, COMBLK0, CYCSTART; NCYC = 0, spec-notes
/// "NCYC").
pub(crate) fn start_cycles<B: SerconBus + ?Sized>(bus: &mut B, comblk0: bool) {
    let c = Ctrl0C(0)
        .with_msten(true)
        .with_mstmaster(true)
        .with_comblk0(comblk0);
    bus.write_reg(c);
    bus.write_reg(c.with_cycstart(true));
}

/// Selects the block processed for the phase in PHAS0 from the next cycle on (410B §4.1
/// 0CH.2 COMBLK0, sampled at every cycle start).
pub(crate) fn select_block<B: SerconBus + ?Sized>(bus: &mut B, comblk0: bool) {
    let c = Ctrl0C(0)
        .with_msten(true)
        .with_mstmaster(true)
        .with_comblk0(comblk0);
    bus.write_reg(c);
}

/// Sends `phase` in the next MSTs (410B §4.1 0AH PHAS0).
pub(crate) fn set_phase<B: SerconBus + ?Sized>(bus: &mut B, phase: u8) {
    bus.write_reg(Phas::new(phase, 0));
}

#[cfg(test)]
mod tests {
    use super::*;

    // 816 §2.3.1 table rows 7-10 (ENTSBAUD = 1, SBAUD16 = 0) and rows 3-4 / 410B §2.
    #[test]
    fn baud_bits_follow_the_816_table() {
        let v = Variant::Sercon816;
        assert_eq!(
            baud_bits(v, false, BitRate::Mbit2),
            Some(Ctrl1::ENTSBAUD | Ctrl1::SWBAUD | Ctrl1::SWBAUD16)
        );
        assert_eq!(
            baud_bits(v, false, BitRate::Mbit4),
            Some(Ctrl1::ENTSBAUD | Ctrl1::SWBAUD16)
        );
        assert_eq!(
            baud_bits(v, false, BitRate::Mbit8),
            Some(Ctrl1::ENTSBAUD | Ctrl1::SWBAUD)
        );
        assert_eq!(baud_bits(v, false, BitRate::Mbit16), Some(Ctrl1::ENTSBAUD));
        // SBAUD16 = 1 (compatible mode) and the 410B: 2 and 4 Mbit/s only.
        assert_eq!(baud_bits(v, true, BitRate::Mbit16), None);
        assert_eq!(baud_bits(Variant::Sercon410b, true, BitRate::Mbit8), None);
        assert_eq!(
            baud_bits(Variant::Sercon410b, true, BitRate::Mbit2),
            Some(Ctrl1::ENTSBAUD | Ctrl1::SWBAUD)
        );
    }
}
