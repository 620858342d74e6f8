//! MST reception by a slave: phase, misses, time window (410B §4.1 0AH, 0BH, 4H.5-9,
//! 15H/16H, 25H.10; §4.2 word 10 NMSTERR).

mod harness;

use harness::*;
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};

/// A master sending only MSTs (phase `phase`) every 100 µs and a slave expecting
/// PHAS0 = 4; both blocks are just an end marker.
fn mst_ring_on(variant: Variant, phase: u16) -> Ring {
    let mut m = chip(variant);
    let mut s = chip(variant);
    for c in [&mut m, &mut s] {
        c.write_ram(0, 16);
        end_marker(c, 16);
    }
    s.write(Register::Phas, 0xFF04);
    s.write(Register::Jtscyc1, 3);
    s.write(Register::Jtscyc2, 3);
    s.write(Register::Thrpt, MSTTCHK);
    s.write(Register::Ctrl0C, MSTEN);
    m.write(Register::Phas, 0xFF00 | phase);
    m.write(Register::Ctrl0C, MSTEN | MSTMASTER | CYCSTART);
    Ring::new(m, s)
}

fn mst_ring(phase: u16) -> Ring {
    mst_ring_on(Variant::Sercon816, phase)
}

#[test]
fn slave_takes_the_phase_and_syncs_its_cycle() {
    // 410B §4.1 0BH PHASREC; 3H.6 COMACT while the block runs; no errors.
    let mut ring = mst_ring(4);
    ring.run_to(us(250));
    assert_eq!(ring.slave.read(Register::PhasRec) & 0xFF, 4);
    let lo = ring.slave.read(Register::IntFlagsLo);
    // INT_COMBLK0 and INT_COMEND, no PHASERR / MSTEARLY / MSTLATE / MSTMIS.
    assert_eq!(lo & 0b11_1110_0000, 0, "{lo:04x}");
    assert_ne!(lo & (1 << 2), 0);
    assert_ne!(lo & (1 << 4), 0);
    assert_eq!(ring.slave.read_ram(10), 0);
}

#[test]
fn wrong_phase_raises_phaserr_and_phase0_raises_phas0() {
    // 410B §4.1 4H.6 INT_PHASERR "phase MST errored", 4H.5 INT_PHAS0 "phase MST = 0".
    let mut ring = mst_ring(3);
    ring.run_to(us(150));
    assert_ne!(ring.slave.read(Register::IntFlagsLo) & (1 << 6), 0);
    let mut ring = mst_ring(0);
    ring.run_to(us(150));
    assert_ne!(ring.slave.read(Register::IntFlagsLo) & (1 << 5), 0);
}

/// One master telegram (MSTs counted from 0) lost with `lose(ring, [1])`, then two in a
/// row with `lose(ring, [1, 2])`: NMSTERR counts each, INT_MSTMIS only the second; the MSTs
/// after them are taken again.
fn one_then_two_lost(lose: impl Fn(&mut Ring, Vec<usize>)) {
    let mut ring = mst_ring(4);
    lose(&mut ring, vec![1]);
    ring.run_to(us(250));
    assert_eq!(ring.slave.read_ram(10), 1);
    assert_eq!(ring.slave.read(Register::IntFlagsLo) & (1 << 9), 0);
    let mut ring = mst_ring(4);
    lose(&mut ring, vec![1, 2]);
    ring.run_to(us(350));
    assert_eq!(ring.slave.read_ram(10), 2);
    assert_ne!(ring.slave.read(Register::IntFlagsLo) & (1 << 9), 0);
    ring.run_to(us(650));
    assert_eq!(ring.slave.read_ram(10), 2);
}

#[test]
fn two_missing_msts_count_and_raise_mstmis() {
    // 410B §4.2 NMSTERR "Error counter MST", 4H.9 INT_MSTMIS "MST missing twice".
    one_then_two_lost(|ring, lost| ring.drop_master = lost);
}

#[test]
fn late_and_early_msts_with_msttchk() {
    // 410B §4.1 25H.10 MSTTCHK, 15H/16H JTSCYC1/2, 4H.7 INT_MSTEARLY, 4H.8 INT_MSTLATE.
    let mut ring = mst_ring(4);
    ring.run_to(us(150));
    assert_eq!(ring.slave.read(Register::IntFlagsLo) & (3 << 7), 0);
    // The master's next cycle is 10 µs longer: its MST arrives late.
    ring.master.write(Register::Tscyc0, 110);
    ring.run_to(us(260));
    assert_ne!(ring.slave.read(Register::IntFlagsLo) & (1 << 8), 0);
    let mut ring = mst_ring(4);
    ring.run_to(us(150));
    ring.master.write(Register::Tscyc0, 90);
    ring.run_to(us(260));
    assert_ne!(ring.slave.read(Register::IntFlagsLo) & (1 << 7), 0);
}

