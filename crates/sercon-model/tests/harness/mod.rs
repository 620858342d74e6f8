//! Test harness for the telegram processor: RAM layout helpers and two or three chips wired
//! back to back in a ring (master → slave → [slave 2 →] master) over the real line
//! interface: `Chip::take_line_output` → fibre delay (and an optional fault: drop or corrupt
//! a master telegram) → `Chip::line_input`. Every test through it exercises the encoder, the
//! decoder, the slaves' repeaters and the telegram processors together.
#![allow(dead_code)]

use std::collections::VecDeque;

use sercon_model::serial_port::{LineSegment, LineSignal, REPEATER_LATENCY_BITS, Shared};
use sercon_model::{Chip, ChipConfig};
use sercon_regs::ram::container::ContainerControl;
use sercon_regs::ram::header::{EndMarker, RxHeader, TxEnable, TxHeader};
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};
use sercos_wire::line::BitVec;
use sercos_wire::time::{Duration, Instant};

/// 410B §4.1 0CH.0 MSTEN, 0CH.1 MSTMASTER, 0CH.10 CYCSTART.
pub const MSTEN: u16 = 1 << 0;
pub const MSTMASTER: u16 = 1 << 1;
pub const CYCSTART: u16 = 1 << 10;
/// 410B §4.1 3H.8 ENTMT.
pub const ENTMT: u16 = 1 << 8;
/// 410B §4.1 25H.10 MSTTCHK, 25H.11 PHAS12, 25H.12 FLMDTADR.
pub const MSTTCHK: u16 = 1 << 10;
pub const PHAS12: u16 = 1 << 11;
pub const FLMDTADR: u16 = 1 << 12;

/// `n` µs after time 0.
pub fn us(n: u64) -> Instant {
    Instant::ZERO + Duration::from_micros(n)
}

/// A chip of `variant` with a 1 µs predivider; the 816 runs at 16 Mbit/s (SBAUD16 = 0,
/// SBAUD = 0, 816 §2.3.1), the 410B at 4 Mbit/s (SCLK/16).
pub fn chip(variant: Variant) -> Chip {
    let mut c = match variant {
        Variant::Sercon816 => {
            let mut c = Chip::new(ChipConfig::sercon816());
            c.write(Register::MclkDiv, 31);
            c
        }
        Variant::Sercon410b => Chip::new(ChipConfig::sercon410b()),
    };
    c.write(Register::Tscyc0, 100);
    c
}

/// Writes a transmit header at `at` (410B §4.2.1).
pub fn tx_header(c: &mut Chip, at: u16, h: TxHeader) {
    let v = c.config().variant;
    c.write_ram_words(at, &h.to_words(v));
}

/// Writes a receive header at `at` (410B §4.2.1).
pub fn rx_header(c: &mut Chip, at: u16, h: RxHeader) {
    let v = c.config().variant;
    c.write_ram_words(at, &h.to_words(v));
}

/// Writes an end marker at `at` (410B §4.2.3).
pub fn end_marker(c: &mut Chip, at: u16) {
    c.write_ram_words(at, &EndMarker::default().to_words());
}

/// Control word 0 of a container of `len` words (410B §4.2.2).
pub fn control(len: u16, lastdc: bool) -> u16 {
    ContainerControl::new(len, false, 0, false, lastdc)
        .map(|c| c.to_word())
        .unwrap_or(0)
}

/// A transmit header with the usual fields.
pub fn tx(adr: u8, en: TxEnable, trt: u16, tlen: u16, pt: u16) -> TxHeader {
    TxHeader {
        adr,
        en,
        trt,
        tlen,
        pt,
        ..TxHeader::default()
    }
}

/// A receive header with the usual fields.
pub fn rx(adr: u8, achk: bool, trt: u16, tlen: u16, pt: u16) -> RxHeader {
    RxHeader {
        adr,
        achk,
        trt,
        tlen,
        pt,
        ..RxHeader::default()
    }
}

