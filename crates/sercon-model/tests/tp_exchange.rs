//! Master and slave exchanging MDT and AT through the telegram processor (410B §4.2.1–
//! §4.2.3, §4.1 3H, 4H, 11H, 21H–27H).

mod harness;

use harness::*;
use sercon_model::pins::{Pin, PinSet};
use sercon_regs::ram::header::{RxHeader, TxEnable};
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Buf {
    Single,
    Double,
    Dma,
}

fn data_words(b: Buf) -> u16 {
    match b {
        Buf::Single => 8,
        Buf::Double => 16,
        Buf::Dma => 0,
    }
}

/// Addresses of the interesting words.
struct Layout {
    /// Master: MDT data (buffer 0), AT receive header, AT receive data.
    m_mdt_data: u16,
    m_at_hdr: u16,
    m_at_data: u16,
    /// Slave: MDT receive header, MDT receive data, AT data.
    s_mdt_hdr: u16,
    s_mdt_data: u16,
    s_at_data: u16,
}

/// Phase 4, one slave (address 1): broadcast MDT of 8 words at TRT 5, AT of 8 words at
/// TRT 40, cycle 100 µs; MDT/AT with buffering `b` on the receive and transmit side.
fn phase4(variant: Variant, b: Buf) -> (Ring, Layout) {
    phase4_timed(variant, b, 40, 100)
}

/// [`phase4`] with the AT at TRT `at_trt` and a cycle of `tscyc` µs.
fn phase4_timed(variant: Variant, b: Buf, at_trt: u16, tscyc: u16) -> (Ring, Layout) {
    let mut m = chip(variant);
    let mut s = chip(variant);
    m.write(Register::Tscyc0, tscyc);
    s.write(Register::Tscyc0, tscyc);
    let dw = data_words(b);
    let dma = b == Buf::Dma;
    let dbuf = b == Buf::Double;
    // Master: COMPT0 → tx MDT → rx AT → end marker.
    m.write_ram(0, 16);
    let p1 = 16 + 4 + 1 + dw;
    let mut h = tx(255, TxEnable::Continuous, 5, 8, p1);
    h.dma = dma;
    h.dbuf = dbuf;
    tx_header(&mut m, 16, h);
    m.write_ram(20, control(8, true));
    let p2 = p1 + 5 + 2 + dw;
    let mut r = rx(1, true, at_trt, 8, p2);
    r.dma = dma;
    r.dbuf = dbuf;
    rx_header(&mut m, p1, r);
    m.write_ram_words(p1 + 5, &[control(8, true), 0]);
    end_marker(&mut m, p2);
    // Slave: COMPT0 → rx MDT → tx AT → end marker.
    s.write_ram(0, 16);
    let q1 = 16 + 5 + 2 + dw;
    let mut r = rx(255, true, 5, 8, q1);
    r.dma = dma;
    r.dbuf = dbuf;
    rx_header(&mut s, 16, r);
    s.write_ram_words(21, &[control(8, true), 0]);
    let q2 = q1 + 4 + 1 + dw;
    let mut h = tx(1, TxEnable::Continuous, at_trt, 8, q2);
    h.dma = dma;
    h.dbuf = dbuf;
    tx_header(&mut s, q1, h);
    s.write_ram(q1 + 4, control(8, true));
    end_marker(&mut s, q2);
    start_phase4(&mut m, &mut s);
    let layout = Layout {
        m_mdt_data: 21,
        m_at_hdr: p1,
        m_at_data: p1 + 7,
        s_mdt_hdr: 16,
        s_mdt_data: 23,
        s_at_data: q1 + 5,
    };
    (Ring::new(m, s), layout)
}

fn fill(c: &mut sercon_model::Chip, at: u16, base: u16) -> Vec<u16> {
    let v: Vec<u16> = (0..8).map(|i| base + i).collect();
    c.write_ram_words(at, &v);
    v
}

