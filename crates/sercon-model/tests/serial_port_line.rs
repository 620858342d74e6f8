//! The serial port through the public line interface: transmitter timing, back-to-back chips,
//! repeater, FIBBR/RDIST, pins, test modes, polarity and NRZ (410B §1, §2, §4.1 1H–4H;
//! 816 §2.3; spec-notes "Serial port").

use sercon_model::config::Straps;
use sercon_model::pins::{Pin, PinEvent, PinSet};
use sercon_model::serial_port::{
    FIBBR_BIT_TIMES, LineSegment, LineSignal, PRESYNC_BITS, REPEATER_LATENCY_BITS, RxFrame,
};
use sercon_model::{Chip, ChipConfig};
use sercon_regs::SerconBus;
use sercos_wire::line::{BitVec, Coding, Encoder, LineConfig, Polarity, frame_bit_len};
use sercos_wire::time::{BitRate, Duration, Instant};

/// 410B §4.1 1H bits.
const SWBAUD: u16 = 1 << 6;
const POLTXD: u16 = 1 << 9;
const PRESYNC: u16 = 1 << 8;
const ENTSBAUD: u16 = 1 << 10;
const RXDNRZ: u16 = 1 << 12;
const SWBAUD16: u16 = 1 << 15;
/// 410B §4.1 2H: ENTXD1–6 all on.
const ENTXD_ALL: u16 = 0x3F;

fn us(n: u64) -> Instant {
    Instant::ZERO + Duration::from_micros(n)
}

/// A SERCON816, SBAUD16 = 0 (816 rates), TM0 = TM1 = 1 (no test mode, REPON = 1 after reset).
fn chip816(repon: bool) -> Chip {
    let mut cfg = ChipConfig::sercon816();
    cfg.straps = Straps::NORMAL;
    let mut chip = Chip::new(cfg);
    if !repon {
        chip.write_register(1, 0);
    }
    chip
}

/// 1H value selecting `rate` by software on the 816 (816 §2.3.1 table, ENTSBAUD = 1).
fn reg1_for(rate: BitRate) -> u16 {
    ENTSBAUD
        | match rate {
            BitRate::Mbit2 => SWBAUD16 | SWBAUD,
            BitRate::Mbit4 => SWBAUD16,
            BitRate::Mbit8 => SWBAUD,
            BitRate::Mbit16 => 0,
        }
}

fn output_until(chip: &mut Chip, t: Instant) -> Vec<LineSegment> {
    chip.advance_to(t);
    let mut out = Vec::new();
    chip.take_line_output(&mut out);
    out
}

fn frames(chip: &mut Chip) -> Vec<RxFrame> {
    let mut v = Vec::new();
    chip.take_rx_frames(&mut v);
    v
}

const MST: [u8; 2] = [0xFF, 0x02];
const MDT: [u8; 9] = [0x01, 0x3F, 0x00, 0xFF, 0xFF, 0x7E, 0x7E, 0x00, 0x00];

#[test]
fn telegram_durations_are_exact_at_every_rate() {
    // 816 §2.3.1: 2, 4, 8, 16 Mbit/s; the end is exact from the frame's bit length.
    for rate in BitRate::ALL {
        let mut chip = chip816(false);
        chip.write_register(1, reg1_for(rate));
        let at = us(3);
        let end = chip.transmit_telegram(at, &MDT).expect("transmitter on");
        assert_eq!(
            end,
            at + rate.duration_of_bits(frame_bit_len(&MDT)),
            "{rate}"
        );
        // With PRESYNC (1H.8) the 16-bit sync word comes first.
        let mut chip = chip816(false);
        chip.write_register(1, reg1_for(rate) | PRESYNC);
        let end = chip.transmit_telegram(at, &MDT).expect("transmitter on");
        assert_eq!(
            end,
            at + rate.duration_of_bits(PRESYNC_BITS + frame_bit_len(&MDT)),
            "{rate} presync"
        );
    }
}