/// The blocks of a phase-4 ring of one slave (410B §4.2.1–§4.2.3): the master sends the MDT
/// (8 words) at TRT 5 and expects the AT (8 words, ADR 1) at TRT 40, the slave the other way
/// round; both receive headers check their time when `tchk` (TCHK with JTRDEL1 = 2,
/// JTRDEL2 = 3). Master: COMPT0 → tx MDT (16) → rx AT (29) → end marker (44); slave:
/// COMPT0 → rx MDT (16) → tx AT (31) → end marker (44).
pub fn one_slave_blocks(m: &mut Chip, s: &mut Chip, tchk: bool) {
    m.write_ram(0, 16);
    tx_header(m, 16, tx(255, TxEnable::Continuous, 5, 8, 29));
    m.write_ram(20, control(8, true));
    let mut r = rx(1, true, 40, 8, 44);
    r.tchk = tchk;
    rx_header(m, 29, r);
    m.write_ram_words(34, &[control(8, true), 0]);
    end_marker(m, 44);
    s.write_ram(0, 16);
    let mut r = rx(255, true, 5, 8, 31);
    r.tchk = tchk;
    rx_header(s, 16, r);
    s.write_ram_words(21, &[control(8, true), 0]);
    tx_header(s, 31, tx(1, TxEnable::Continuous, 40, 8, 44));
    s.write_ram(35, control(8, true));
    end_marker(s, 44);
    for c in [m, s] {
        c.write(Register::Jtrdel1, 2);
        c.write(Register::Jtrdel2, 3);
    }
}

/// Starts phase 4 (410B §4.1 0AH PHAS, 3H.8 ENTMT, 0CH.0/1/10 MSTEN, MSTMASTER, CYCSTART):
/// the slave a SERCOS slave taking phase 4 in PHAS0, the master sending phase 4 in continuous
/// cycles from now, both with their telegrams on.
pub fn start_phase4(m: &mut Chip, s: &mut Chip) {
    s.write(Register::Phas, 0xFF04);
    s.write(Register::Ctrl3, ENTMT);
    s.write(Register::Ctrl0C, MSTEN);
    m.write(Register::Phas, 0x0404);
    m.write(Register::Ctrl3, ENTMT);
    m.write(Register::Ctrl0C, MSTEN | MSTMASTER | CYCSTART);
}

/// Reads `n` RAM words from `at`.
pub fn words(c: &mut Chip, at: u16, n: u16) -> Vec<u16> {
    (0..n).map(|i| c.read_ram(at + i)).collect()
}

/// 410B §4.1 1H.3 REPON.
pub const REPON: u16 = 1 << 3;

/// A telegram a chip sent itself (not forwarded by its repeater), as seen on its output.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Sent {
    /// First bit of the opening flag.
    pub start: Instant,
    /// After the last bit of the closing flag.
    pub end: Instant,
    /// ADR and data, without FCS.
    pub bytes: Vec<u8>,
}

/// One node of the ring and what its output has shown.
struct Node {
    /// Starts of segments received, shifted by the repeater latency: an output segment
    /// starting at one of them is forwarded, not sent.
    forwarded_at: VecDeque<Instant>,
}

/// A master and one or two slaves in a ring: master → slave → (slave 2 →) master, each fibre
/// `delay` long. The slaves' repeaters (REPON = 1 from the straps TM0 = TM1 = 1, 816 §2.3.3;
/// 410B §4.1 1H.3 reset value) forward the master's telegrams around the ring; the master's
/// repeater is switched off (a master ends the ring, as a driver programs it).
pub struct Ring {
    pub master: Chip,
    pub slave: Chip,
    pub slave2: Option<Chip>,
    /// Fibre delay of every link.
    pub delay: Duration,
    /// Every telegram a chip sent itself, in order of release, tagged (true = master).
    pub log: Vec<(bool, Sent)>,
    /// Frames received (ADR, data, FCS result), per chip: master, slave, slave 2.
    pub received: [Vec<sercon_model::serial_port::RxFrame>; 3],
    /// Master telegrams (counted in the order sent, MSTs included) whose bits the link
    /// master → slave corrupts: the hint is dropped and the receiver decodes an FCS error.
    pub corrupt_master: Vec<usize>,
    /// Master telegrams the link master → slave drops (the fibre keeps the filler).
    pub drop_master: Vec<usize>,
    master_count: usize,
    nodes: [Node; 3],
    now: Instant,
    buf: Vec<LineSegment>,
}

impl Ring {
    /// Wires `master` and `slave`; the master's repeater is switched off.
    pub fn new(master: Chip, slave: Chip) -> Self {
        Self::with_slaves(master, slave, None)
    }

