//! NERR counts each missing or erroneous receive telegram once (410B §4.2.1 receive header
//! word 4 NERR "Error counter"; RERR "errored or not received"; 5H.8 INT_RMISS "receive
//! telegram missing twice"), whichever event finds it missing: its TCHK window closing, the
//! next MST or cycle starting while it is still expected (17H PROGERR_FL overlap), or a
//! programming error in the header read after it (816 §2.10.1.2: the next header is read
//! when a telegram starts or its window closes).

mod common;
mod harness;

use harness::*;
use sercon_model::Chip;
use sercon_model::serial_port::LineSignal;
use sercon_regs::ram::header::TxEnable;
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};
use sercos_wire::time::{Duration, Instant};

/// ERRATA "telegram header marker bits": 10 is no structure (the processor stops there with
/// a programming error, 410B §4.1 17H).
const NO_HEADER: u16 = 0x8000;
/// 410B §4.1 5H.8 INT_RMISS.
const INT_RMISS: u16 = 1 << 8;

/// The MDT receive header of [`slave`] (word 4 is NERR).
const MDT_HDR: u16 = 16;
/// Where the MDT header's PT leads.
const AFTER_MDT: u16 = 25;

/// A SERCON816 slave in phase 4 whose block is COMPT0 → receive MDT (ADR 255, one word, TRT
/// `trt`, TCHK with JTRDEL1 = 2, JTRDEL2 = 3 when `tchk`) → the word at 25: an end marker, or
/// with `broken` a word that is no header.
fn slave(trt: u16, tchk: bool, broken: bool) -> Chip {
    let mut s = chip(Variant::Sercon816);
    s.write_ram(0, MDT_HDR);
    let mut r = rx(255, true, trt, 1, AFTER_MDT);
    r.tchk = tchk;
    rx_header(&mut s, MDT_HDR, r);
    s.write_ram_words(21, &[control(1, true), 0, 0]);
    if broken {
        s.write_ram_words(AFTER_MDT, &[NO_HEADER, 0]);
    } else {
        end_marker(&mut s, AFTER_MDT);
    }
    s.write(Register::Jtrdel1, 2);
    s.write(Register::Jtrdel2, 3);
    s.write(Register::Phas, 0xFF04);
    s.write(Register::Ctrl3, ENTMT);
    s.write(Register::Ctrl0C, MSTEN);
    s
}

/// Runs `s` µs by µs, handing it an MST of phase 4 every 100 µs from 10 µs on (a µs ahead of
/// its start, at 16 Mbit/s) and, with `mdt`, an MDT of one word `mdt` µs after each MST's
/// start; returns NERR of the MDT header 10 µs after every MST but the first, and the
/// INT_RMISS flags seen then.
fn nerr_after_msts(mut s: Chip, mdt: Option<u64>) -> (Vec<u16>, Vec<bool>) {
    let mut nerr = Vec::new();
    let mut rmiss = Vec::new();
    let mut buf = Vec::new();
    for t in 1..=1000u64 {
        let now = us(t);
        if t % 100 == 9 {
            s.line_input(common::hinted_frame(us(t + 1), &[255, 4]));
        }
        if let Some(d) = mdt
            && t >= 10
            && (t - 10) % 100 + 1 == d
        {
            s.line_input(common::hinted_frame(us(t + 1), &[255, 0x34, 0x12]));
        }
        s.advance_to(now);
        s.take_line_output(&mut buf);
        buf.clear();
        if t > 100 && t % 100 == 20 {
            nerr.push(s.read_ram(MDT_HDR + 4));
            rmiss.push(s.read(Register::IntFlagsHi) & INT_RMISS != 0);
        }
    }
    (nerr, rmiss)
}

/// 1, 2, … `n`.
fn one_per_cycle(n: usize) -> Vec<u16> {
    (1..=n as u16).collect()
}