#[test]
fn phase4_single_buffer_exchange() {
    // 410B §4.2.1/§4.2.2: single buffer, data stored by POS/LEN, VAL = 1 after an
    // error-free receive telegram, RERR = 0, NERR unchanged.
    let (mut ring, l) = phase4(Variant::Sercon816, Buf::Single);
    let mdt = fill(&mut ring.master, l.m_mdt_data, 0x1100);
    let at = fill(&mut ring.slave, l.s_at_data, 0x2200);
    // Up to just before the fourth AT starts (cycle 3 begins at 300 µs).
    ring.run_to(us(340));
    assert_eq!(words(&mut ring.slave, l.s_mdt_data, 8), mdt);
    assert_eq!(words(&mut ring.master, l.m_at_data, 8), at);
    let sh = RxHeader::decode(Variant::Sercon816, &words(&mut ring.slave, l.s_mdt_hdr, 5)).unwrap();
    assert!(sh.val && !sh.rerr && sh.nerr == 0, "{sh:?}");
    let mh = RxHeader::decode(Variant::Sercon816, &words(&mut ring.master, l.m_at_hdr, 5)).unwrap();
    assert!(mh.val && !mh.rerr && mh.nerr == 0, "{mh:?}");
    // 410B §4.1 4H.10/11 INT_TSTART/INT_TEND, 13/14 INT_RSTART/INT_REND, 4H.4 INT_COMEND.
    let lo = ring.slave.read(Register::IntFlagsLo);
    for bit in [4, 10, 11, 12, 13, 14] {
        assert!(lo & (1 << bit) != 0, "slave 4H = {lo:04x}, bit {bit}");
    }
    assert_eq!(lo & (1 << 15), 0, "no INT_RERR");
    // 410B §4.1 0BH PHASREC = 4 (slave), RECADR = 255 (the MDT).
    assert_eq!(ring.slave.read(Register::PhasRec), 0xFF04);
    // 410B §4.1 11H TCYCDEL: the master's MST returns 2 µs after it left.
    assert_eq!(ring.master.read(Register::Tcycdel), 2);
    assert_eq!(ring.master.read(Register::ProgerrFl), 0);
    assert_eq!(ring.slave.read(Register::ProgerrFl), 0);
    // One MST, one MDT per 100 µs cycle from the master; one AT from the slave.
    let master_sent = ring.log.iter().filter(|(m, _)| *m).count();
    let slave_sent = ring.log.iter().filter(|(m, _)| !*m).count();
    assert_eq!(master_sent, 8);
    assert_eq!(slave_sent, 3);
}

#[test]
fn telegram_times_follow_trt_after_the_end_of_the_mst() {
    // 410B §4.2.1 TRT: "Time for the start of telegram in µs after end of MST"; the
    // frame's duration is its exact bit length at 16 Mbit/s (62.5 ns per bit).
    let (mut ring, _) = phase4(Variant::Sercon816, Buf::Single);
    ring.run_to(us(100));
    let sent: Vec<_> = ring.log.iter().map(|(m, t)| (*m, t.clone())).collect();
    let mst = &sent[0].1;
    assert_eq!(mst.bytes, vec![255, 4]);
    let bit_ps = 62_500u64;
    let bits = sercos_wire::line::frame_bit_len(&mst.bytes);
    assert_eq!((mst.end - mst.start).as_picos(), bits * bit_ps);
    let mdt = &sent[1].1;
    assert!(sent[1].0);
    // MCLK 32 MHz: the MST end is taken at the next MCLK edge, TRT = 5 µs after it.
    let mst_end_ps = mst.end.as_picos().div_ceil(31_250) * 31_250;
    assert_eq!(mdt.start.as_picos(), mst_end_ps + 5_000_000);
    assert_eq!(mdt.bytes.len(), 17);
    let at = sent
        .iter()
        .find(|(m, _)| !*m)
        .map(|(_, t)| t.clone())
        .unwrap();
    // The slave sees the MST 1 µs later; its AT starts 40 µs after that MST's end.
    let slave_mst_end = (mst.end.as_picos() + 1_000_000).div_ceil(31_250) * 31_250;
    assert_eq!(at.start.as_picos(), slave_mst_end + 40_000_000);
    assert_eq!(at.bytes.first(), Some(&1));
}

#[test]
fn phase4_double_buffer_toggles_val() {
    // 410B §4.2.1 VAL, double buffer: the controller toggles VAL at the end of each
    // receive telegram to the buffer just written; transmit data come from buffer VAL.
    let (mut ring, l) = phase4(Variant::Sercon816, Buf::Double);
    // Master sends from buffer 1 (VAL = 1): put the data there, garbage in buffer 0.
    fill(&mut ring.master, l.m_mdt_data, 0xDEAD);
    let mdt = fill(&mut ring.master, l.m_mdt_data + 8, 0x3300);
    let w0 = ring.master.read_ram(16);
    ring.master.write_ram(16, w0 | (1 << 10));
    ring.run_to(us(60));
    // One MDT received: VAL went from 0 to 1, data in buffer 1.
    let h = RxHeader::decode(Variant::Sercon816, &words(&mut ring.slave, l.s_mdt_hdr, 5)).unwrap();
    assert!(h.val);
    assert_eq!(words(&mut ring.slave, l.s_mdt_data + 8, 8), mdt);
    assert_eq!(words(&mut ring.slave, l.s_mdt_data, 8), vec![0; 8]);
    ring.run_to(us(160));
    // The second MDT went to buffer 0 and VAL toggled back.
    let h = RxHeader::decode(Variant::Sercon816, &words(&mut ring.slave, l.s_mdt_hdr, 5)).unwrap();
    assert!(!h.val);
    assert_eq!(words(&mut ring.slave, l.s_mdt_data, 8), mdt);
}