#[test]
fn master_to_slave_back_to_back_with_delay() {
    // 410B §1: the telegrams sent by the master are received by the slaves.
    let delay = Duration::from_nanos(1_230);
    for presync in [false, true] {
        let mut master = chip816(false);
        let mut slave = chip816(false);
        if presync {
            master.write_register(1, PRESYNC);
        }
        let t0 = us(5);
        let end0 = master.transmit_telegram(t0, &MST).expect("sent");
        let t1 = end0 + Duration::from_micros(2);
        let end1 = master.transmit_telegram(t1, &MDT).expect("sent");
        let segs = output_until(&mut master, end1 + Duration::from_micros(1));
        // Filler, MST, filler, MDT, filler.
        let kinds: Vec<_> = segs
            .iter()
            .map(|s| matches!(s.signal, LineSignal::Bits(_)))
            .collect();
        assert_eq!(kinds, [false, true, false, true, false]);
        for s in &segs {
            slave.line_input(s.clone().delayed(delay));
        }
        let got = frames(&mut slave);
        let lead = if presync {
            BitRate::Mbit16.duration_of_bits(PRESYNC_BITS)
        } else {
            Duration::ZERO
        };
        assert_eq!(
            got,
            vec![
                RxFrame {
                    start: t0 + lead + delay,
                    end: end0 + delay,
                    bytes: MST.to_vec(),
                    fcs_ok: true
                },
                RxFrame {
                    start: t1 + lead + delay,
                    end: end1 + delay,
                    bytes: MDT.to_vec(),
                    fcs_ok: true
                },
            ]
        );
        // Without the hints the receiver decodes the bits to the same frames.
        let mut slave2 = chip816(false);
        for s in &segs {
            let mut s = s.clone().delayed(delay);
            s.hint = None;
            slave2.line_input(s);
        }
        assert_eq!(frames(&mut slave2), got);
    }
}

#[test]
fn damaged_bits_give_an_fcs_error_frame() {
    let mut master = chip816(false);
    let mut slave = chip816(false);
    let end = master.transmit_telegram(us(2), &MDT).expect("sent");
    for mut s in output_until(&mut master, end) {
        if let LineSignal::Bits(b) = &s.signal {
            // Flip the level of two bit times inside the data (a fault injector).
            let mut bits = BitVec::new();
            for (i, v) in b.bits().iter().enumerate() {
                bits.push(if i == 40 || i == 41 { !v } else { v });
            }
            s.signal = LineSignal::Bits(bits.into());
            s.hint = None;
        }
        slave.line_input(s);
    }
    let got = frames(&mut slave);
    assert_eq!(got.len(), 1);
    assert!(!got[0].fcs_ok);
}

#[test]
fn idle_and_reactn_pin_events() {
    let mut master = chip816(false);
    let mut slave = chip816(false);
    master.set_traced_pins(PinSet::of(&[Pin::Idle]));
    slave.set_traced_pins(PinSet::of(&[Pin::Reactn]));
    let at = us(4);
    let end = master.transmit_telegram(at, &MDT).expect("sent");
    let segs = output_until(&mut master, end + Duration::from_micros(1));
    let mut ev = Vec::new();
    master.drain_pin_events(&mut ev);
    // 410B §2 IDLE: 0 while the node transmits its own data.
    assert_eq!(
        ev,
        vec![
            PinEvent {
                at,
                pin: Pin::Idle,
                level: false
            },
            PinEvent {
                at: end,
                pin: Pin::Idle,
                level: true
            },
        ]
    );
    // 3H.14 reads the IDLE level.
    assert_eq!(master.read_register(3) & (1 << 14), 1 << 14);
    for s in segs {
        slave.line_input(s);
    }
    slave.advance_to(at + Duration::from_nanos(1_000));
    // 3H.15 REACTN low while the telegram is being received.
    assert_eq!(slave.read_register(3) & (1 << 15), 0);
    assert!(!slave.pin_level(Pin::Reactn));
    slave.advance_to(end + Duration::from_micros(1));
    let mut ev = Vec::new();
    slave.drain_pin_events(&mut ev);
    let flag = BitRate::Mbit16.duration_of_bits(8);
    // REACTN low once the opening flag is recognised, high at the end of the closing flag.
    assert_eq!(
        ev,
        vec![
            PinEvent {
                at: at + flag,
                pin: Pin::Reactn,
                level: false
            },
            PinEvent {
                at: end,
                pin: Pin::Reactn,
                level: true
            },
        ]
    );
}