// 410B §4.2.1 NERR, TCHK: a slave whose MDT never comes counts one error per cycle, whether
// its window closes before the next MST (TRT 5 … 96) or the next MST ends the block first
// (17H overlap; TRT 97 … 104: the window would close 100 … 107 µs after the MST's end).
#[test]
fn a_slave_missing_its_mdt_counts_one_error_per_cycle_whenever_the_next_mst_comes() {
    for trt in [5, 60, 94, 95, 96, 97, 98, 99, 100, 104] {
        for tchk in [true, false] {
            let (nerr, _) = nerr_after_msts(slave(trt, tchk, false), None);
            assert_eq!(nerr, one_per_cycle(9), "TRT {trt}, TCHK {tchk}");
        }
    }
}

// 410B §4.2.1 NERR, §4.1 17H PROGERR_FL: the MDT's window closes and the header after it is
// no header (a programming error that ends the block): the missing MDT is counted once, not
// once more by the block's end; INT_RMISS (5H.8, missing twice) only from the second cycle.
#[test]
fn a_programming_error_after_a_closed_window_does_not_count_the_telegram_again() {
    for trt in [5, 60, 96] {
        let (nerr, rmiss) = nerr_after_msts(slave(trt, true, true), None);
        assert_eq!(nerr, one_per_cycle(9), "TRT {trt}");
        // The first check follows one missed cycle (the second one's window is still
        // open then); INT_RMISS stays set once raised.
        assert!(
            rmiss.first() == Some(&false) && rmiss.iter().skip(1).all(|r| *r),
            "TRT {trt}: {rmiss:?}"
        );
    }
    // The first cycle alone: one miss, no INT_RMISS yet.
    let mut s = slave(5, true, true);
    s.line_input(common::hinted_frame(us(10), &[255, 4]));
    s.advance_to(us(40));
    assert_eq!(s.read_ram(MDT_HDR + 4), 1);
    assert_eq!(s.read(Register::IntFlagsHi) & INT_RMISS, 0, "missing once");
    assert_ne!(s.read(Register::ProgerrFl), 0, "the header after it");
}

// 410B §4.2.1 NERR, RERR; 816 §2.10.1.2 (the next header is read at the start of a
// telegram): a good MDT whose next header is no header ends the block when it starts, but
// it was received: no error is counted, RERR stays clear and its data are stored.
#[test]
fn a_programming_error_at_a_good_telegrams_start_counts_no_error() {
    let (nerr, rmiss) = nerr_after_msts(slave(5, true, true), Some(9));
    assert_eq!(nerr, vec![0; 9]);
    assert!(rmiss.iter().all(|r| !r), "{rmiss:?}");
    let mut s = slave(5, true, true);
    s.line_input(common::hinted_frame(us(10), &[255, 4]));
    s.line_input(common::hinted_frame(us(19), &[255, 0x34, 0x12]));
    s.advance_to(us(40));
    let w0 = s.read_ram(MDT_HDR);
    assert_eq!(w0 & (1 << 13), 0, "RERR");
    assert_eq!(s.read_ram(MDT_HDR + 4), 0, "NERR");
    assert_eq!(s.read_ram(23), 0x1234, "the data");
}

/// A SERCON816 master sending its MST every 100 µs and an MDT at TRT 5, then expecting an AT
/// (ADR 1, TRT `trt`, TCHK when `tchk`) whose PT leads to an end marker or, with `broken`, to
/// a word that is no header. Returns the master and the AT header's address.
fn master(trt: u16, tchk: bool, broken: bool) -> (Chip, u16) {
    let mut m = chip(Variant::Sercon816);
    m.write_ram(0, 16);
    tx_header(&mut m, 16, tx(255, TxEnable::Continuous, 5, 1, 29));
    m.write_ram_words(20, &[control(1, true), 0x0101]);
    let mut r = rx(1, true, trt, 1, 44);
    r.tchk = tchk;
    rx_header(&mut m, 29, r);
    m.write_ram_words(34, &[control(1, true), 0, 0]);
    if broken {
        m.write_ram_words(44, &[NO_HEADER, 0]);
    } else {
        end_marker(&mut m, 44);
    }
    let c1 = m.read(Register::Ctrl1);
    m.write(Register::Ctrl1, c1 & !REPON);
    m.write(Register::Jtrdel1, 2);
    m.write(Register::Jtrdel2, 3);
    m.write(Register::Phas, 0x0404);
    m.write(Register::Ctrl3, ENTMT);
    m.write(Register::Ctrl0C, MSTEN | MSTMASTER | CYCSTART);
    (m, 29)
}

