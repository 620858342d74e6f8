//! Typed register values: field positions per 410B §4.1 and 816 §2.11, and the typed
//! accessors over `SerconBus`.

mod common;

use common::MemBus;
use sercon_regs::Variant::{Sercon410b, Sercon816};
use sercon_regs::*;

#[test]
fn ctrl2_fields() {
    // 410B §4.1 2H: ENTXD1-6 0-5 (reset 1), TXDMODE 6, TMODE 9-7, TM0-1 11-10, RDIST 12,
    // FIBBR 13, LMODE 15-14.
    let r = Ctrl2::RESET;
    assert_eq!(r.entxd(), TxdPins::all());
    assert_eq!(r.tmode(), TestMode::PinControlled);
    assert_eq!(r.lmode(), LineErrorMode::FibbrAndRdist);
    let v = r
        .with_entxd(TxdPins::TXD1)
        .with_tmode(TestMode::ZeroBitStream)
        .with_lmode(LineErrorMode::Inactive)
        .with_txdmode(true);
    assert_eq!(v.0, 0x0001 | 1 << 6 | 5 << 7 | 3 << 14);
    // 410B §4.1 2H TMODE: 0-3 pins, 4 and 6 continuous light, 5 zero bits, 7 normal.
    for (code, mode) in [
        (0, TestMode::PinControlled),
        (3, TestMode::PinControlled),
        (4, TestMode::ContinuousLight),
        (5, TestMode::ZeroBitStream),
        (6, TestMode::ContinuousLight),
        (7, TestMode::Normal),
    ] {
        let v = Ctrl2(0).with_tmode_code(code).expect("3 bits");
        assert_eq!(v.tmode(), mode);
        assert_eq!(v.tmode_code(), code);
    }
    assert!(Ctrl2(0).with_tmode_code(8).is_err());
    assert_eq!(Ctrl2(0x0C00).tm(), 3);
    assert!(Ctrl2(1 << 12).rdist() && Ctrl2(1 << 13).fibbr());
}

#[test]
fn ctrl1_and_ctrl3_flags_are_at_their_datasheet_bits() {
    // 410B §4.1 1H and 3H bit numbers; 816 §2.3.1 SWBAUD16 = 1H.15; ERRATA 1H.6 SWBAUD.
    assert_eq!(Ctrl1::RSTFL.bits(), 1);
    assert_eq!(Ctrl1::SWRST.bits(), 1 << 1);
    assert_eq!(Ctrl1::SWBAUD.bits(), 1 << 6);
    assert_eq!(Ctrl1::ENTSBAUD.bits(), 1 << 10);
    assert_eq!(Ctrl1::SWBAUD16.bits(), 1 << 15);
    assert_eq!(
        (Ctrl1::RSTFL | Ctrl1::REPON | Ctrl1::REGMODE).bits(),
        0x0029
    );
    assert_eq!(Ctrl3::ENTMT.bits(), 1 << 8);
    assert_eq!(Ctrl3::REACTN.bits(), 1 << 15);
}

#[test]
fn interrupt_flags() {
    // 410B §4.1 4H: INT_RDIST 0 … INT_RERR 15; 5H: INT_SC_0-7 0-7, INT_RMISS 8,
    // INT_TIME0-3 9-12, INT_DIVCLK 13, INT_PROGERR 14, INT_NEWADR 15.
    assert_eq!(IntFlagsLo::INT_RDIST.bits(), 1);
    assert_eq!(IntFlagsLo::INT_MSTMIS.bits(), 1 << 9);
    assert_eq!(IntFlagsLo::INT_REND.bits(), 1 << 14);
    assert_eq!(IntFlagsLo::INT_RERR.bits(), 1 << 15);
    assert_eq!(IntFlagsHi::int_sc(7), Some(IntFlagsHi::INT_SC_7));
    assert_eq!(IntFlagsHi::int_sc(8), None);
    assert_eq!(IntFlagsHi::INT_RMISS.bits(), 1 << 8);
    assert_eq!(IntFlagsHi::int_time(3), Some(IntFlagsHi::INT_TIME3));
    assert_eq!(IntFlagsHi::INT_TIME3.bits(), 1 << 12);
    assert_eq!(IntFlagsHi::int_time(4), None);
    assert_eq!(IntFlagsHi::INT_NEWADR.bits(), 1 << 15);
    // 816 §2.11.2 28H: INT_WDOG bit 1, INT_RSCEND bit 6.
    assert_eq!(WdogStatus::INT_WDOG.bits(), 1 << 1);
    assert_eq!(WdogStatus::INT_RSCEND.bits(), 1 << 6);
    assert_eq!(
        WdogCommand::CLR_INT_WDOG.bits(),
        WdogStatus::INT_WDOG.bits()
    );
    assert_eq!(
        WdogCommand::CLR_RSCEND.bits(),
        WdogStatus::INT_RSCEND.bits()
    );
}

#[test]
fn watchdog_read_modify_write_keeps_only_enables() {
    // 816 §2.11.2 28H: bits 0, 1, 2, 6 act on write; 3, 4, 5, 7, 8 are R/W.
    let status = WdogStatus::all();
    assert_eq!(WdogCommand::keeping_enables(status).bits(), 0x01B8);
    // 816 §2.6.4: the software trigger is 42H in WDOG_TRIG (29H.7-0).
    assert!(WdogTrig::TRIGGER.is_trigger());
    assert!(WdogTrig(0xFF42).is_trigger());
    assert!(!WdogTrig(0x0043).is_trigger());
}