// 410B §2 IDLE / REACTN and §4.1 3H.14–15: with the pins untraced their changes are kept
// as scheduled and read when asked for (spec-notes "Quiet pins"); what a read sees is the
// same as with the pins traced, also across a trace switched on and off mid-run, with
// telegrams received ahead of the chip's time and the slave sending its own; and with the
// sender's filler implied (one segment per telegram, the receivers' filler-to-filler path,
// which keeps the serial port's loud bound when the pins are quiet only).
#[test]
fn idle_and_reactn_levels_are_the_same_traced_or_not() {
    for implied in [false, true] {
        idle_and_reactn_levels_traced_or_not(implied);
    }
}

fn idle_and_reactn_levels_traced_or_not(implied: bool) {
    let mut master = chip816(false);
    master.set_implied_filler(implied);
    let mut segs = Vec::new();
    let mut ends = Vec::new();
    for k in 0..12u64 {
        let at = us(4 + 12 * k);
        let bytes: &[u8] = if k % 3 == 0 { &MST } else { &MDT };
        let end = master.transmit_telegram(at, bytes).expect("sent");
        ends.push(end);
        segs.extend(output_until(&mut master, end + Duration::from_nanos(300)));
    }
    let traced = PinSet::of(&[Pin::Idle, Pin::Reactn]);
    // a: traced throughout; b: never; c: switched on and off along the way.
    let mut a = chip816(false);
    a.set_traced_pins(traced);
    let mut b = chip816(false);
    let mut c = chip816(false);
    for chip in [&mut a, &mut b, &mut c] {
        for s in &segs {
            chip.line_input(s.clone());
        }
    }
    // Own telegrams too (IDLE), queued ahead of the chips' time.
    for chip in [&mut a, &mut b, &mut c] {
        for k in 0..4u64 {
            chip.transmit_telegram(us(10 + 30 * k), &MST).expect("sent");
        }
    }
    let mut t = us(1);
    let mut step = 0u32;
    let mut lows = (0u32, 0u32);
    while t < us(160) {
        step += 1;
        if step % 40 == 0 {
            let on = c.traced_pins().is_empty();
            c.set_traced_pins(if on { traced } else { PinSet::EMPTY });
            // Read at once, before any advance: the levels stand across the switch.
            for pin in [Pin::Idle, Pin::Reactn] {
                assert_eq!(c.pin_level(pin), b.pin_level(pin), "{pin:?} switched");
            }
        }
        let read = |chip: &mut Chip| {
            chip.advance_to(t);
            let mut out = Vec::new();
            chip.take_line_output(&mut out);
            (
                chip.read_register(3) & (3 << 14),
                chip.pin_level(Pin::Idle),
                chip.pin_level(Pin::Reactn),
            )
        };
        let want = read(&mut a);
        assert_eq!(read(&mut b), want, "untraced at {t:?}");
        assert_eq!(read(&mut c), want, "switched at {t:?}");
        lows.0 += u32::from(!want.1);
        lows.1 += u32::from(!want.2);
        t += Duration::from_nanos(137);
    }
    // The walk saw both pins low and high.
    assert!(lows.0 > 10 && lows.1 > 100, "{lows:?}");
    assert!(step > 1000);
}

// 410B §2 REACTN: telegrams with their filler implied, each handed over after the chip ran
// past everything the one before scheduled (as a ring hands them over), take the receivers'
// filler-to-filler path; a traced REACTN's changes are then the port's next loud events,
// and the levels and flags read at every step are those of the untraced chip.
#[test]
fn implied_filler_telegrams_after_quiet_gaps_keep_reactn_traced_or_not() {
    let mut master = chip816(false);
    master.set_implied_filler(true);
    let traced = PinSet::of(&[Pin::Idle, Pin::Reactn]);
    let mut a = chip816(false);
    a.set_traced_pins(traced);
    let mut b = chip816(false);
    let mut t = us(1);
    let mut lows = 0u32;
    for k in 0..10u64 {
        let at = us(4 + 9 * k);
        let bytes: &[u8] = if k % 2 == 0 { &MST } else { &MDT };
        let end = master.transmit_telegram(at, bytes).expect("sent");
        let segs = output_until(&mut master, end + Duration::from_nanos(300));
        for s in segs {
            // Each chip has applied every change before the segment comes.
            for chip in [&mut a, &mut b] {
                chip.advance_to(s.start.max(t));
                chip.line_input(s.clone());
            }
        }
        while t < end + Duration::from_micros(4) {
            let read = |chip: &mut Chip| {
                chip.advance_to(t);
                (
                    chip.read_register(3) & (3 << 14),
                    chip.pin_level(Pin::Idle),
                    chip.pin_level(Pin::Reactn),
                )
            };
            let want = read(&mut a);
            assert_eq!(read(&mut b), want, "untraced at {t:?}");
            lows += u32::from(!want.2);
            t += Duration::from_nanos(97);
        }
    }
    // REACTN was seen low (a telegram being received).
    assert!(lows > 20, "{lows}");
}