#[test]
fn phase4_dma_through_the_fifos() {
    // 410B §2 DMAREQT/DMAREQR, §4.1 27H RFIFO/TFIFO: DMA containers have no data words;
    // the slave's AT data come from TFIFO, the master's received AT data go to RFIFO.
    let (mut ring, _) = phase4(Variant::Sercon816, Buf::Dma);
    let at: Vec<u16> = (0..8).map(|i| 0x4400 + i).collect();
    let mut got = Vec::new();
    let mut t = 0;
    while t < 260 {
        t += 1;
        ring.run_to(us(t));
        // 410B §2 DMAREQT: the slave asks for its AT data; a DMA controller writes them.
        // The master's MDT data come from its TFIFO too.
        while ring.master.read(Register::Ctrl3) & (1 << 12) != 0 {
            ring.master.write(Register::Fifo, 0x7700);
        }
        if ring.slave.pin_level(Pin::DmaReqT) {
            assert!(ring.slave.read(Register::Ctrl3) & (1 << 12) != 0);
            for w in &at {
                ring.slave.dma_write_transmit(*w);
            }
            assert!(!ring.slave.pin_level(Pin::DmaReqT));
        }
        // The slave's MDT data arrive in its RFIFO: read them through 27H.
        while ring.slave.read(Register::Ctrl3) & (1 << 13) != 0 {
            ring.slave.read(Register::Fifo);
        }
        // 410B §2 DMAREQR: the master's received AT data wait in RFIFO.
        while ring.master.pin_level(Pin::DmaReqR) {
            got.push(ring.master.dma_read_receive());
        }
    }
    assert!(got.len() >= 16, "{got:?}");
    assert_eq!(&got[..8], &at[..]);
    assert_eq!(ring.master.read(Register::ProgerrFl), 0);
    assert_eq!(ring.slave.read(Register::ProgerrFl), 0);
}

#[test]
fn corrupted_mdt_sets_rerr_counts_nerr_and_keeps_data() {
    // 410B §4.2.1 RERR "errored", NERR "Error counter"; 4H.15 INT_RERR.
    let (mut ring, l) = phase4(Variant::Sercon816, Buf::Single);
    let mdt = fill(&mut ring.master, l.m_mdt_data, 0x5500);
    // Master telegrams: 0 MST, 1 MDT, 2 MST, 3 MDT: corrupt the second MDT.
    ring.corrupt_master = vec![3];
    ring.run_to(us(150));
    assert_eq!(words(&mut ring.slave, l.s_mdt_data, 8), mdt);
    // Change the data: the corrupted MDT carries it, but it must not be stored.
    fill(&mut ring.master, l.m_mdt_data, 0x6600);
    ring.run_to(us(195));
    let h = RxHeader::decode(Variant::Sercon816, &words(&mut ring.slave, l.s_mdt_hdr, 5)).unwrap();
    assert!(h.rerr);
    assert_eq!(h.nerr, 1);
    assert_eq!(words(&mut ring.slave, l.s_mdt_data, 8), mdt);
    assert!(ring.slave.read(Register::IntFlagsLo) & (1 << 15) != 0);
    // The next good MDT clears RERR and stores the new data; NERR keeps its count.
    ring.run_to(us(300));
    let h = RxHeader::decode(Variant::Sercon816, &words(&mut ring.slave, l.s_mdt_hdr, 5)).unwrap();
    assert!(!h.rerr && h.nerr == 1);
    assert_eq!(words(&mut ring.slave, l.s_mdt_data, 8)[0], 0x6600);
}

