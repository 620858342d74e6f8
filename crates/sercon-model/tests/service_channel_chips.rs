//! Service-channel transfers through two chips on the line (410B §1 "executed
//! automatically", §4.2.2 SVFL/NSV/SCMASTER, §4.2.4 both container tables, §4.1 5H INT_SC_n,
//! 0DH): the telegram processors fill and take the service info of the MDT and the AT, and
//! the hosts react to INT_SC_n by reading and writing the container words over the bus, as a
//! driver would. Handshakes are counted per cycle from the telegrams on the line.

mod harness;

use harness::*;
use sercon_model::Chip;
use sercon_regs::ram::container::ContainerControl;
use sercon_regs::ram::header::TxEnable;
use sercon_regs::ram::service::{NInfo, ScMaster, ScSlave};
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};

/// NSV of the master's container (410B §4.2.2) and its start (SCPT2, RAM word 4).
const M_NSV: u8 = 2;
const M_SC: u16 = 0x100;
/// NSV of the slave's container and its start (SCPT5, RAM word 7).
const S_NSV: u8 = 5;
const S_SC: u16 = 0x300;
/// Buffer offset: the buffers follow the five control words (spec-notes "Service containers").
const BUF: u8 = 5;
const IDN_NAME: u16 = 0x8001;
const NAME: &[u8; 60] = b"Spindle drive 7, retrofit 2024, SERCON816 model, axis X-left";

/// Container control word 0 of a record of `len` words with SVFL = 1 (410B §4.2.2).
fn sc_control(len: u16, nsv: u8, scmaster: bool) -> u16 {
    ContainerControl::new(len, true, nsv, scmaster, true).map_or(0, |c| c.to_word())
}

/// A master and a slave in phase 4, each telegram one service-channel record (control or
/// status word and one info word): MDT at TRT 5, AT at TRT 40, cycle 100 µs.
fn sc_ring(variant: Variant) -> Ring {
    let mut m = chip(variant);
    let mut s = chip(variant);
    // Master: COMPT0 → tx MDT (16) → rx AT (23) → end marker (32).
    m.write_ram(0, 16);
    m.write_ram(2 + u16::from(M_NSV), M_SC);
    tx_header(&mut m, 16, tx(255, TxEnable::Continuous, 5, 2, 23));
    m.write_ram_words(20, &[sc_control(2, M_NSV, true), 0xE000, 0]);
    rx_header(&mut m, 23, rx(1, true, 40, 2, 32));
    m.write_ram_words(28, &[sc_control(2, M_NSV, true), 0]);
    end_marker(&mut m, 32);
    // Slave: COMPT0 → rx MDT (16) → tx AT (25) → end marker (32).
    s.write_ram(0, 16);
    s.write_ram(2 + u16::from(S_NSV), S_SC);
    rx_header(&mut s, 16, rx(255, true, 5, 2, 25));
    s.write_ram_words(21, &[sc_control(2, S_NSV, false), 0]);
    tx_header(&mut s, 25, tx(1, TxEnable::Continuous, 40, 2, 32));
    s.write_ram_words(29, &[sc_control(2, S_NSV, false), 0xC000, 0]);
    end_marker(&mut s, 32);
    // Idle master container: M_BUSY = 1 until the host sets up a transfer.
    let mut sc = ScMaster::from_words([0; 5]);
    sc.m_busy = true;
    m.write_ram_words(M_SC, &sc.to_words());
    start_phase4(&mut m, &mut s);
    Ring::new(m, s)
}

fn words5(c: &mut Chip, at: u16) -> [u16; 5] {
    let w = words(c, at, 5);
    [w[0], w[1], w[2], w[3], w[4]]
}

fn master_sc(r: &mut Ring) -> ScMaster {
    ScMaster::from_words(words5(&mut r.master, M_SC))
}

fn slave_sc(r: &mut Ring) -> ScSlave {
    ScSlave::from_words(words5(&mut r.slave, S_SC))
}

fn clear_master_ints(m: &mut ScMaster) {
    m.int_err = false;
    m.int_end_wrbuf = false;
    m.int_end_rdbuf = false;
    m.int_sc_err = false;
    m.int_hs_timeout = false;
    m.int_busy_timeout = false;
    m.int_cmd = false;
}

