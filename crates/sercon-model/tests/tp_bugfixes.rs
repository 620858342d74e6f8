//! The two SERCON816 bug fixes against their SERCON410B behaviour (816 §2.9, §2.10.1),
//! phase 1/2 unicast exchange, and programming errors (410B §4.1 17H PROGERR_FL).

mod harness;

use harness::*;
use sercon_model::serial_port::LineSignal;
use sercon_regs::ram::header::TxEnable;
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};
use sercos_wire::time::Duration;

/// Phase 2: the master addresses drive 1 with an MDT (unicast, ADR 1) in the cycles it
/// chooses; the slave's AT (EN = 3) answers only when the MDT carried its address.
fn phase2(variant: Variant) -> Ring {
    let mut m = chip(variant);
    let mut s = chip(variant);
    // Master: tx MDT (adr 1, EN = 1 once, 2 words) → end marker.
    m.write_ram(0, 16);
    tx_header(&mut m, 16, tx(1, TxEnable::Once, 5, 2, 23));
    m.write_ram_words(20, &[control(2, true), 0xAAAA, 0x5555]);
    end_marker(&mut m, 23);
    // Slave: rx MDT (adr 1, ACHK) → tx AT (adr 1, EN = 3) → end marker.
    s.write_ram(0, 16);
    // TCHK with the window TRT − 2 ..= TRT + 5 µs (410B §4.1 18H/19H JTRDEL1/2): a
    // missing MDT ends the wait, so the walk reaches the AT header in every cycle.
    let mut r = rx(1, true, 5, 2, 25);
    r.tchk = true;
    rx_header(&mut s, 16, r);
    s.write(Register::Jtrdel1, 2);
    s.write(Register::Jtrdel2, 5);
    s.write_ram_words(21, &[control(2, true), 0, 0, 0]);
    tx_header(&mut s, 25, tx(1, TxEnable::OnAddress, 40, 2, 32));
    s.write_ram_words(29, &[control(2, true), 0x1234, 0x5678]);
    end_marker(&mut s, 32);
    s.write(Register::Phas, 0xFF02);
    s.write(Register::Thrpt, PHAS12);
    s.write(Register::Ctrl3, ENTMT);
    s.write(Register::Ctrl0C, MSTEN);
    m.write(Register::Phas, 0x0202);
    m.write(Register::Ctrl3, ENTMT);
    m.write(Register::Ctrl0C, MSTEN | MSTMASTER | CYCSTART);
    Ring::new(m, s)
}

fn ats(ring: &Ring) -> usize {
    ring.log.iter().filter(|(m, _)| !*m).count()
}

#[test]
fn phase2_unicast_mdt_is_answered_by_one_at_on_the_816() {
    // 816 §2.9.2: "the flag FLMDTADR is reset after starting to send a telegram when
    // initiated when the flag is set. Therefore sending AT's can occur only once."
    let mut ring = phase2(Variant::Sercon816);
    ring.run_to(us(450));
    assert_eq!(words(&mut ring.slave, 23, 2), vec![0xAAAA, 0x5555]);
    assert_eq!(ats(&ring), 1);
    let at = ring
        .log
        .iter()
        .find(|(m, _)| !*m)
        .map(|(_, t)| t.bytes.clone());
    assert_eq!(at, Some(vec![1, 0x34, 0x12, 0x78, 0x56]));
    assert_eq!(ring.slave.read(Register::Thrpt) & FLMDTADR, 0);
    // 410B §4.2.1 EN = 1: the master's header went back to EN = 0 after the start.
    assert_eq!((ring.master.read_ram(16) >> 11) & 3, 0);
}

#[test]
fn phase2_at_repeats_on_the_410b_until_another_address() {
    // 816 §2.9.1: "The SERCON410B is constantly sending the telegram until the master is
    // requesting another drive"; a missing MDT does not reset FLMDTADR (§2.9.2).
    let mut ring = phase2(Variant::Sercon410b);
    ring.run_to(us(450));
    assert!(ats(&ring) >= 4, "{}", ats(&ring));
    assert_ne!(ring.slave.read(Register::Thrpt) & FLMDTADR, 0);
}

/// A slave whose AT is double-buffered with EN = 1; the host flips VAL between the
/// header read (NTH, at the start of the preceding MDT) and the AT's start.
fn val_race(variant: Variant) -> Vec<u8> {
    let mut ring = phase2(variant);
    // AT: EN = 1, double buffer, VAL = 0; buffer 0 = 0x0101…, buffer 1 = 0x0202….
    let mut h = tx(1, TxEnable::Once, 40, 2, 34);
    h.dbuf = true;
    tx_header(&mut ring.slave, 25, h);
    ring.slave
        .write_ram_words(29, &[control(2, true), 0x0101, 0x0101, 0x0202, 0x0202]);
    end_marker(&mut ring.slave, 34);
    ring.slave.write(Register::Thrpt, 0);
    // The MDT ends about 8 µs after the MST; the AT starts 40 µs after it.
    ring.run_to(us(20));
    let w0 = ring.slave.read_ram(25);
    ring.slave.write_ram(25, w0 | (1 << 10));
    ring.run_to(us(90));
    let at = ring
        .log
        .iter()
        .find(|(m, _)| !*m)
        .map(|(_, t)| t.bytes.clone());
    let w0 = ring.slave.read_ram(25);
    let mut out = at.unwrap_or_default();
    out.push(u8::from(w0 & (1 << 10) != 0));
    out
}