#[test]
fn repeater_forwards_with_latency_and_substitutes_own_telegrams() {
    // 410B §1: slaves "regenerate and repeat their received data or send their own
    // telegrams"; 1H.3 REPON.
    let mut master = chip816(false);
    let mut slave = chip816(true);
    let end = master.transmit_telegram(us(2), &MST).expect("sent");
    let segs = output_until(&mut master, end);
    for s in &segs {
        slave.line_input(s.clone());
    }
    let latency = BitRate::Mbit16.duration_of_bits(REPEATER_LATENCY_BITS);
    let fwd = output_until(&mut slave, us(10));
    // Dark until the first forwarded segment (nothing received before).
    let mut expected = vec![LineSegment::steady(
        Instant::ZERO,
        BitRate::Mbit16.bit_time(),
        LineSignal::Dark,
        false,
    )];
    expected.extend(segs.iter().map(|s| s.clone().delayed(latency)));
    assert_eq!(fwd, expected);
    // Own telegram while filler is forwarded: it goes out instead, then the filler resumes.
    let own_at = us(12);
    let own_end = slave.transmit_telegram(own_at, &MDT).expect("sent");
    let out = output_until(&mut slave, own_end + Duration::from_micros(1));
    assert_eq!(out.len(), 2);
    assert_eq!(out[0].start, own_at);
    assert_eq!(out[0].end(), Some(own_end));
    assert!(out[0].hint.as_ref().is_some_and(|h| h.telegram[..] == MDT));
    assert_eq!(out[1].start, own_end);
    assert_eq!(out[1].signal, LineSignal::Filler);
    // A telegram forwarded during the own one is replaced; after it, the rest of the
    // forwarded telegram (if any) follows.
    let mut slave = chip816(true);
    let mut master = chip816(false);
    let m_end = master.transmit_telegram(us(20), &MDT).expect("sent");
    for s in output_until(&mut master, m_end) {
        slave.line_input(s);
    }
    let own_end = slave.transmit_telegram(us(19), &MST).expect("sent");
    let out = output_until(&mut slave, m_end + Duration::from_micros(2));
    let own: Vec<_> = out.iter().filter(|s| s.hint.is_some()).collect();
    assert_eq!(own.len(), 1, "only the own telegram keeps a hint: {out:?}");
    // The own MST (19 µs to 22.06 µs) overlaps the forwarded MDT (from 20 µs + latency):
    // after the MST only the rest of the MDT goes out, cut from its start.
    assert!(own_end > us(20) + latency);
    let rest = out
        .iter()
        .find(|s| s.start > own[0].start)
        .expect("the rest");
    assert_eq!(rest.start, own_end);
    assert!(matches!(rest.signal, LineSignal::Bits(_)));
    let mut receiver = chip816(false);
    for s in out {
        receiver.line_input(s);
    }
    let got = frames(&mut receiver);
    assert_eq!(got.first().map(|f| f.bytes.clone()), Some(MST.to_vec()));
    assert!(got.iter().all(|f| f.bytes != MDT), "the MDT was replaced");
}