/// The master's host starts a write of `data` to `element` (410B §4.2.4 master table).
fn master_write(r: &mut Ring, element: u8, data: &[u16]) {
    r.master.write_ram_words(M_SC + u16::from(BUF), data);
    let mut m = master_sc(r);
    m.elem_mdt = element;
    m.ls_mdt = true;
    m.setend = true;
    m.ninfo_write = NInfo::from_count(1).expect("1-4");
    m.pointers.wrdatpt = BUF;
    m.pointers.wrdatlast = BUF + data.len() as u8 - 1;
    clear_master_ints(&mut m);
    m.m_busy = false;
    r.master.write_ram_words(M_SC, &m.to_words());
}

/// The master's host starts a read of `len` words of `element` into its read buffer.
fn master_read(r: &mut Ring, element: u8, len: u8, setend: bool) {
    let mut m = master_sc(r);
    m.elem_mdt = element;
    m.ls_mdt = false;
    m.setend = setend;
    m.ninfo_read = NInfo::from_count(1).expect("1-4");
    m.pointers.rddatpt = BUF;
    m.pointers.rddatlast = BUF + len - 1;
    clear_master_ints(&mut m);
    m.m_busy = false;
    r.master.write_ram_words(M_SC, &m.to_words());
}

/// The slave's microprocessor: holds elements, reacts to INT_SC_5 (410B §4.2.4 slave
/// table) by updating its container over the bus and clearing the flag (5H, write 1).
#[derive(Default)]
struct Drive {
    idn: u16,
    elements: [Vec<u16>; 8],
    /// INT_SC_5 seen (times the host was interrupted).
    interrupts: usize,
    asleep: bool,
}

impl Drive {
    fn react(&mut self, r: &mut Ring) {
        if r.slave.read(Register::IntFlagsHi) & (1 << S_NSV) == 0 || self.asleep {
            return;
        }
        self.interrupts += 1;
        r.slave.write(Register::IntFlagsHi, 1 << S_NSV);
        let mut s = slave_sc(r);
        if s.int_elem_change {
            s.int_elem_change = false;
            s.err_at = false;
            if s.ls {
                s.pointers.rddatpt = BUF;
                s.pointers.rddatlast = 255;
            } else {
                let data = self.elements[usize::from(s.elem & 7)].clone();
                r.slave.write_ram_words(S_SC + u16::from(BUF), &data);
                s.pointers.wrdatpt = BUF;
                s.pointers.wrdatlast = BUF + data.len() as u8 - 1;
            }
            s.busy_at = false;
        }
        if s.int_end_mdt {
            s.int_end_mdt = false;
            if s.ls {
                let len = u16::from(s.pointers.rddatpt.saturating_sub(BUF));
                let data = words(&mut r.slave, S_SC + u16::from(BUF), len);
                if s.elem == 1 {
                    self.idn = data.first().copied().unwrap_or(0);
                } else {
                    self.elements[usize::from(s.elem & 7)] = data;
                }
                s.pointers.rddatpt = BUF;
                s.busy_at = false;
            }
        }
        s.int_end_rdbuf = false;
        r.slave.write_ram_words(S_SC, &s.to_words());
    }
}

/// One cycle as seen on the line: the MDT's control and info word, the AT's status and
/// info word (`None` when no AT came).
#[derive(Debug, Clone, Copy)]
struct Cycle {
    mdt: [u16; 2],
    at: Option<[u16; 2]>,
}

fn word_at(b: &[u8], i: usize) -> u16 {
    u16::from_le_bytes([b[1 + 2 * i], b[2 + 2 * i]])
}

/// The cycles on the line so far (MDTs with the AT that followed each).
fn cycles(r: &Ring) -> Vec<Cycle> {
    let mdts: Vec<_> = r
        .log
        .iter()
        .filter(|(m, t)| *m && t.bytes[0] == 255 && t.bytes.len() == 5)
        .collect();
    let ats: Vec<_> = r
        .log
        .iter()
        .filter(|(m, t)| !*m && t.bytes[0] == 1)
        .collect();
    mdts.iter()
        .map(|(_, mdt)| {
            // The AT of this cycle starts within 100 µs after the MDT.
            let at = ats.iter().find(|(_, a)| {
                a.start > mdt.start
                    && a.start < mdt.start + sercos_wire::time::Duration::from_micros(100)
            });
            Cycle {
                mdt: [word_at(&mdt.bytes, 0), word_at(&mdt.bytes, 1)],
                at: at.map(|(_, a)| [word_at(&a.bytes, 0), word_at(&a.bytes, 1)]),
            }
        })
        .collect()
}