    /// Wires `master`, `slave` and `slave2` (in that order around the ring).
    pub fn three(master: Chip, slave: Chip, slave2: Chip) -> Self {
        Self::with_slaves(master, slave, Some(slave2))
    }

    fn with_slaves(mut master: Chip, slave: Chip, slave2: Option<Chip>) -> Self {
        // 410B §4.1 1H.3 REPON = 0: the master does not forward what comes back to it.
        let c1 = master.read(Register::Ctrl1);
        master.write(Register::Ctrl1, c1 & !REPON);
        let node = || Node {
            forwarded_at: VecDeque::new(),
        };
        Ring {
            master,
            slave,
            slave2,
            delay: Duration::from_micros(1),
            log: Vec::new(),
            received: [Vec::new(), Vec::new(), Vec::new()],
            corrupt_master: Vec::new(),
            drop_master: Vec::new(),
            master_count: 0,
            nodes: [node(), node(), node()],
            now: Instant::ZERO,
            buf: Vec::new(),
        }
    }

    /// The simulated time the ring has reached.
    pub fn now(&self) -> Instant {
        self.now
    }

    /// Runs every chip to `until` in steps of half the fibre delay, so every segment reaches
    /// its receiver before the receiver's time passes its start.
    pub fn run_to(&mut self, until: Instant) {
        let step = Duration::from_picos((self.delay.as_picos() / 2).max(1));
        while self.now < until {
            let next = (self.now + step).min(until);
            let n = if self.slave2.is_some() { 3 } else { 2 };
            for i in 0..n {
                self.chip(i).advance_to(next);
                let mut out = std::mem::take(&mut self.buf);
                self.chip(i).take_line_output(&mut out);
                for seg in out.drain(..) {
                    self.carry(i, (i + 1) % n, seg);
                }
                self.buf = out;
            }
            for i in 0..n {
                let mut frames = Vec::new();
                self.chip(i).take_rx_frames(&mut frames);
                self.received[i].extend(frames);
            }
            self.now = next;
        }
    }

    fn chip(&mut self, i: usize) -> &mut Chip {
        match i {
            0 => &mut self.master,
            1 => &mut self.slave,
            _ => self.slave2.as_mut().unwrap_or(&mut self.slave),
        }
    }

    /// Carries one output segment of chip `from` over the fibre to chip `to`.
    fn carry(&mut self, from: usize, to: usize, seg: LineSegment) {
        let mut seg = seg;
        if let Some(hint) = &seg.hint {
            let forwarded = {
                let node = &mut self.nodes[from];
                while node.forwarded_at.front().is_some_and(|t| *t < seg.start) {
                    node.forwarded_at.pop_front();
                }
                node.forwarded_at.front() == Some(&seg.start)
            };
            if !forwarded {
                let start = seg.start + seg.bit_time.saturating_mul(hint.offset);
                let end = seg.end().unwrap_or(start);
                let sent = Sent {
                    start,
                    end,
                    bytes: hint.telegram.to_vec(),
                };
                self.log.push((from == 0, sent));
                if from == 0 {
                    let i = self.master_count;
                    self.master_count += 1;
                    if self.drop_master.contains(&i) {
                        return;
                    }
                    if self.corrupt_master.contains(&i) {
                        seg = corrupted(seg);
                    }
                }
            }
        }
        let seg = seg.delayed(self.delay);
        if seg.hint.is_some() {
            let latency = seg.bit_time.saturating_mul(REPEATER_LATENCY_BITS);
            self.nodes[to].forwarded_at.push_back(seg.start + latency);
        }
        self.chip(to).line_input(seg);
    }
}

/// `seg` with the light level of one bit in the middle of its telegram inverted (NRZI: two
/// data bits change) and the hint dropped, as a fault injector must (serial_port segment).
pub fn corrupted(mut seg: LineSegment) -> LineSegment {
    let offset = seg.hint.as_ref().map_or(0, |h| h.offset);
    if let LineSignal::Bits(bits) = &seg.signal {
        let len = bits.len();
        // Past the opening flag and ADR: in the data (or the FCS of a short telegram).
        let flip = (offset + 8 + 12).min(len.saturating_sub(12));
        let mut out = BitVec::with_capacity(len as usize);
        for (i, b) in bits.bits().iter().enumerate() {
            out.push(if i as u64 == flip { !b } else { b });
        }
        seg.signal = LineSignal::Bits(Shared::new(out));
    }
    seg.hint = None;
    seg
}