#[test]
fn phase4_exchange_on_the_410b_at_4_mbit_single_double_and_dma() {
    // 410B §4.2.1/§4.2.2 on the 410B at 4 Mbit/s (SCLK/16, 410B §2 SBAUD): an 8-word MDT
    // lasts about 45 µs, so the AT goes at TRT 60 in a 150 µs cycle. Single and double
    // buffer store by POS/LEN and set VAL; DMA goes through the FIFOs (§2 DMAREQT/DMAREQR).
    for b in [Buf::Single, Buf::Double, Buf::Dma] {
        let (mut ring, l) = phase4_timed(Variant::Sercon410b, b, 60, 150);
        let at: Vec<u16> = (0..8).map(|i| 0x2200 + i).collect();
        let mdt: Vec<u16> = (0..8).map(|i| 0x1100 + i).collect();
        if b != Buf::Dma {
            ring.master.write_ram_words(l.m_mdt_data, &mdt);
            ring.slave.write_ram_words(l.s_at_data, &at);
        }
        let mut got_at = Vec::new();
        let mut got_mdt = Vec::new();
        for t in 1..=600u64 {
            ring.run_to(us(t));
            if b == Buf::Dma {
                // 410B §2 DMAREQT: a DMA controller writes the transmit data on request.
                if ring.master.pin_level(Pin::DmaReqT) {
                    mdt.iter().for_each(|w| ring.master.dma_write_transmit(*w));
                }
                if ring.slave.pin_level(Pin::DmaReqT) {
                    at.iter().for_each(|w| ring.slave.dma_write_transmit(*w));
                }
                while ring.master.pin_level(Pin::DmaReqR) {
                    got_at.push(ring.master.dma_read_receive());
                }
                while ring.slave.pin_level(Pin::DmaReqR) {
                    got_mdt.push(ring.slave.dma_read_receive());
                }
            }
        }
        if b == Buf::Dma {
            assert!(
                got_at.len() >= 16 && got_mdt.len() >= 16,
                "{got_at:?} {got_mdt:?}"
            );
            assert_eq!(&got_at[..8], &at[..]);
            assert_eq!(&got_mdt[..8], &mdt[..]);
        } else {
            // Double buffer: the 4 cycles received alternate buffers; VAL names the last.
            let h = RxHeader::decode(Variant::Sercon410b, &words(&mut ring.slave, l.s_mdt_hdr, 5))
                .unwrap();
            let off = if b == Buf::Double && h.val { 8 } else { 0 };
            assert_eq!(words(&mut ring.slave, l.s_mdt_data + off, 8), mdt, "{b:?}");
            let h2 = RxHeader::decode(Variant::Sercon410b, &words(&mut ring.master, l.m_at_hdr, 5))
                .unwrap();
            let off = if b == Buf::Double && h2.val { 8 } else { 0 };
            assert_eq!(words(&mut ring.master, l.m_at_data + off, 8), at, "{b:?}");
            assert!(
                !h.rerr && h.nerr == 0 && !h2.rerr && h2.nerr == 0,
                "{h:?} {h2:?}"
            );
            if b == Buf::Single {
                assert!(h.val && h2.val);
            }
        }
        assert_eq!(ring.master.read(Register::ProgerrFl), 0, "{b:?}");
        assert_eq!(ring.slave.read(Register::ProgerrFl), 0, "{b:?}");
    }
}

#[test]
fn corrupted_mdt_on_the_410b_sets_rerr_and_int_rerr() {
    // 410B §4.2.1 RERR, NERR; §4.1 4H.15 INT_RERR: the corrupted bits reach the 410B's
    // decoder (no hint), which reports an FCS error; the data stay unchanged.
    let (mut ring, l) = phase4_timed(Variant::Sercon410b, Buf::Single, 60, 150);
    let mdt = fill(&mut ring.master, l.m_mdt_data, 0x5500);
    ring.corrupt_master = vec![3];
    ring.run_to(us(200));
    assert_eq!(words(&mut ring.slave, l.s_mdt_data, 8), mdt);
    fill(&mut ring.master, l.m_mdt_data, 0x6600);
    ring.run_to(us(290));
    let h = RxHeader::decode(Variant::Sercon410b, &words(&mut ring.slave, l.s_mdt_hdr, 5)).unwrap();
    assert!(h.rerr && h.nerr == 1, "{h:?}");
    assert_eq!(words(&mut ring.slave, l.s_mdt_data, 8), mdt);
    assert_ne!(ring.slave.read(Register::IntFlagsLo) & (1 << 15), 0);
    assert!(
        ring.received[1].iter().any(|f| !f.fcs_ok),
        "the slave saw an errored frame"
    );
}

