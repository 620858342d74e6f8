//! `Chip::next_line_send_at` (the send horizon) as the lookahead of a conservative event loop:
//! rings run with it give the same telegrams, received frames, RAM and registers as rings run
//! in steps of half the fibre delay (410B §4.2.1 TRT: a telegram starts at its time after the
//! MST, so the events between telegrams need no round of the loop).

mod harness;

use harness::*;
use proptest::prelude::*;
use sercon_model::Chip;
use sercon_regs::ram::header::TxEnable;
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};
use sercos_wire::time::Duration;

/// What a ring run can be told apart by.
#[derive(Debug, PartialEq, Eq)]
struct Outcome {
    log: Vec<(bool, Sent)>,
    received: Vec<Vec<sercon_model::serial_port::RxFrame>>,
    ram: Vec<Vec<u16>>,
    registers: Vec<Vec<u16>>,
}

/// Everything observable of `ring` after its run.
fn outcome(mut ring: Ring) -> Outcome {
    let mut chips: Vec<Chip> = vec![ring.master.clone(), ring.slave.clone()];
    if let Some(s2) = ring.slave2.clone() {
        chips.push(s2);
    }
    let words = |c: &mut Chip| -> Vec<u16> {
        let n = c.config().variant.ram_words();
        (0..n).map(|a| c.read_ram(a)).collect()
    };
    // 410B §4.1: registers 0H..=27H (read in the same order in both runs; reads may clear
    // flags, so both runs are treated alike).
    let regs = |c: &mut Chip| -> Vec<u16> { (0u8..0x28).map(|a| c.read_register(a)).collect() };
    Outcome {
        log: std::mem::take(&mut ring.log),
        received: ring.received.to_vec(),
        ram: chips.iter_mut().map(words).collect(),
        registers: chips.iter_mut().map(regs).collect(),
    }
}

/// Parameters of one ring.
#[derive(Debug, Clone)]
struct Setup {
    variant: Variant,
    three: bool,
    mdt_trt: u16,
    at_trt: u16,
    tscyc: u16,
    delay_ns: u64,
    corrupt: Vec<usize>,
    drop: Vec<usize>,
}

/// A slave: receives the broadcast MDT at `mdt_trt`, sends its AT (address `adr`) at `at_trt`.
fn slave(s: &Setup, adr: u8) -> Chip {
    let mut c = chip(s.variant);
    c.write(Register::Tscyc0, s.tscyc);
    c.write_ram(0, 16);
    rx_header(&mut c, 16, rx(255, true, s.mdt_trt, 8, 31));
    c.write_ram_words(21, &[control(8, true), 0]);
    tx_header(&mut c, 31, tx(adr, TxEnable::Continuous, s.at_trt, 8, 44));
    c.write_ram(35, control(8, true));
    c.write_ram_words(36, &[0x1000 * u16::from(adr); 8]);
    end_marker(&mut c, 44);
    c.write(Register::Phas, 0xFF04);
    c.write(Register::Ctrl3, ENTMT);
    c.write(Register::Ctrl0C, MSTEN);
    c
}

/// The master: MDT at `mdt_trt`, the slaves' ATs at `at_trt` (+ 20 for slave 2), phase 4.
fn ring(s: &Setup) -> Ring {
    let mut m = chip(s.variant);
    m.write(Register::Tscyc0, s.tscyc);
    m.write_ram(0, 16);
    tx_header(&mut m, 16, tx(255, TxEnable::Continuous, s.mdt_trt, 8, 29));
    m.write_ram(20, control(8, true));
    m.write_ram_words(21, &[0x0A0A; 8]);
    rx_header(&mut m, 29, rx(1, true, s.at_trt, 8, 44));
    m.write_ram_words(34, &[control(8, true), 0]);
    rx_header(&mut m, 44, rx(2, true, s.at_trt.saturating_add(20), 8, 59));
    m.write_ram_words(49, &[control(8, true), 0]);
    end_marker(&mut m, 59);
    m.write(Register::Phas, 0x0404);
    m.write(Register::Ctrl3, ENTMT);
    m.write(Register::Ctrl0C, MSTEN | MSTMASTER | CYCSTART);
    let mut r = if s.three {
        let mut s2 = slave(s, 2);
        // Slave 2 sends later than slave 1.
        tx_header(
            &mut s2,
            31,
            tx(2, TxEnable::Continuous, s.at_trt.saturating_add(20), 8, 44),
        );
        Ring::three(m, slave(s, 1), s2)
    } else {
        Ring::new(m, slave(s, 1))
    };
    r.delay = Duration::from_nanos(s.delay_ns);
    r.corrupt_master = s.corrupt.clone();
    r.drop_master = s.drop.clone();
    r
}

/// Runs the ring of `s` both ways for `us` µs and compares.
fn check(s: &Setup, us: u64) {
    let mut stepped = ring(s);
    stepped.run_to(harness::us(us));
    let mut horizon = ring(s);
    horizon.run_to_by_send_horizon(harness::us(us));
    assert_eq!(horizon.now(), stepped.now());
    let a = outcome(stepped);
    let b = outcome(horizon);
    assert!(!a.log.is_empty(), "the ring sent telegrams");
    assert_eq!(a, b);
}

fn base(variant: Variant) -> Setup {
    Setup {
        variant,
        three: false,
        mdt_trt: 5,
        at_trt: 40,
        tscyc: 100,
        delay_ns: 1000,
        corrupt: Vec::new(),
        drop: Vec::new(),
    }
}

#[test]
fn pair_in_phase4_runs_alike_with_the_send_horizon() {
    // 410B §4.2.1–§4.2.3: MDT and AT each cycle.
    check(&base(Variant::Sercon816), 1000);
    check(&base(Variant::Sercon410b), 1000);
}

#[test]
fn three_chips_with_faults_run_alike_with_the_send_horizon() {
    // 410B §4.1 4H INT_RERR / RDIST: a corrupted MDT and a dropped MST change what follows.
    let mut s = base(Variant::Sercon816);
    s.three = true;
    s.tscyc = 200;
    s.corrupt = vec![1, 4];
    s.drop = vec![6, 7];
    check(&s, 2000);
}

#[test]
fn overlapping_telegrams_run_alike_with_the_send_horizon() {
    // 410B §4.2.1 TRT: an AT due before the MDT has ended overlaps (a programming error).
    let mut s = base(Variant::Sercon816);
    s.at_trt = 6;
    check(&s, 800);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn rings_run_alike_with_the_send_horizon(
        v410 in any::<bool>(),
        three in any::<bool>(),
        mdt_trt in 0u16..30,
        at_trt in 0u16..80,
        tscyc in 60u16..250,
        delay_ns in 1u64..3000,
        corrupt in proptest::collection::vec(0usize..20, 0..3),
        drop in proptest::collection::vec(0usize..20, 0..3),
    ) {
        let s = Setup {
            variant: if v410 { Variant::Sercon410b } else { Variant::Sercon816 },
            three,
            mdt_trt,
            at_trt,
            tscyc,
            delay_ns,
            corrupt,
            drop,
        };
        check(&s, 800);
    }
}