/// Runs `m` to 1000 µs (its output goes nowhere: no AT comes back); returns NERR of the AT
/// header at `at` 10 µs after every MST but the first.
fn master_nerr(mut m: Chip, at: u16) -> Vec<u16> {
    let mut buf = Vec::new();
    let mut msts = Vec::new();
    let mut nerr = Vec::new();
    for t in 1..=1000u64 {
        let now = us(t);
        m.advance_to(now);
        m.take_line_output(&mut buf);
        for seg in buf.drain(..) {
            if let (LineSignal::Bits(_), Some(h)) = (&seg.signal, &seg.hint)
                && h.telegram.len() == 2
            {
                msts.push(seg.start);
            }
        }
        let k = msts
            .iter()
            .skip(1)
            .filter(|s| **s + Duration::from_micros(10) <= now)
            .count();
        while nerr.len() < k {
            nerr.push(m.read_ram(at + 4));
        }
    }
    nerr
}

// 410B §4.2.1 NERR, TCHK; §4.1 0CH cycle start: a master whose AT never comes counts one
// error per cycle, whether the AT's window closes first or the next cycle's block ends the
// one still waiting (with or without TCHK), and once only when the header after the AT is
// no header (17H PROGERR_FL).
#[test]
fn a_master_missing_its_at_counts_one_error_per_cycle() {
    for trt in [40, 94, 95, 96, 97, 98, 100, 104] {
        for (tchk, broken) in [(true, false), (false, false), (true, true)] {
            let (m, at) = master(trt, tchk, broken);
            let nerr = master_nerr(m, at);
            assert!(nerr.len() >= 8, "{nerr:?}");
            assert_eq!(
                nerr,
                one_per_cycle(nerr.len()),
                "TRT {trt}, TCHK {tchk}, broken {broken}"
            );
        }
    }
}

/// 410B §4.1 3H.11 FLREC: "Receiving telegram".
const FLREC: u16 = 1 << 11;

/// The one-word MDT at 19 µs, coded as a transmitter codes it from a dark line (the light
/// levels decode from `level_before`, as a receiver's decoder reads them).
fn mdt_at_19() -> sercon_model::serial_port::LineSegment {
    use sercos_wire::line::{BitVec, Coding, Encoder, LineConfig, Polarity};
    let mut seg = common::hinted_frame(us(19), &[255, 0x34, 0x12]);
    let mut enc = Encoder::new(LineConfig::new(Coding::Nrzi, Polarity::LightOnHigh));
    let mut bits = BitVec::new();
    enc.encode(&[255, 0x34, 0x12], &mut bits)
        .expect("encodable");
    seg.signal = LineSignal::Bits(sercon_model::serial_port::Shared::new(bits));
    seg
}