/// Whether the cycle's AT acknowledges its MDT's step: AHS = MHS and BUSY = 0
/// (410B §4.2.4; sercos-telegrams MDT/AT service bits 0 and 1).
fn acknowledged(c: &Cycle) -> bool {
    c.at.is_some_and(|a| a[0] & 1 == c.mdt[0] & 1 && a[0] & 2 == 0)
}

/// Runs the ring in 5 µs steps, the hosts reacting after each, until the master's
/// container raises `until` (seen at INT_SC_2) or `limit` cycles pass. Returns the cycles
/// on the line during the run.
fn run(r: &mut Ring, drive: &mut Drive, until: fn(&ScMaster) -> bool, limit: u64) -> Vec<Cycle> {
    let first = cycles(r).len();
    let end = r.now() + sercos_wire::time::Duration::from_micros(100 * limit);
    while r.now() < end {
        let t = r.now() + sercos_wire::time::Duration::from_micros(5);
        r.run_to(t);
        drive.react(r);
        if r.master.read(Register::IntFlagsHi) & (1 << M_NSV) != 0 {
            r.master.write(Register::IntFlagsHi, 1 << M_NSV);
            if until(&master_sc(r)) {
                return cycles(r).split_off(first);
            }
        }
    }
    panic!("no end after {limit} cycles: {:?}", master_sc(r));
}

fn open_idn(r: &mut Ring, drive: &mut Drive, idn: u16) {
    master_write(r, 1, &[idn]);
    run(r, drive, |m| m.int_end_wrbuf, 10);
    assert_eq!(drive.idn, idn);
}

fn bytes_to_words(bytes: &[u8]) -> Vec<u16> {
    bytes
        .chunks(2)
        .map(|c| u16::from(c[0]) | u16::from(*c.get(1).unwrap_or(&0)) << 8)
        .collect()
}

/// sercos-facts: variable-length data = current length, maximum length, then the bytes.
fn name_words() -> Vec<u16> {
    let mut w = vec![60, 60];
    w.extend(bytes_to_words(NAME));
    w
}

// 410B §4.2.4 master table (HS_MDT, L/S_MDT, SETEND → END_MDT, NINFO_WRITE, WRDATPT →
// WRDATLAST, INT_END_WRBUF), slave table (HS_AT, INT_ELEM_CHANGE, INT_END_MDT, read
// buffer), through both telegram processors and the line, on both variants.
#[test]
fn sixty_byte_name_master_to_slave_one_handshake_per_cycle() {
    for variant in Variant::ALL {
        let mut r = sc_ring(variant);
        let mut drive = Drive::default();
        open_idn(&mut r, &mut drive, IDN_NAME);
        let name = name_words();
        assert_eq!(name.len(), 32);
        master_write(&mut r, 2, &name);
        let cycles = run(&mut r, &mut drive, |m| m.int_end_wrbuf, 60);
        assert_eq!(drive.elements[2], name, "{variant:?}");
        // One new step per acknowledged cycle, never two in a cycle: 32 handshakes.
        let acks: Vec<&Cycle> = cycles.iter().filter(|c| acknowledged(c)).collect();
        assert_eq!(acks.len(), 32, "{variant:?} {cycles:x?}");
        let sent: Vec<u16> = acks.iter().map(|c| c.mdt[1]).collect();
        assert_eq!(sent, name);
        // MHS toggles from each acknowledged step to the next.
        assert!(acks.windows(2).all(|w| w[0].mdt[0] & 1 != w[1].mdt[0] & 1));
        // END_MDT (bit 2) only on the last step; element 2, write (L/S bit 1).
        let ends: Vec<bool> = acks.iter().map(|c| c.mdt[0] & 4 != 0).collect();
        assert_eq!(ends.iter().filter(|e| **e).count(), 1);
        assert_eq!(ends.last(), Some(&true));
        assert!(
            acks.iter()
                .all(|c| (c.mdt[0] >> 3) & 7 == 2 && c.mdt[0] & 2 != 0)
        );
        // The host bits of the control and status words are kept.
        assert!(cycles.iter().all(|c| c.mdt[0] & 0xE000 == 0xE000));
        // Held cycles: the element change and the END_MDT check (spec-notes "Service
        // containers"), each answered after the drive's reaction.
        assert!(
            cycles.len() <= 32 + 3,
            "{variant:?}: {} cycles",
            cycles.len()
        );
        let m = master_sc(&mut r);
        assert_eq!(m.pointers.wrdatpt, BUF + 32);
        assert!(m.m_busy && m.end_mdt);
    }
}