#[test]
fn fibbr_after_the_light_stops() {
    // sercos-facts: the absence of the filler's edges is what the controller reports as
    // FIBBR (410B §4.1 2H.13), with INT_FIBBR (4H.1) and L_ERRN (LMODE = 0).
    let mut chip = chip816(false);
    let bt = BitRate::Mbit16.bit_time();
    chip.set_traced_pins(PinSet::of(&[Pin::LErrn]));
    // After reset the receive line is dark: FIBBR after the timeout.
    chip.advance_to(Instant::ZERO + bt.saturating_mul(FIBBR_BIT_TIMES) - Duration::from_picos(1));
    assert_eq!(chip.read_register(2) & (1 << 13), 0);
    chip.advance_to(Instant::ZERO + bt.saturating_mul(FIBBR_BIT_TIMES));
    assert_ne!(chip.read_register(2) & (1 << 13), 0);
    assert_ne!(chip.read_register(4) & 2, 0);
    chip.write_register(4, 2); // clear INT_FIBBR
    // Filler from 10 µs: FIBBR clears at its first edge.
    chip.line_input(LineSegment::steady(us(10), bt, LineSignal::Filler, false));
    chip.advance_to(us(10));
    assert_eq!(chip.read_register(2) & (1 << 13), 0);
    assert!(chip.pin_level(Pin::LErrn));
    // The light stops at 20 µs: the last edge is at the filler's last bit before 20 µs.
    chip.line_input(LineSegment::steady(us(20), bt, LineSignal::Dark, false));
    let last_edge = us(20) - bt;
    let fibbr_at = last_edge + bt.saturating_mul(FIBBR_BIT_TIMES);
    chip.advance_to(us(20));
    assert_eq!(chip.next_deadline(), Some(fibbr_at));
    chip.advance_to(fibbr_at - Duration::from_picos(1));
    assert_eq!(chip.read_register(4) & 2, 0);
    chip.advance_to(fibbr_at);
    assert_ne!(chip.read_register(2) & (1 << 13), 0);
    assert_ne!(chip.read_register(4) & 2, 0, "INT_FIBBR");
    assert!(!chip.pin_level(Pin::LErrn));
    let mut ev = Vec::new();
    chip.drain_pin_events(&mut ev);
    assert_eq!(
        ev.last(),
        Some(&PinEvent {
            at: fibbr_at,
            pin: Pin::LErrn,
            level: false
        })
    );
    // LMODE = 3 (2H.14–15): L_ERRN inactive.
    chip.write_register(2, ENTXD_ALL | 0xC000);
    assert!(chip.pin_level(Pin::LErrn));
}

#[test]
fn rdist_while_a_distorted_signal_lasts() {
    // 410B §4.1 2H.12 RDIST, 4H.0 INT_RDIST; LMODE = 1: L_ERRN by RDIST only.
    let mut chip = chip816(false);
    let bt = BitRate::Mbit16.bit_time();
    chip.write_register(2, ENTXD_ALL | 0x4000);
    chip.line_input(LineSegment::steady(us(1), bt, LineSignal::Filler, false));
    let mut bad = LineSegment::steady(us(5), bt, LineSignal::Filler, false);
    bad.distorted = true;
    chip.line_input(bad);
    chip.line_input(LineSegment::steady(us(9), bt, LineSignal::Filler, false));
    chip.advance_to(us(4));
    assert_eq!(chip.read_register(2) & (1 << 12), 0);
    assert!(chip.pin_level(Pin::LErrn));
    chip.advance_to(us(6));
    assert_ne!(chip.read_register(2) & (1 << 12), 0);
    assert_eq!(chip.read_register(4) & 1, 1);
    assert!(!chip.pin_level(Pin::LErrn));
    chip.advance_to(us(9));
    assert_eq!(chip.read_register(2) & (1 << 12), 0);
    assert_eq!(chip.read_register(4) & 1, 1, "the flag stays until cleared");
    // A signal at another bit rate is off the receiver's bit grid: RDIST, no frames.
    let mut chip = chip816(false);
    let mut enc = Encoder::new(LineConfig::new(Coding::Nrzi, Polarity::LightOnHigh));
    let mut bits = BitVec::new();
    enc.encode(&MDT, &mut bits).expect("encodes");
    chip.line_input(LineSegment::bits(
        us(1),
        BitRate::Mbit4.bit_time(),
        bits,
        false,
    ));
    chip.advance_to(us(2));
    assert_ne!(chip.read_register(2) & (1 << 12), 0);
    assert!(frames(&mut chip).is_empty());
}