/// [`slave`] (TRT 5, TCHK) given an MST at 10 µs and a one-word MDT at 19 µs, advanced to
/// `before` µs; then the line from bit `cut` of the MDT on is `after` light levels (the RS-485
/// bus's second driver, spec-notes "RS-485 bus"); run to 40 µs. Returns the chip, whether
/// FLREC was set before the cut, and the frames it logged.
fn cut_mdt(
    before: u64,
    cut: u64,
    after: &[bool],
) -> (Chip, bool, Vec<sercon_model::serial_port::RxFrame>) {
    use sercon_model::serial_port::LineSegment;
    use sercos_wire::line::BitVec;
    let mut s = slave(5, true, false);
    s.line_input(common::hinted_frame(us(10), &[255, 4]));
    let mdt = mdt_at_19();
    let bt = mdt.bit_time;
    s.line_input(mdt.clone());
    s.advance_to(Instant::ZERO + Duration::from_nanos(before * 1000));
    let receiving = s.read(Register::Ctrl3) & FLREC != 0;
    let at = mdt.start + bt.saturating_mul(cut);
    let mut bits = BitVec::new();
    for b in after {
        bits.push(*b);
    }
    s.line_input(LineSegment::bits(at, bt, bits, mdt.level_at(at)));
    s.advance_to(us(40));
    let mut frames = Vec::new();
    s.take_rx_frames(&mut frames);
    (s, receiving, frames)
}

// 410B §4.2.1 RERR, NERR; spec-notes "RS-485 bus": a telegram whose line is garbled from a
// bit on (a second driver) is the frame the garbled line makes, whether the chip had taken
// its start (FLREC set) or not: an error, counted once, no data stored, and the intact frame
// it was first given is no longer in the receive log.
#[test]
fn a_telegram_cut_inside_on_its_bit_grid_is_the_frame_the_line_then_shows() {
    // 24 bit times of one level: no edge, an HDLC abort.
    let steady = |level: bool| vec![level; 24];
    // Every register and RAM word at 40 µs, per cut: the same whether the chip had taken
    // the telegram's start before the cut or not.
    let mut states: std::collections::HashMap<u64, Vec<u16>> = Default::default();
    for before in [18u64, 19, 20] {
        for cut in [0u64, 9, 12, 30, 45] {
            // Segments come before the chip passes their start (`Chip::line_input`).
            if before * 1_000_000 > 19_000_000 + cut * 62_500 {
                continue;
            }
            let mdt = mdt_at_19();
            let level = mdt.level_at(mdt.start + mdt.bit_time.saturating_mul(cut));
            let (mut s, receiving, frames) = cut_mdt(before, cut, &steady(level));
            let mut state: Vec<u16> = (0u8..0x40).map(|a| s.read_register(a)).collect();
            state.extend((0..2048).map(|a| s.read_ram(a)));
            assert_eq!(
                states.entry(cut).or_insert_with(|| state.clone()),
                &state,
                "cut at bit {cut}: the chip advanced to {before} µs ends elsewhere"
            );
            let name = format!("advanced to {before} µs, cut at bit {cut}");
            // From 19 µs on the chip took the MDT's start before its cut (FLREC).
            assert_eq!(receiving, before >= 19, "{name}");
            let w0 = s.read_ram(MDT_HDR);
            assert_ne!(w0 & (1 << 13), 0, "{name}: RERR");
            assert_eq!(s.read_ram(MDT_HDR + 4), 1, "{name}: NERR");
            assert_eq!(s.read_ram(23), 0, "{name}: no data");
            let mdts: Vec<_> = frames.iter().filter(|f| f.start == mdt.start).collect();
            assert!(mdts.iter().all(|f| !f.fcs_ok), "{name}: {frames:?}");
            assert!(mdts.len() <= 1, "{name}: {frames:?}");
        }
    }
    // The line going on as the telegram did (its own bits from the cut on) is the telegram.
    let mdt = mdt_at_19();
    let LineSignal::Bits(b) = &mdt.signal else {
        panic!("bits")
    };
    let rest: Vec<bool> = b.bits().iter().skip(30).collect();
    let (mut s, receiving, frames) = cut_mdt(20, 30, &rest);
    assert!(receiving);
    assert_eq!(s.read_ram(MDT_HDR + 4), 0, "NERR {frames:?}");
    assert_eq!(s.read_ram(23), 0x1234, "the data");
    let mdts: Vec<_> = frames.iter().filter(|f| f.start == mdt.start).collect();
    assert!(
        mdts.len() == 1 && mdts.iter().all(|f| f.fcs_ok),
        "{frames:?}"
    );
}