#[test]
fn val_written_between_telegrams_is_kept_on_the_816() {
    // 816 §2.10.1.2: "the VAL bit is read from the telegram header at start of a
    // transmit telegram again"; "This new VAL bit is then used".
    assert_eq!(val_race(Variant::Sercon816), vec![1, 2, 2, 2, 2, 1]);
}

#[test]
fn val_written_between_telegrams_is_lost_on_the_410b() {
    // 816 §2.10.1.1: on the 410B "the new VAL bit information is overwritten with its
    // old value by the telegram processor" when the header is written back (EN = 1).
    assert_eq!(val_race(Variant::Sercon410b), vec![1, 1, 1, 1, 1, 0]);
}

#[test]
fn header_loop_is_a_programming_error() {
    // 410B §4.1 17H PROGERR_FL, 5H.14 INT_PROGERR: a list whose PT points back to itself
    // never reaches an end marker; the model reports and carries on.
    let mut m = chip(Variant::Sercon816);
    m.write_ram(0, 16);
    rx_header(&mut m, 16, rx(1, false, 5, 0, 16));
    m.write_ram_words(21, &[control(0, true), 0]);
    m.write(Register::Ctrl3, ENTMT);
    m.write(Register::Ctrl0C, MSTEN | MSTMASTER | CYCSTART);
    m.advance_to(us(250));
    assert_ne!(m.read(Register::IntFlagsHi) & (1 << 14), 0);
    assert_ne!(m.read(Register::ProgerrFl), 0);
    // CLR_PROGERR_FL: writing 1s clears.
    m.write(Register::ProgerrFl, 0xFFFF);
    assert_eq!(m.read(Register::ProgerrFl), 0);
}

#[test]
fn header_past_the_end_of_the_ram_is_a_programming_error() {
    // ERRATA "word addresses": the 816 has 2048 words; a header at 2046 needs 4.
    let mut m = chip(Variant::Sercon816);
    m.write_ram(0, 2046);
    m.write_ram(2046, 0x4000);
    m.write(Register::Ctrl3, ENTMT);
    m.write(Register::Ctrl0C, MSTEN | MSTMASTER | CYCSTART);
    m.advance_to(us(50));
    assert_eq!(m.read(Register::ProgerrFl) & 1, 1);
}

#[test]
fn overlapping_transmit_telegrams_are_a_programming_error() {
    // Two transmit telegrams at the same TRT: the second would overlap the first.
    let mut m = chip(Variant::Sercon816);
    m.write_ram(0, 16);
    tx_header(&mut m, 16, tx(1, TxEnable::Continuous, 5, 4, 25));
    m.write_ram(20, control(4, true));
    tx_header(&mut m, 25, tx(2, TxEnable::Continuous, 5, 4, 34));
    m.write_ram(29, control(4, true));
    end_marker(&mut m, 34);
    m.write(Register::Ctrl3, ENTMT);
    m.write(Register::Ctrl0C, MSTEN | MSTMASTER | CYCSTART);
    m.advance_to(us(50));
    assert_ne!(m.read(Register::ProgerrFl) & (1 << 3), 0);
}

#[test]
fn an_mst_due_while_the_last_one_goes_out_is_not_sent() {
    // A cycle (2 µs) shorter than the MST (3.375 µs at 16 Mbit/s): an MST due while the
    // transmitter still sends the one before is a programming error and is not sent (410B
    // §4.1 17H PROGERR_FL bit 3 as for transmit telegrams; spec-notes "An MST due while the
    // transmitter is busy"), so one goes out at every second cycle start. Queued behind it
    // instead, MSTs piled up without end (the fuzz target bus_sequence found ≈ 1.4 GB after
    // ≈ 1 s).
    let mut m = chip(Variant::Sercon816);
    m.write(Register::Tscyc0, 2);
    m.write_ram(0, 16);
    end_marker(&mut m, 16);
    m.write(Register::Ctrl3, ENTMT);
    m.write(Register::Ctrl0C, MSTEN | MSTMASTER | CYCSTART);
    m.advance_to(us(2000));
    let mut out = Vec::new();
    m.take_line_output(&mut out);
    let msts: Vec<_> = out
        .iter()
        .filter(|s| matches!(s.signal, LineSignal::Bits(_)))
        .map(|s| (s.start, s.end().unwrap_or(s.start)))
        .collect();
    assert_eq!(
        msts.len(),
        501,
        "an MST every second cycle from 0 to 2000 µs"
    );
    for (w, pair) in msts.windows(2).enumerate() {
        let [(start, end), (next, _)] = pair else {
            continue;
        };
        assert!(end.saturating_duration_since(*start) < Duration::from_micros(4));
        assert_eq!(
            next.saturating_duration_since(*start),
            Duration::from_micros(4),
            "MST {w} and the next two cycles apart"
        );
    }
    assert_ne!(m.read(Register::ProgerrFl) & (1 << 3), 0);
}