#[test]
fn pulsed_dma_requests_one_pulse_per_word() {
    // 410B §4.1 1H.14 DMAMODE = 1: "DMAREQR/DMAREQT are pulses" (spec-notes "Pulsed DMA
    // requests": one MCLK period per word the DMA controller may move; 3H.12/13 stay static).
    for variant in Variant::ALL {
        let (mut ring, _) = phase4_timed(variant, Buf::Dma, 60, 150);
        let c1 = ring.slave.read(Register::Ctrl1);
        ring.slave.write(Register::Ctrl1, c1 | (1 << 14));
        let step = sercos_wire::time::Duration::from_nanos(10);
        // Find the slave's first DMAREQT pulse (its AT header becomes current).
        let mut t = us(1);
        while !ring.slave.pin_level(Pin::DmaReqT) && t < us(400) {
            t += step;
            ring.run_to(t);
        }
        assert!(ring.slave.pin_level(Pin::DmaReqT), "{variant:?}: a pulse");
        // One MCLK period later the pin is low again although the FIFO still wants words;
        // the status bit 3H.12 stays active.
        let period = sercos_wire::time::Duration::from_picos(
            1_000_000_000_000 / ring.slave.config().mclk_hz,
        );
        ring.run_to(t + period);
        assert!(
            !ring.slave.pin_level(Pin::DmaReqT),
            "{variant:?}: the pulse ended"
        );
        assert_ne!(ring.slave.read(Register::Ctrl3) & (1 << 12), 0);
        // Each word written brings the next pulse on the following MCLK edge, the last none.
        let mut pulses = 1;
        for w in 0..8u16 {
            ring.slave.dma_write_transmit(0x4400 + w);
            let now = ring.now() + period;
            ring.run_to(now);
            if ring.slave.pin_level(Pin::DmaReqT) {
                pulses += 1;
                ring.run_to(now + period);
                assert!(!ring.slave.pin_level(Pin::DmaReqT));
            }
        }
        assert_eq!(pulses, 8, "{variant:?}: one pulse per word");
        assert_eq!(ring.slave.read(Register::Ctrl3) & (1 << 12), 0);
    }
}

#[test]
fn dma_request_pins_are_traced_in_both_modes() {
    // 410B §2 pins 38/39 DMAREQR/DMAREQT as timed events (issue "controller part 1": every
    // output pin as a level-change stream); 1H.14 DMAMODE: static level or one pulse per word.
    for variant in Variant::ALL {
        for pulsed in [false, true] {
            let (mut ring, _) = phase4_timed(variant, Buf::Dma, 60, 150);
            ring.slave
                .set_traced_pins(PinSet::of(&[Pin::DmaReqT, Pin::DmaReqR]));
            let c1 = ring.slave.read(Register::Ctrl1);
            let mode = if pulsed { 1 << 14 } else { 0 };
            ring.slave.write(Register::Ctrl1, (c1 & !(1 << 14)) | mode);
            let step = sercos_wire::time::Duration::from_nanos(10);
            let mut t = us(1);
            while !ring.slave.pin_level(Pin::DmaReqT) && t < us(400) {
                t += step;
                ring.run_to(t);
            }
            let period = sercos_wire::time::Duration::from_picos(
                1_000_000_000_000 / ring.slave.config().mclk_hz,
            );
            for w in 0..8u16 {
                ring.slave.dma_write_transmit(0x4400 + w);
                let now = ring.now() + period + period;
                ring.run_to(now);
            }
            let mut ev = Vec::new();
            ring.slave.drain_pin_events(&mut ev);
            let t_edges: Vec<_> = ev.iter().filter(|e| e.pin == Pin::DmaReqT).collect();
            assert!(ev.windows(2).all(|w| w[0].at <= w[1].at), "time order");
            let rises = t_edges.iter().filter(|e| e.level).count();
            let falls = t_edges.iter().filter(|e| !e.level).count();
            if pulsed {
                // One pulse (rise, then fall one MCLK period later) per word the FIFO wants.
                assert_eq!((rises, falls), (8, 8), "{variant:?} pulsed: {t_edges:?}");
                for p in t_edges.chunks(2) {
                    assert!(p[0].level && !p[1].level);
                    assert_eq!(p[1].at - p[0].at, period);
                }
            } else {
                // Static: high while the FIFO wants words, low once the 8 words are in.
                assert_eq!((rises, falls), (1, 1), "{variant:?} static: {t_edges:?}");
                assert!(t_edges[0].level && !t_edges[1].level);
            }
        }
    }
}
