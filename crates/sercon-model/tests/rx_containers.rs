//! A receive telegram of several data containers: each container's words stored by its
//! POS and LEN (410B §4.2.2), the last one marked LASTDC.

mod harness;

use harness::*;
use sercon_regs::ram::header::{RxHeader, TxEnable};
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};

/// Phase 4, one slave (address 1): the master's broadcast MDT of 8 words at TRT 5, which
/// the slave receives in two containers (3 words at POS 0, 5 words at POS 3); the slave's
/// AT of 8 words at TRT 40; cycle 100 µs, single buffers. Returns the ring, the master's
/// MDT data address and the slave's two container data addresses.
fn two_container_mdt(variant: Variant) -> (Ring, u16, u16, u16) {
    let mut m = chip(variant);
    let mut s = chip(variant);
    m.write(Register::Tscyc0, 100);
    s.write(Register::Tscyc0, 100);
    // Master: COMPT0 → tx MDT (one container of 8) → rx AT → end marker.
    m.write_ram(0, 16);
    let p1 = 16 + 4 + 1 + 8;
    tx_header(&mut m, 16, tx(255, TxEnable::Continuous, 5, 8, p1));
    m.write_ram(20, control(8, true));
    let p2 = p1 + 5 + 2 + 8;
    rx_header(&mut m, p1, rx(1, true, 40, 8, p2));
    m.write_ram_words(p1 + 5, &[control(8, true), 0]);
    end_marker(&mut m, p2);
    // Slave: COMPT0 → rx MDT in two containers → tx AT → end marker.
    s.write_ram(0, 16);
    s.write_ram_words(21, &[control(3, false), 0]);
    s.write_ram_words(26, &[control(5, true), 3]);
    let q1 = 28 + 5;
    rx_header(&mut s, 16, rx(255, true, 5, 8, q1));
    let q2 = q1 + 4 + 1 + 8;
    tx_header(&mut s, q1, tx(1, TxEnable::Continuous, 40, 8, q2));
    s.write_ram(q1 + 4, control(8, true));
    end_marker(&mut s, q2);
    start_phase4(&mut m, &mut s);
    (Ring::new(m, s), 21, 23, 28)
}

#[test]
fn every_container_of_a_receive_telegram_is_stored() {
    // The 816 at its 16 Mbit/s (816 §2.3.1; the 410B's rates in tp_exchange.rs).
    let variant = Variant::Sercon816;
    let (mut ring, m_data, a, b) = two_container_mdt(variant);
    let mdt: Vec<u16> = (0..8).map(|i| 0x3300 + i).collect();
    ring.master.write_ram_words(m_data, &mdt);
    ring.run_to(us(340));
    assert_eq!(words(&mut ring.slave, a, 3), mdt[..3], "{variant:?}");
    assert_eq!(words(&mut ring.slave, b, 5), mdt[3..], "{variant:?}");
    let h = RxHeader::decode(variant, &words(&mut ring.slave, 16, 5)).unwrap();
    assert!(h.val && !h.rerr && h.nerr == 0, "{variant:?} {h:?}");
    assert_eq!(ring.slave.read(Register::ProgerrFl), 0, "{variant:?}");
}
