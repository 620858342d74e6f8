//! The register access table checked row by row against the datasheet (410B §4.1) and
//! the delta specification (816 §2.3.1, §2.7, §2.11), both variants.

use sercon_regs::{Register, RegisterSpec, Variant, register_spec, reset_values};

/// (reset, rw, read_only, write_action, w1c) of one register on one variant.
type Masks = (u16, u16, u16, u16, u16);

/// One row: register, where the datasheet says it, masks on the 410B and on the 816
/// (`None` = the register does not exist).
struct Row {
    register: Register,
    source: &'static str,
    on_410b: Option<Masks>,
    on_816: Option<Masks>,
}

const fn both(register: Register, source: &'static str, m: Masks) -> Row {
    Row {
        register,
        source,
        on_410b: Some(m),
        on_816: Some(m),
    }
}

const fn rw16(register: Register, source: &'static str) -> Row {
    both(register, source, (0, 0xFFFF, 0, 0, 0))
}

const fn ro16(register: Register, source: &'static str) -> Row {
    both(register, source, (0, 0, 0xFFFF, 0, 0))
}

#[rustfmt::skip]
fn rows() -> Vec<Row> {
    use Register::*;
    vec![
        Row { register: Version, source: "410B §4.1 0H VERSION R 0002H; 816 §2.11.1.1 0010H",
              on_410b: Some((0x0002, 0, 0xFFFF, 0, 0)), on_816: Some((0x0010, 0, 0xFFFF, 0, 0)) },
        // RSTFL 1, REPON 1, REGMODE 1 (bold); SWRST W; SREGEN, SBAUD R; bit 2 unused;
        // bit 15 SWBAUD16 on the 816 only.
        Row { register: Ctrl1, source: "410B §4.1 1H; 816 §2.3.1 SWBAUD16 1H.15; ERRATA 1H.15",
              on_410b: Some((0x0029, 0x77E9, 0x0810, 0x0002, 0)),
              on_816: Some((0x0029, 0xF7E9, 0x0810, 0x0002, 0)) },
        // ENTXD1-6 reset 1; TMODE, LMODE, TXDMODE R/W; TM0-1, RDIST, FIBBR R.
        both(Ctrl2, "410B §4.1 2H", (0x003F, 0xC3FF, 0x3C00, 0, 0)),
        // ENINT0, POLINT0, ENINT1, POLINT1, ENTMT R/W; IDLE, REACTN inactive (1).
        both(Ctrl3, "410B §4.1 3H", (0xC000, 0x0136, 0xFEC9, 0, 0)),
        both(IntFlagsLo, "410B §4.1 4H INT_n R / CLR_INT_n W; ERRATA 4H/5H", (0, 0, 0, 0, 0xFFFF)),
        both(IntFlagsHi, "410B §4.1 5H INT_n R / CLR_INT_n W; ERRATA 4H/5H", (0, 0, 0, 0, 0xFFFF)),
        rw16(En0IntLo, "410B §4.1 6H EN0_INT_n R/W"),
        rw16(En0IntHi, "410B §4.1 7H EN0_INT_n R/W"),
        rw16(En1IntLo, "410B §4.1 8H EN1_INT_n R/W"),
        rw16(En1IntHi, "410B §4.1 9H EN1_INT_n R/W"),
        both(Phas, "410B §4.1 0AH PHAS0/PHAS1 R/W reset 0FFH; ERRATA 0AH", (0xFFFF, 0xFFFF, 0, 0, 0)),
        ro16(PhasRec, "410B §4.1 0BH PHASREC/RECADR R"),
        // CON_CLK 4, CYC_CLK 7 R; CYCSTART 10, RDCNT 11 W; the rest R/W.
        both(Ctrl0C, "410B §4.1 0CH", (0, 0xF36F, 0x0090, 0x0C00, 0)),
        rw16(ScTimeout, "410B §4.1 0DH HS_TIMEOUT/BUSY_TIMEOUT R/W"),
        Row { register: MclkDiv, source: "410B §4.1 0EH reset 19; 816 §2.11.1.2 widths; ERRATA 0EH",
              on_410b: Some((19, 0x1F1F, 0, 0, 0)), on_816: Some((19, 0x3F3F, 0, 0, 0)) },
        rw16(Tscyc0, "410B §4.1 0FH TSCYC0 R/W"),
        rw16(Tscyc1, "410B §4.1 10H TSCYC1 R/W"),
        ro16(Tcycdel, "410B §4.1 11H TCYCDEL R"),
        ro16(Tcntlt, "410B §4.1 12H TCNTLT R"),
        rw16(Tcntst, "410B §4.1 13H TCNTST R/W"),
        rw16(Tcycstart, "410B §4.1 14H TCYCSTART R/W"),
        rw16(Jtscyc1, "410B §4.1 15H JTSCYC1 R/W"),
        rw16(Jtscyc2, "410B §4.1 16H JTSCYC2 R/W"),
        both(ProgerrFl, "410B §4.1 17H PROGERR_FL R / CLR_PROGERR_FL W", (0, 0, 0, 0, 0xFFFF)),
        rw16(Jtrdel1, "410B §4.1 18H JTRDEL1 R/W"),
        rw16(Jtrdel2, "410B §4.1 19H JTRDEL2 R/W"),
        rw16(Tint0, "410B §4.1 1AH TINT0 R/W"),
        rw16(Tint1, "410B §4.1 1BH TINT1 R/W"),
        rw16(Tint2, "410B §4.1 1CH TINT2 R/W"),
        rw16(Tint3, "410B §4.1 1DH TINT3 R/W"),
        rw16(Tdivclk, "410B §4.1 1EH TDIVCLK R/W"),
        rw16(Dtdivclk, "410B §4.1 1FH DTDIVCLK R/W"),
        Row { register: Ndivclk, source: "410B §4.1 20H NDIVCLK/POLDIVCLK reset 0; 816 §2.7 DIVCLKMODE 20H.9",
              on_410b: Some((0, 0x01FF, 0, 0, 0)), on_816: Some((0, 0x03FF, 0, 0, 0)) },
        Row { register: Thtpt, source: "410B §4.1 21H THTPT 9-0 R; ERRATA pointers 11 bits on 816",
              on_410b: Some((0, 0, 0x03FF, 0, 0)), on_816: Some((0, 0, 0x07FF, 0, 0)) },
        ro16(Tht, "410B §4.1 22H THT R"),
        Row { register: Thwpt, source: "410B §4.1 23H THWPT 9-0 R; ERRATA pointers 11 bits on 816",
              on_410b: Some((0, 0, 0x03FF, 0, 0)), on_816: Some((0, 0, 0x07FF, 0, 0)) },
        ro16(Thw, "410B §4.1 24H THW R"),
        // THRPT keeps 10 bits on the 816: bit 10 is MSTTCHK (spec-notes).
        both(Thrpt, "410B §4.1 25H THRPT R, MSTTCHK/PHAS12/FLMDTADR R/W reset 0", (0, 0x1C00, 0x03FF, 0, 0)),
        ro16(Thr, "410B §4.1 26H THR R"),
        both(Fifo, "410B §4.1 27H RFIFO R / TFIFO W", (0, 0, 0xFFFF, 0xFFFF, 0)),
        Row { register: WdogCtrl, source: "816 §2.11.2 28H; ERRATA 28H.2, 28H.6",
              on_410b: None, on_816: Some((0, 0x01B8, 0x0005, 0x0005, 0x0042)) },
        Row { register: WdogTrig, source: "816 §2.11.2 29H WDOG_TRIG 7-0 W",
              on_410b: None, on_816: Some((0, 0, 0, 0x00FF, 0)) },
        Row { register: Twdog, source: "816 §2.11.2 2AH TWDOG R/W",
              on_410b: None, on_816: Some((0, 0xFFFF, 0, 0, 0)) },
    ]
}

