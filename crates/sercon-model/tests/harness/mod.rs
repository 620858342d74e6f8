//! Test harness for the telegram processor: RAM layout helpers and two chips wired back
//! to back (master → slave → master ring) through their line-side entry points
//! (`Chip::drain_line_telegrams` / `Chip::receive_telegram`).
#![allow(dead_code)]

use sercon_model::telegram_processor::{LineTelegram, RxTelegram};
use sercon_model::{Chip, ChipConfig};
use sercon_regs::ram::container::ContainerControl;
use sercon_regs::ram::header::{EndMarker, RxHeader, TxEnable, TxHeader};
use sercon_regs::{Register, SerconBus, SerconBusExt, Variant};
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

/// Reads `n` RAM words from `at`.
pub fn words(c: &mut Chip, at: u16, n: u16) -> Vec<u16> {
    (0..n).map(|i| c.read_ram(at + i)).collect()
}

/// A master and a slave in a ring: master → slave takes `delay`, slave → master takes
/// `delay`, and the master's own telegrams come back to it after `2 × delay`.
pub struct Ring {
    pub master: Chip,
    pub slave: Chip,
    pub delay: Duration,
    /// Every telegram either chip sent, in order, tagged (true = master).
    pub log: Vec<(bool, LineTelegram)>,
    /// Master → slave telegrams the ring corrupts (FCS error) by index in `log` order
    /// of master telegrams.
    pub corrupt_master: Vec<usize>,
    /// Master telegrams to drop (not delivered to the slave) by index.
    pub drop_master: Vec<usize>,
    master_count: usize,
    now: Instant,
}

impl Ring {
    /// Wires `master` and `slave`.
    pub fn new(master: Chip, slave: Chip) -> Self {
        Ring {
            master,
            slave,
            delay: Duration::from_micros(1),
            log: Vec::new(),
            corrupt_master: Vec::new(),
            drop_master: Vec::new(),
            master_count: 0,
            now: Instant::ZERO,
        }
    }

    fn shifted(t: &LineTelegram, d: Duration, fcs_ok: bool) -> RxTelegram {
        RxTelegram {
            start: t.start + d,
            end: t.end + d,
            bytes: t.bytes.clone(),
            fcs_ok,
        }
    }

    /// Runs both chips to `until` in steps of half the ring delay, so every telegram
    /// reaches its receiver before its start.
    pub fn run_to(&mut self, until: Instant) {
        let step = Duration::from_picos((self.delay.as_picos() / 2).max(1));
        let mut buf = Vec::new();
        while self.now < until {
            let next = (self.now + step).min(until);
            self.master.advance_to(next);
            self.master.drain_line_telegrams(&mut buf);
            for t in buf.drain(..) {
                let i = self.master_count;
                self.master_count += 1;
                let ok = !self.corrupt_master.contains(&i);
                if !self.drop_master.contains(&i) {
                    self.slave
                        .receive_telegram(Self::shifted(&t, self.delay, ok));
                }
                self.master
                    .receive_telegram(Self::shifted(&t, self.delay + self.delay, true));
                self.log.push((true, t));
            }
            self.slave.advance_to(next);
            self.slave.drain_line_telegrams(&mut buf);
            for t in buf.drain(..) {
                self.master
                    .receive_telegram(Self::shifted(&t, self.delay, true));
                self.log.push((false, t));
            }
            self.now = next;
        }
    }
}