// 410B §4.2.4: a read (L/S_MDT = 0) fills the master's read buffer from the AT's info
// words, NINFO_READ per step; INT_END_RDBUF at RDDATLAST; SETEND → END_MDT on the last.
#[test]
fn sixty_byte_name_slave_to_master_one_handshake_per_cycle() {
    for variant in Variant::ALL {
        let mut r = sc_ring(variant);
        let mut drive = Drive::default();
        let name = name_words();
        drive.elements[2] = name.clone();
        open_idn(&mut r, &mut drive, IDN_NAME);
        master_read(&mut r, 2, 32, true);
        let cycles = run(&mut r, &mut drive, |m| m.int_end_rdbuf, 60);
        let acks: Vec<&Cycle> = cycles.iter().filter(|c| acknowledged(c)).collect();
        assert_eq!(acks.len(), 32, "{variant:?} {cycles:x?}");
        let got: Vec<u16> = acks.iter().filter_map(|c| c.at.map(|a| a[1])).collect();
        assert_eq!(got, name);
        assert_eq!(words(&mut r.master, M_SC + u16::from(BUF), 32), name);
        assert!(
            acks.last().is_some_and(|c| c.mdt[0] & 4 != 0),
            "END_MDT on the last step"
        );
        assert!(acks.iter().all(|c| c.mdt[0] & 2 == 0), "read");
        assert!(
            cycles.len() <= 32 + 3,
            "{variant:?}: {} cycles",
            cycles.len()
        );
    }
}

// 410B §4.2.4: a one-word value written in one step (SETEND: END_MDT on the first and last
// step), the slave's INT_END_MDT holding BUSY_AT until its host took the value.
#[test]
fn one_word_value_written_through_the_chips() {
    for variant in Variant::ALL {
        let mut r = sc_ring(variant);
        let mut drive = Drive::default();
        open_idn(&mut r, &mut drive, 0x0024);
        let before = drive.interrupts;
        master_write(&mut r, 7, &[0x1234]);
        let cycles = run(&mut r, &mut drive, |m| m.int_end_wrbuf, 10);
        assert_eq!(drive.elements[7], vec![0x1234], "{variant:?}");
        let acks: Vec<&Cycle> = cycles.iter().filter(|c| acknowledged(c)).collect();
        assert_eq!(acks.len(), 1, "{variant:?} {cycles:x?}");
        assert_eq!(acks[0].mdt[1], 0x1234);
        assert_eq!(
            acks[0].mdt[0] & 0x3E,
            0x38 | 4 | 2,
            "element 7, last, write"
        );
        // The slave's host was interrupted for the element change and for END_MDT.
        assert_eq!(drive.interrupts - before, 2, "{variant:?}");
        let m = master_sc(&mut r);
        assert_eq!(m.pointers.wrdatpt, BUF + 1);
    }
}

// 410B §4.2.4 master INT_HS_TIMEOUT with §4.1 0DH HS_TIMEOUT: the slave never answers
// (its microprocessor sleeps through INT_ELEM_CHANGE, BUSY_AT stays 1 — BUSY_CNT counts
// busy cycles only when set, so the handshake difference is what counts here).
#[test]
fn handshake_timeout_when_the_slave_never_answers() {
    for variant in Variant::ALL {
        let mut r = sc_ring(variant);
        let mut drive = Drive::default();
        open_idn(&mut r, &mut drive, 0x0024);
        // 410B §4.1 0DH: HS_TIMEOUT = 5 cycles (bits 7-0), BUSY_TIMEOUT = 0 (off).
        r.master.write(Register::ScTimeout, 5);
        // The slave's telegram processor stops sending ATs: no answer at all.
        r.slave.write(Register::Ctrl3, 0);
        master_write(&mut r, 7, &[0x0001]);
        let cycles = run(&mut r, &mut drive, |m| m.int_hs_timeout, 10);
        let m = master_sc(&mut r);
        assert!(m.int_hs_timeout && m.m_busy, "{variant:?} {m:?}");
        assert_eq!(m.err_cnt, 5);
        assert!(cycles.iter().all(|c| c.at.is_none()));
        // The step's first MDT, then one count per unanswered cycle (spec-notes "ERR_CNT"):
        // the fifth unanswered cycle (the sixth MDT) raises the timeout.
        assert_eq!(cycles.len(), 1 + 5, "{variant:?} {cycles:x?}");
        assert_eq!(drive.idn, 0x0024);
    }
}