fn expected(m: Option<Masks>) -> RegisterSpec {
    match m {
        None => RegisterSpec::ABSENT,
        Some((reset, rw, read_only, write_action, w1c)) => RegisterSpec {
            exists: true,
            reset,
            rw,
            read_only,
            write_action,
            w1c,
        },
    }
}

#[test]
fn every_register_matches_its_datasheet_row_on_both_variants() {
    let rows = rows();
    // Every register has exactly one row.
    assert_eq!(rows.len(), Register::ALL.len());
    for (row, register) in rows.iter().zip(Register::ALL) {
        assert_eq!(row.register, register, "rows out of address order");
        for (variant, m) in [
            (Variant::Sercon410b, row.on_410b),
            (Variant::Sercon816, row.on_816),
        ] {
            assert_eq!(
                row.register.spec(variant),
                expected(m),
                "{:?} on {variant:?} ({})",
                row.register,
                row.source
            );
        }
    }
}

#[test]
fn masks_are_disjoint_and_reset_values_use_no_unused_bits() {
    // 410B §4.1: unused bits read 0, so no reset value may have them set; a bit is
    // either R/W, read-only, write-1-to-clear or unused (write actions may also be status).
    for variant in Variant::ALL {
        for register in Register::ALL {
            let s = register.spec(variant);
            assert_eq!(s.rw & s.read_only, 0, "{register:?}");
            assert_eq!(s.rw & s.w1c, 0, "{register:?}");
            assert_eq!(s.read_only & s.w1c, 0, "{register:?}");
            assert_eq!(s.write_action & (s.rw | s.w1c), 0, "{register:?}");
            assert_eq!(s.reset & s.unused(), 0, "{register:?} on {variant:?}");
            assert_eq!(s.reset & !s.readable(), 0, "{register:?} on {variant:?}");
        }
    }
}