#[test]
fn mst_loss_and_late_mst_on_the_line_on_both_variants() {
    // 410B §4.2 NMSTERR, 4H.9 INT_MSTMIS; 25H.10 MSTTCHK with 16H JTSCYC2, 4H.8 INT_MSTLATE.
    // The 410B runs at 4 Mbit/s (its MST lasts 12 µs), the 816 at 16 Mbit/s.
    for variant in Variant::ALL {
        // Two MSTs lost on the fibre (master telegrams 1 and 2: no MDTs in this ring).
        let mut ring = mst_ring_on(variant, 4);
        ring.drop_master = vec![1, 2];
        ring.run_to(us(350));
        assert_eq!(ring.slave.read_ram(10), 2, "{variant:?}");
        let lo = ring.slave.read(Register::IntFlagsLo);
        assert_ne!(lo & (1 << 9), 0, "{variant:?} INT_MSTMIS");
        // The MST after the loss is good again: PHASREC holds its phase.
        assert_eq!(ring.slave.read(Register::PhasRec) & 0xFF, 4);
        // One lost MST is counted but not reported twice-missing.
        let mut ring = mst_ring_on(variant, 4);
        ring.drop_master = vec![1];
        ring.run_to(us(350));
        assert_eq!(ring.slave.read_ram(10), 1, "{variant:?}");
        assert_eq!(
            ring.slave.read(Register::IntFlagsLo) & (1 << 9),
            0,
            "{variant:?}"
        );
        // A late MST: the master's cycle grows by more than JTSCYC2 = 3 µs.
        let mut ring = mst_ring_on(variant, 4);
        ring.run_to(us(150));
        assert_eq!(
            ring.slave.read(Register::IntFlagsLo) & (3 << 7),
            0,
            "{variant:?}"
        );
        ring.master.write(Register::Tscyc0, 105);
        ring.run_to(us(260));
        let lo = ring.slave.read(Register::IntFlagsLo);
        assert_ne!(lo & (1 << 8), 0, "{variant:?} INT_MSTLATE");
        assert_eq!(lo & (1 << 7), 0, "{variant:?} not early");
        // Later than TSCYC + JTSCYC2 the window has closed: counted missing once (spec-notes
        // "MST"), not twice.
        assert_eq!(ring.slave.read_ram(10), 1, "{variant:?}");
        assert_eq!(lo & (1 << 9), 0, "{variant:?} no INT_MSTMIS");
    }
}

#[test]
fn phase_byte_change_shifting_the_mst_end_by_a_bit_is_not_a_missing_mst() {
    // Task mst3, spec-notes "MST window in whole µs": the MST of phase 3 carries one
    // stuffed bit more than that of phase 2, so it ends one bit time (< 1 µs) later than
    // TSCYC after the phase 2 MST. The chip times the MST in whole µs (410B §4.1 16H
    // JTSCYC2, 4H.8 INT_MSTLATE), so it is on time: NMSTERR (410B §4.2 word 10) stays 0
    // and the slave follows PHAS1 (0AH, 0CH.3 COMBLK1) — here with JTSCYC2 = 0.
    for variant in Variant::ALL {
        let mut ring = mst_ring_on(variant, 2);
        ring.slave.write(Register::Phas, 0x0302);
        ring.slave.write(Register::Jtscyc2, 0);
        ring.run_to(us(450));
        assert_eq!(ring.slave.read(Register::PhasRec) & 0xFF, 2, "{variant:?}");
        ring.master.write(Register::Phas, 0xFF03);
        ring.run_to(us(850));
        assert_eq!(ring.slave.read(Register::PhasRec) & 0xFF, 3, "{variant:?}");
        let lo = ring.slave.read(Register::IntFlagsLo);
        // No INT_PHASERR (6), INT_MSTEARLY (7), INT_MSTLATE (8), INT_MSTMIS (9).
        assert_eq!(lo & (0b1111 << 6), 0, "{variant:?} {lo:04x}");
        assert_eq!(ring.slave.read_ram(10), 0, "{variant:?} NMSTERR");
    }
}

#[test]
fn msts_of_block_1_are_timed_by_tscyc1_also_when_its_cycle_ends_with_them() {
    // 410B §4.1 0FH/10H TSCYC0/1, 0CH.3 (PHAS1 selects block 1), 25H.10 MSTTCHK with
    // 15H/16H JTSCYC1/2: a slave in block 1 expects its MSTs TSCYC1 apart. On an ideal ring
    // the slave's cycle (one TSCYC1 from the last MST's end) ends on the very tick the next
    // MST ends; the window is still that of block 1 (spec-notes "MST window of the last
    // cycle"), not TSCYC0 for want of a running cycle.
    let mut m = chip(Variant::Sercon816);
    let mut s = chip(Variant::Sercon816);
    for c in [&mut m, &mut s] {
        c.write_ram(0, 16);
        c.write_ram(1, 16);
        end_marker(c, 16);
    }
    s.write(Register::Phas, 0x0504);
    s.write(Register::Tscyc1, 200);
    s.write(Register::Jtscyc1, 3);
    s.write(Register::Jtscyc2, 3);
    s.write(Register::Thrpt, MSTTCHK);
    s.write(Register::Ctrl0C, MSTEN | (1 << 3));
    m.write(Register::Tscyc0, 200);
    m.write(Register::Phas, 0xFF05);
    m.write(Register::Ctrl0C, MSTEN | MSTMASTER | CYCSTART);
    let mut ring = Ring::new(m, s);
    ring.run_to(us(1250));
    let lo = ring.slave.read(Register::IntFlagsLo);
    // 4H.3 INT_COMBLK1: block 1 ran; no INT_MSTEARLY / INT_MSTLATE (4H.7/8), INT_MSTMIS (4H.9).
    assert_ne!(lo & (1 << 3), 0, "{lo:04x}");
    assert_eq!(lo & (7 << 7), 0, "{lo:04x}");
    // §4.2 word 10 NMSTERR: no MST counted missing.
    assert_eq!(ring.slave.read_ram(10), 0);
}

#[test]
fn a_corrupted_mst_counts_as_missing() {
    // 410B §4.2 word 10 NMSTERR, 4H.9 INT_MSTMIS: an MST whose FCS fails is not taken (no
    // phase, no cycle synchronisation); it counts as missing when its window closes, as a
    // lost one does (spec-notes "MST later than TSCYC + JTSCYC2").
    one_then_two_lost(|ring, corrupted| ring.corrupt_master = corrupted);
}