#[test]
fn mclkdiv_widths_per_variant() {
    // 816 §2.11.1.2: MCLKDIV/MCLKST 4-0/12-8 on the 410B, 5-0/13-8 on the 816.
    assert_eq!(MclkDiv::RESET.mclkdiv(), 19);
    let v = MclkDiv(0)
        .with_mclkdiv(Sercon816, 63)
        .and_then(|v| v.with_mclkst(Sercon816, 33));
    assert_eq!(v.map(|v| v.0), Ok(0x213F));
    assert!(MclkDiv(0).with_mclkdiv(Sercon410b, 32).is_err());
    assert_eq!(
        MclkDiv(0).with_mclkst(Sercon410b, 31).map(|v| v.mclkst()),
        Ok(31)
    );
    // 410B §4.1 0EH: MCLKDIV = f_MCLK / 1 MHz − 1.
    assert_eq!(MclkDiv::for_mclk(Sercon410b, 20_000_000), Ok(19));
    assert_eq!(MclkDiv::for_mclk(Sercon816, 64_000_000), Ok(63));
    assert!(MclkDiv::for_mclk(Sercon410b, 64_000_000).is_err());
    assert_eq!(MclkDiv::for_mclk(Sercon410b, 0), Ok(0));
}

#[test]
fn other_multi_bit_fields() {
    // 410B §4.1 0AH, 0BH, 0DH, 0CH NCYC 15-12, 20H, 25H.
    let p = Phas::new(2, 3);
    assert_eq!((p.0, p.phas0(), p.phas1()), (0x0302, 2, 3));
    assert_eq!(Phas::RESET.phas0(), 0xFF);
    let r = PhasRec(0x0704);
    assert_eq!((r.phasrec(), r.recadr()), (4, 7));
    let t = ScTimeout::new(10, 20);
    assert_eq!((t.0, t.hs_timeout(), t.busy_timeout()), (0x140A, 10, 20));
    let c = Ctrl0C(0)
        .with_msten(true)
        .with_mstmaster(true)
        .with_ncyc(15)
        .expect("4 bits");
    assert_eq!(c.0, 0xF003);
    assert!(Ctrl0C(0).with_ncyc(16).is_err());
    assert!(Ctrl0C(1 << 10).cycstart() && Ctrl0C(1 << 11).rdcnt());
    let n = Ndivclk(0)
        .with_ndivclk(200)
        .with_poldivclk(true)
        .with_divclkmode(true);
    assert_eq!(n.0, 200 | 1 << 8 | 1 << 9);
    // THRPT stays bits 9-0 (bit 10 is MSTTCHK); THTPT/THWPT read 11 bits.
    let x = Thrpt(0x1FFF);
    assert_eq!(x.thrpt(), 0x3FF);
    assert!(x.msttchk() && x.phas12() && x.flmdtadr());
    assert_eq!(Thtpt(0xFFFF).thtpt(), 0x7FF);
    assert_eq!(Thwpt(0x0400).thwpt(), 0x400);
    assert_eq!(Tht(0x4005).kind(), Ok(ram::header::HeaderKind::Transmit));
    assert_eq!(Thr(0x0009).adr(), 9);
}

#[test]
fn typed_accessors_over_the_bus() {
    let mut bus = MemBus::new(Sercon816);
    bus.regs[0] = 0x0010;
    assert_eq!(bus.detect_variant(), Some(Sercon816));
    bus.write_reg(Phas::new(4, 1));
    assert_eq!(bus.regs[0x0A], 0x0104);
    assert_eq!(bus.read_reg::<Phas>().phas0(), 4);
    bus.write(Register::Tscyc0, 1000);
    assert_eq!(bus.read_reg::<Tscyc0>(), Tscyc0(1000));
    bus.modify_reg(|c: Ctrl3| c | Ctrl3::ENTMT);
    assert_eq!(bus.read(Register::Ctrl3), 1 << 8);
    bus.clear_int_lo(IntFlagsLo::INT_REND);
    assert_eq!(bus.regs[4], 1 << 14);
    bus.write_reg(WdogTrig::TRIGGER);
    assert_eq!(bus.regs[0x29], 0x42);
    // 410B §4.1 27H: a read pops RFIFO, a write pushes TFIFO.
    bus.rfifo.extend([7, 8]);
    assert_eq!(bus.read_reg::<Fifo>(), Fifo(7));
    bus.write_reg(Fifo(9));
    assert_eq!((bus.rfifo.len(), bus.tfifo.as_slice()), (1, &[9][..]));
}

#[test]
fn headers_over_the_bus() {
    // 410B §4.2.1: word 0 decides how many words the structure has.
    let mut bus = MemBus::new(Sercon410b);
    let tx = ram::header::Header::Transmit(ram::header::TxHeader {
        adr: 3,
        tlen: 4,
        pt: 0x40,
        ..Default::default()
    });
    bus.write_header(Sercon410b, 0x20, &tx);
    bus.write_ram_words(0x40, &[0xC000, 500]);
    assert_eq!(bus.read_header(Sercon410b, 0x20), Ok(tx));
    bus.ram_reads = 0;
    let end = bus.read_header(Sercon410b, 0x40);
    assert!(matches!(end, Ok(ram::header::Header::End(e)) if e.tend == 500));
    assert_eq!(bus.ram_reads, 2);
    bus.write_ram(0x60, 0x8000);
    assert_eq!(
        bus.read_header(Sercon410b, 0x60),
        Err(RamError::InvalidMarker { word0: 0x8000 })
    );
    assert_eq!(bus.read_ram_words::<2>(0x40), [0xC000, 500]);
    // Addresses wrap at the end of the 16-bit word-address space without panicking.
    let _ = bus.read_ram_words::<3>(0xFFFF);
}