#[test]
fn addresses_without_a_register_read_zero_and_ignore_writes() {
    // 410B §4.1: A6-1 decode 00H–3FH; only 00H–27H (410B) / 00H–2AH (816) are registers.
    for variant in Variant::ALL {
        for address in 0u8..=255 {
            let spec = register_spec(variant, address);
            let decoded = address & 0x3F;
            let exists = decoded <= variant.last_register_address();
            assert_eq!(spec.exists, exists, "{address:#x} on {variant:?}");
            if !exists {
                assert_eq!(spec, RegisterSpec::ABSENT);
                assert_eq!(spec.read_value(0xFFFF, 0xFFFF), 0);
            }
        }
    }
}

#[test]
fn the_816_registers_read_zero_on_the_410b() {
    // 816 §2.11.2: 28H–2AH are new; task reading: they read 0 on the 410B.
    for register in [Register::WdogCtrl, Register::WdogTrig, Register::Twdog] {
        assert!(!register.exists_on(Variant::Sercon410b));
        assert!(register.exists_on(Variant::Sercon816));
        assert_eq!(register.spec(Variant::Sercon410b).readable(), 0);
    }
}

#[test]
fn reset_values_table_matches_the_specs() {
    for variant in Variant::ALL {
        let values = reset_values(variant);
        for (address, value) in values.iter().enumerate() {
            let address = u8::try_from(address).unwrap_or(u8::MAX);
            assert_eq!(*value, register_spec(variant, address).reset);
        }
        // 410B §4.1 0AH PHAS0/PHAS1 reset 0FFH; 0EH MCLKDIV reset 19.
        assert_eq!(values[0x0A], 0xFFFF);
        assert_eq!(values[0x0E], 19);
        assert_eq!(values[0x00], variant.version());
    }
}