#[test]
fn test_modes_and_transmitter_off() {
    // 410B §4.1 2H.7–9 TMODE: 4/6 continuous light, 5 zero bit stream; ENTXD1–6 = 0: off.
    for (reg2, want) in [
        (ENTXD_ALL | 4 << 7, LineSignal::Light),
        (ENTXD_ALL | 6 << 7, LineSignal::Light),
        (ENTXD_ALL | 5 << 7, LineSignal::Filler),
        (0, LineSignal::Dark),
    ] {
        let mut chip = chip816(false);
        chip.advance_to(us(1));
        chip.write_register(2, reg2);
        assert_eq!(chip.transmit_telegram(us(2), &MST), None, "nothing is sent");
        let out = output_until(&mut chip, us(3));
        let last = out.last().expect("a segment");
        assert_eq!(last.start, us(1));
        assert_eq!(last.signal, want);
    }
    // TM0 = 0 (816 §2.3.3, TM0/TM1 = 01): continuous light from reset.
    let mut cfg = ChipConfig::sercon816();
    cfg.straps.tm0 = false;
    cfg.straps.tm1 = true;
    let mut chip = Chip::new(cfg);
    let out = output_until(&mut chip, us(1));
    assert_eq!(
        out.last().map(|s| s.signal.clone()),
        Some(LineSignal::Light)
    );
}

#[test]
fn poltxd_inverts_the_light() {
    // 410B §4.1 1H.9 POLTXD = 1: "light on" when TxD = 1; the line interface's transceiver
    // lights the fibre for TxD = 0, so continuous light becomes a dark fibre.
    let mut chip = chip816(false);
    chip.write_register(1, POLTXD);
    chip.write_register(2, ENTXD_ALL | 4 << 7);
    let out = output_until(&mut chip, us(1));
    assert_eq!(out.last().map(|s| s.signal.clone()), Some(LineSignal::Dark));
    // NRZI telegrams decode the same either way.
    let mut master = chip816(false);
    master.write_register(1, POLTXD);
    let mut slave = chip816(false);
    let end = master.transmit_telegram(us(2), &MDT).expect("sent");
    for s in output_until(&mut master, end) {
        slave.line_input(s);
    }
    assert_eq!(frames(&mut slave).len(), 1);
}

#[test]
fn rxdnrz_selects_nrz_reception() {
    // ERRATA 1H.12 RXDNRZ: 1 = receive data NRZ-coded.
    let mut enc = Encoder::new(LineConfig::new(Coding::Nrz, Polarity::LightOnHigh));
    let mut bits = BitVec::new();
    enc.idle(8, &mut bits).expect("room");
    enc.encode(&MDT, &mut bits).expect("encodes");
    enc.idle(8, &mut bits).expect("room");
    let bt = BitRate::Mbit16.bit_time();
    let seg = LineSegment::bits(us(1), bt, bits, false);
    let mut nrz = chip816(false);
    nrz.write_register(1, RXDNRZ);
    nrz.line_input(seg.clone());
    let got = frames(&mut nrz);
    assert_eq!(got.len(), 1);
    assert_eq!(got[0].bytes, MDT);
    assert_eq!(got[0].start, us(1) + bt.saturating_mul(8));
    let mut nrzi = chip816(false);
    nrzi.line_input(seg);
    assert!(frames(&mut nrzi).iter().all(|f| f.bytes != MDT));
}

#[test]
fn txd_is_traced_as_the_envelope_of_own_telegrams() {
    // 410B §2 TxD1 carries the transmitted signal; traced edge by edge it would be one event
    // per bit, so TxD is traced as its activity (spec-notes "Serial port"): high from the
    // first bit of an own telegram to the end of its closing flag, the inverse of IDLE.
    let mut master = chip816(false);
    master.set_traced_pins(PinSet::of(&[Pin::TxD]));
    let at = us(4);
    let end = master.transmit_telegram(at, &MDT).expect("sent");
    master.advance_to(at + Duration::from_nanos(100));
    assert!(master.pin_level(Pin::TxD));
    assert_eq!(master.next_deadline(), Some(end));
    master.advance_to(end + Duration::from_micros(1));
    assert!(!master.pin_level(Pin::TxD));
    let mut ev = Vec::new();
    master.drain_pin_events(&mut ev);
    assert_eq!(
        ev,
        vec![
            PinEvent {
                at,
                pin: Pin::TxD,
                level: true
            },
            PinEvent {
                at: end,
                pin: Pin::TxD,
                level: false
            },
        ]
    );
}