#[test]
fn read_and_write_follow_the_masks() {
    // 410B §4.1: R/W bits read back; unused bits read 0; read-only bits come from the chip.
    let s = Register::Ctrl1.spec(Variant::Sercon410b);
    let stored = s.stored_after_write(0, 0xFFFF);
    assert_eq!(stored, 0x77E9);
    // SREGEN and SBAUD pins high: they show; SWRST (action) reads 0; bit 15 reads 0.
    assert_eq!(s.read_value(stored, 0xFFFF), 0x77E9 | 0x0810);
    let s816 = Register::Ctrl1.spec(Variant::Sercon816);
    assert_eq!(
        s816.read_value(s816.stored_after_write(0, 0x8000), 0),
        0x8000
    );
    // 816 §2.11.2 28H: WDOG_STAT and WDOUT_STAT read the status, not what was written.
    let w = Register::WdogCtrl.spec(Variant::Sercon816);
    assert_eq!(w.read_value(w.stored_after_write(0, 0x0001), 0), 0);
    assert_eq!(w.read_value(0, 0x0047), 0x0047);
}

#[test]
fn register_addresses_and_names() {
    for register in Register::ALL {
        assert_eq!(Register::from_address(register.address()), Some(register));
        assert_eq!(register.byte_address(), register.address() * 2);
        assert!(!register.datasheet_name().is_empty());
    }
    // 410B §4.1: TSCYC0 at 0FH, RFIFO/TFIFO at 27H; 816 §2.11.2: TWDOG at 2AH.
    assert_eq!(Register::Tscyc0.address(), 0x0F);
    assert_eq!(Register::Fifo.address(), 0x27);
    assert_eq!(Register::Twdog.address(), 0x2A);
    assert_eq!(Register::from_address(0x2B), None);
}

#[test]
fn variant_data() {
    // 816 §2.11.1.1 VERSION; §2.5 RAM size; ERRATA pointer width; §2.11.1.2 MCLKDIV.
    let a = Variant::Sercon410b;
    let b = Variant::Sercon816;
    assert_eq!((a.version(), b.version()), (0x0002, 0x0010));
    assert_eq!(Variant::from_version(0x0010), Some(b));
    assert_eq!(Variant::from_version(0x0003), None);
    assert_eq!((a.ram_words(), b.ram_words()), (1024, 2048));
    assert_eq!((a.pointer_bits(), b.pointer_bits()), (10, 11));
    assert_eq!((a.pointer_mask(), b.pointer_mask()), (0x3FF, 0x7FF));
    assert_eq!((a.mclkdiv_bits(), b.mclkdiv_bits()), (5, 6));
    assert!(!a.has_swbaud16() && b.has_swbaud16());
    assert!(!a.has_divclkmode() && b.has_divclkmode());
    assert!(!a.has_watchdog() && b.has_watchdog());
}

#[test]
fn repon_after_reset() {
    // 410B §4.1 1H REPON reset 1; 816 §2.3.3 table: only TM0 = TM1 = 0 gives REPON 0.
    for (tm0, tm1) in [(false, false), (false, true), (true, false), (true, true)] {
        assert!(Variant::Sercon410b.repon_after_reset(tm0, tm1));
        assert_eq!(Variant::Sercon816.repon_after_reset(tm0, tm1), tm0 || tm1);
    }
}

/// 410B §4.1 27H: only a read of RFIFO changes the chip (it takes the oldest word of the
/// receive FIFO); A6-1 decode the address, so 67H is 27H.
#[test]
fn only_a_read_of_rfifo_has_an_effect() {
    use sercon_regs::register::read_has_effect;
    for address in 0..=u8::MAX {
        assert_eq!(
            read_has_effect(address),
            Register::from_address(address & 0x3F) == Some(Register::Fifo),
            "{address:02X}H"
        );
    }
    assert!(read_has_effect(0x27) && read_has_effect(0x67));
    assert!(!read_has_effect(0x03) && !read_has_effect(0x04));
}
