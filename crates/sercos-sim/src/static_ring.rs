//! A configured phase-4 ring of one master and n slaves whose hosts write static RAM images
//! at start (drivers come later): transmission blocks per 410B §4.2, registers per §4.1.
//!
//! Layout (`docs/spec-notes.md`, "Ring simulation"): the master sends one broadcast MDT
//! (ADR 255) whose single container holds every slave's record (`mdt_words` per slave) and
//! receives one AT per slave; each slave receives its record from the MDT (POS) and sends
//! its AT. Where the RAM is too small (254 slaves), the master's AT containers have LEN 0
//! (the telegrams are checked, VAL/RERR/NERR, but not stored) and, if still needed, the MDT
//! container is shorter than the telegram (410B §4.2.2: the rest goes out as 0).

use sercon_model::ChipConfig;
use sercon_model::config::Straps;
use sercon_regs::Register;
use sercon_regs::ram::container::ContainerControl;
use sercon_regs::ram::header::{EndMarker, RxHeader, TxEnable, TxHeader};
use sercos_wire::time::{BitRate, Duration};

use crate::config::{Delivery, NodeConfig, SimConfig, TraceConfig};
use crate::error::SimError;
use crate::host::{Access, HostProgram, StaticImageHost};
use crate::topology::Topology;

/// 410B §4.1 0CH.0 MSTEN, 0CH.1 MSTMASTER, 0CH.10 CYCSTART.
const MSTEN: u16 = 1 << 0;
const MSTMASTER: u16 = 1 << 1;
const CYCSTART: u16 = 1 << 10;
/// 410B §4.1 3H.8 ENTMT.
const ENTMT: u16 = 1 << 8;
/// 410B §4.1 1H.3 REPON, 1H.10 ENTSBAUD, 1H.6 SWBAUD; 816 table 2.3.1 1H.15 SWBAUD16.
const REPON: u16 = 1 << 3;
const ENTSBAUD: u16 = 1 << 10;
const SWBAUD: u16 = 1 << 6;
const SWBAUD16: u16 = 1 << 15;
/// First header: after the eleven fixed words (410B §4.2), at 16.
const FIRST_HEADER: u16 = 16;
/// MDT starts this long after the end of the MST (µs, TRT).
const MDT_TRT_US: u16 = 4;
/// Receive window before and after TRT at the master (µs; 410B §4.1 18H, 19H).
const JTRDEL_US: u16 = 2;
/// Gap between telegrams (µs).
const GAP_US: u64 = 2;

/// What [`StaticRing::build`] gives: the configuration, one host program per node, the plan.
pub type BuiltRing = (SimConfig, Vec<Box<dyn HostProgram>>, RingPlan);

/// A static ring to build.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticRing {
    /// Slaves 1..=n (at most 254).
    pub slaves: usize,
    /// Line bit rate (816 §2.3.1).
    pub bit_rate: BitRate,
    /// Communication cycle in µs (TSCYC0).
    pub cycle_us: u16,
    /// MDT data words per slave.
    pub mdt_words: u16,
    /// AT data words per slave.
    pub at_words: u16,
    /// Length of every fibre in metres.
    pub fibre_m: u32,
    /// Reference or fast delivery.
    pub delivery: Delivery,
    /// Seed.
    pub seed: u64,
    /// AT TRTs to use instead of the planned ones (index i − 1 for slave i), e.g. to make
    /// telegrams collide on a bus.
    pub at_trt_override: Option<Vec<u16>>,
    /// Slaves repeat (1H.3 REPON = 1): on for a ring, off for an RS-485 bus.
    pub repon: bool,
    /// The MDT after the ATs (MST, AT 1 … AT n, MDT: the order SERCOS drives are usually
    /// configured in, AT transmission starting time T1 before the MDT's T2, and the one the
    /// master driver plans, `sercdrv::timing`) instead of right after the MST (MST, MDT,
    /// AT 1 … AT n). Each node's header list follows the telegrams' order in time
    /// (410B §4.2: the processor works through the list in order).
    pub mdt_after_ats: bool,
}

impl StaticRing {
    /// `slaves` slaves at 16 Mbit/s, `cycle_us`, 8 data words each way, 10 m fibres.
    pub fn new(slaves: usize, cycle_us: u16) -> Self {
        StaticRing {
            slaves,
            bit_rate: BitRate::Mbit16,
            cycle_us,
            mdt_words: 8,
            at_words: 8,
            fibre_m: 10,
            delivery: Delivery::Fast,
            seed: 1,
            at_trt_override: None,
            repon: true,
            mdt_after_ats: false,
        }
    }
}

/// Where things are and when they happen in a built ring.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RingPlan {
    /// TRT of the MDT (µs after the end of the MST).
    pub mdt_trt_us: u16,
    /// TRT of slave i's AT at index i − 1 (µs after the end of the MST at that slave).
    pub at_trt_us: Vec<u16>,
    /// Words of the MDT telegram (TLEN).
    pub mdt_tlen: u16,
    /// Master: the MDT's data words in RAM (from the start of the MDT container data).
    pub master_mdt_data: u16,
    /// Words of the MDT container (≤ TLEN).
    pub mdt_container_len: u16,
    /// Master: receive header of slave i's AT at index i − 1.
    pub master_at_header: Vec<u16>,
    /// Master: first data word of slave i's AT, when stored.
    pub master_at_data: Vec<Option<u16>>,
    /// Slave: its MDT receive header.
    pub slave_mdt_header: u16,
    /// Slave: its MDT record.
    pub slave_mdt_data: u16,
    /// Slave: its AT data.
    pub slave_at_data: u16,
}

/// The value slave `i` sends in AT word `k` (a recognisable pattern).
pub fn at_pattern(slave: usize, k: u16) -> u16 {
    0xA000 | ((slave as u16 & 0xFF) << 4) | (k & 0xF)
}

/// The value the master sends to slave `i` in MDT word `k`.
pub fn mdt_pattern(slave: usize, k: u16) -> u16 {
    0x5000 | ((slave as u16 & 0xFF) << 4) | (k & 0xF)
}

/// Upper bound of a frame's line bits for `bytes` telegram bytes: two flags and every byte
/// (with the FCS) stuffed at worst (a 0 after five 1s).
pub fn worst_frame_bits(bytes: u64) -> u64 {
    16 + ((bytes + 2) * 8 * 6).div_ceil(5)
}

fn ctrl(len: u16, lastdc: bool) -> Result<u16, SimError> {
    ContainerControl::new(len, false, 0, false, lastdc)
        .map(|c| c.to_word())
        .map_err(|e| SimError::Layout(format!("container: {e}")))
}

fn reg(r: Register, value: u16) -> Access {
    Access::Register {
        address: r.address(),
        value,
    }
}

/// 1H for `rate` by software (816 table 2.3.1, ENTSBAUD = 1).
fn reg1(rate: BitRate, repon: bool) -> u16 {
    let rate_bits = match rate {
        BitRate::Mbit2 => SWBAUD16 | SWBAUD,
        BitRate::Mbit4 => SWBAUD16,
        BitRate::Mbit8 => SWBAUD,
        BitRate::Mbit16 => 0,
    };
    ENTSBAUD | rate_bits | if repon { REPON } else { 0 }
}

impl StaticRing {
    /// The simulation configuration (SERCON816s, no faults, no traces), one static host per
    /// node, and the plan.
    pub fn build(&self) -> Result<BuiltRing, SimError> {
        let n = self.slaves;
        if n == 0 || n > crate::config::MAX_SLAVES {
            return Err(SimError::TooManySlaves(n));
        }
        // 410B §4.2.2: LEN is 10 bits.
        if self.mdt_words > 1023 || self.at_words > 1023 {
            return Err(SimError::Layout(
                "more than 1023 words in a container".into(),
            ));
        }
        let n16 = n as u16;
        let mut chip = ChipConfig::sercon816();
        // 816 §2.3.3: TM0 = TM1 = 1, no test mode (REPON = 1 after reset).
        chip.straps = Straps::NORMAL;
        let ram = chip.variant.ram_words();
        let bt = self.bit_rate.bit_time();
        let us = |bits: u64| -> u64 { bt.saturating_mul(bits).as_picos().div_ceil(1_000_000) };
        // Timing (µs after the end of the MST at each node).
        let mdt_tlen = n16
            .checked_mul(self.mdt_words)
            .ok_or_else(|| SimError::Layout("MDT too long".into()))?;
        let mdt_us = us(worst_frame_bits(1 + 2 * u64::from(mdt_tlen)));
        let at_us = us(worst_frame_bits(1 + 2 * u64::from(self.at_words)));
        // The first telegram after the MST starts MDT_TRT_US after its end; each next one a
        // gap after the one before (410B §4.2.1 TRT).
        let trt = |t: u64| u16::try_from(t).map_err(|_| SimError::Layout("TRT overflow".into()));
        // The ring delay: every fibre and every slave's repeater latency (spec-notes).
        let ring = (Duration::from_nanos(5)
            .saturating_mul(u64::from(self.fibre_m) * (n as u64 + 1))
            + bt.saturating_mul(2 * n as u64))
        .as_picos();
        let ring_us = ring.div_ceil(1_000_000);
        let ring_floor_us = u16::try_from(ring / 1_000_000).unwrap_or(u16::MAX);
        let mut t = u64::from(MDT_TRT_US);
        if !self.mdt_after_ats {
            t += mdt_us + GAP_US;
        }
        let mut at_trt = Vec::with_capacity(n);
        for _ in 0..n {
            at_trt.push(trt(t)?);
            t += at_us + GAP_US;
        }
        let mdt_trt = if self.mdt_after_ats {
            // The master's list walks the AT headers before the MDT's (410B §4.2: in list
            // order), each AT arriving a ring delay after its TRT at the slave: the MDT's
            // TRT counts from the master's MST end, after the last AT has come round (else
            // its header is reached after its TRT, 17H PROGERR_FL, every cycle).
            t += ring_us;
            let m = trt(t)?;
            t += mdt_us + GAP_US;
            m
        } else {
            MDT_TRT_US
        };
        if let Some(o) = &self.at_trt_override {
            for (t, v) in at_trt.iter_mut().zip(o) {
                *t = *v;
            }
        }
        let mst_us = us(worst_frame_bits(2));
        if mst_us + t + ring_us > u64::from(self.cycle_us) {
            return Err(SimError::Layout(format!(
                "{} slaves need {} µs, cycle is {} µs",
                n,
                mst_us + t + ring_us,
                self.cycle_us
            )));
        }
        // Master RAM: MDT header, container, data; AT headers and containers; end marker.
        let fixed = u32::from(FIRST_HEADER) + 4 + 1 + 2;
        let at_full = 7 + u32::from(self.at_words);
        let (at_stored, mdt_len) = {
            let need_full = fixed + u32::from(mdt_tlen) + n as u32 * at_full;
            let need_min = fixed + n as u32 * 7;
            if need_full <= u32::from(ram) {
                (true, mdt_tlen)
            } else if need_min + u32::from(mdt_tlen) <= u32::from(ram) {
                (false, mdt_tlen)
            } else if need_min < u32::from(ram) {
                (false, (u32::from(ram) - need_min) as u16)
            } else {
                return Err(SimError::Layout(format!(
                    "{n} slaves do not fit the master RAM"
                )));
            }
        };
        let variant = chip.variant;
        let mut m_words: Vec<(u16, Vec<u16>)> = vec![(0, vec![FIRST_HEADER, FIRST_HEADER])];
        // The list in the order of the telegrams (410B §4.2): the MDT's transmit header (4
        // words, its container's control word, the data) and the ATs' receive headers (5
        // words, control word, position, the data if stored), each pointing to the next.
        let at_len = if at_stored { self.at_words } else { 0 };
        let ats_len = n16.saturating_mul(7 + at_len);
        let (mdt_at, ats_at) = if self.mdt_after_ats {
            (FIRST_HEADER + ats_len, FIRST_HEADER)
        } else {
            (FIRST_HEADER, FIRST_HEADER + 4 + 1 + mdt_len)
        };
        let mdt = TxHeader {
            adr: 255,
            en: TxEnable::Continuous,
            trt: mdt_trt,
            tlen: mdt_tlen,
            pt: mdt_at + 4 + 1 + mdt_len,
            ..TxHeader::default()
        };
        let mut w = mdt.to_words(variant).to_vec();
        w.push(ctrl(mdt_len, true)?);
        for i in 0..mdt_len {
            let slave = usize::from(i / self.mdt_words.max(1)) + 1;
            w.push(mdt_pattern(slave, i % self.mdt_words.max(1)));
        }
        m_words.push((mdt_at, w));
        // Slave: the MDT's receive header (5 words, control word, position, its record) and
        // its AT's transmit header (4 words, control word, the data), in the same order.
        let slave_mdt_len = 5 + 2 + self.mdt_words;
        let slave_at_len = 4 + 1 + self.at_words;
        let (slave_mdt, slave_at) = if self.mdt_after_ats {
            (FIRST_HEADER + slave_at_len, FIRST_HEADER)
        } else {
            (FIRST_HEADER, FIRST_HEADER + slave_mdt_len)
        };
        let mut plan = RingPlan {
            mdt_trt_us: mdt_trt,
            at_trt_us: at_trt.clone(),
            mdt_tlen,
            master_mdt_data: mdt_at + 5,
            mdt_container_len: mdt_len,
            master_at_header: Vec::new(),
            master_at_data: Vec::new(),
            slave_mdt_header: slave_mdt,
            slave_mdt_data: slave_mdt + 7,
            slave_at_data: slave_at + 5,
        };
        let mut p = ats_at;
        // In the order of the ATs' times (410B §4.2: the processor walks its list in order):
        // slave order unless `at_trt_override` moves them.
        let mut order: Vec<(u16, usize)> = at_trt.iter().copied().zip(0..).collect();
        order.sort();
        plan.master_at_header = vec![0; n];
        plan.master_at_data = vec![None; n];
        for (trt, i) in order {
            let trt = &trt;
            let len = at_len;
            let next = p + 7 + len;
            // 410B §4.2.1 TCHK: each AT is expected in its own window (18H/19H JTRDEL1/2
            // µs around TRT), TRT counted at the master, i.e. after the ring delay.
            let h = RxHeader {
                adr: (i + 1) as u8,
                achk: true,
                tchk: true,
                trt: trt.saturating_add(ring_floor_us),
                tlen: self.at_words,
                pt: next,
                ..RxHeader::default()
            };
            let mut w = h.to_words(variant).to_vec();
            w.extend([ctrl(len, true)?, 0]);
            w.extend(std::iter::repeat_n(0, usize::from(len)));
            if let Some(h) = plan.master_at_header.get_mut(i) {
                *h = p;
            }
            if let Some(d) = plan.master_at_data.get_mut(i) {
                *d = at_stored.then_some(p + 7);
            }
            m_words.push((p, w));
            p = next;
        }
        let end = if self.mdt_after_ats {
            mdt_at + 4 + 1 + mdt_len
        } else {
            p
        };
        m_words.push((end, EndMarker::default().to_words().to_vec()));
        let rate1 = |repon| reg1(self.bit_rate, repon);
        let common = |repon: bool| {
            vec![
                // 410B §4.1 0EH MCLKDIV: 32 MHz / (31 + 1) = 1 µs predivider (816 §2.11.1.2).
                reg(Register::MclkDiv, 31),
                reg(Register::Ctrl1, rate1(repon)),
                reg(Register::Tscyc0, self.cycle_us),
                reg(Register::Ctrl3, ENTMT),
            ]
        };
        let mut hosts: Vec<Box<dyn HostProgram>> = Vec::with_capacity(n + 1);
        let mut nodes = Vec::with_capacity(n + 1);
        let mut acc: Vec<Access> = m_words
            .into_iter()
            .map(|(address, words)| Access::Ram { address, words })
            .collect();
        acc.extend(common(false));
        acc.push(reg(Register::Jtrdel1, JTRDEL_US));
        acc.push(reg(Register::Jtrdel2, JTRDEL_US));
        // 410B §4.1 0AH PHAS0 = 4 (phase 4), 0CH: master, cycles from now.
        acc.push(reg(Register::Phas, 0x0404));
        acc.push(reg(Register::Ctrl0C, MSTEN | MSTMASTER | CYCSTART));
        hosts.push(Box::new(StaticImageHost { accesses: acc }));
        nodes.push(NodeConfig::new("master", chip));
        for i in 1..=n {
            let end = FIRST_HEADER + slave_mdt_len + slave_at_len;
            let after_mdt = if self.mdt_after_ats { end } else { slave_at };
            let after_at = if self.mdt_after_ats { slave_mdt } else { end };
            let mdt_rx = RxHeader {
                adr: 255,
                achk: true,
                trt: mdt_trt,
                tlen: mdt_tlen,
                pt: after_mdt,
                ..RxHeader::default()
            };
            let mut mdt_words = mdt_rx.to_words(variant).to_vec();
            mdt_words.extend([ctrl(self.mdt_words, true)?, (i as u16 - 1) * self.mdt_words]);
            mdt_words.extend(std::iter::repeat_n(0, usize::from(self.mdt_words)));
            let at = TxHeader {
                adr: i as u8,
                en: TxEnable::Continuous,
                trt: at_trt.get(i - 1).copied().unwrap_or(0),
                tlen: self.at_words,
                pt: after_at,
                ..TxHeader::default()
            };
            let mut at_words = at.to_words(variant).to_vec();
            at_words.push(ctrl(self.at_words, true)?);
            at_words.extend((0..self.at_words).map(|k| at_pattern(i, k)));
            // The slave's list in address order, one write (as the telegrams' order).
            let mut words = if self.mdt_after_ats {
                at_words.extend(mdt_words);
                at_words
            } else {
                mdt_words.extend(at_words);
                mdt_words
            };
            words.extend(EndMarker::default().to_words());
            let mut acc = vec![
                Access::Ram {
                    address: 0,
                    words: vec![FIRST_HEADER, FIRST_HEADER],
                },
                Access::Ram {
                    address: FIRST_HEADER,
                    words,
                },
            ];
            acc.extend(common(self.repon));
            // Slave: PHAS0 ignored (FFH), SERCOS slave (MSTEN, 410B §4.1 0CH.0).
            acc.push(reg(Register::Phas, 0xFF04));
            acc.push(reg(Register::Ctrl0C, MSTEN));
            hosts.push(Box::new(StaticImageHost { accesses: acc }));
            nodes.push(NodeConfig::new(&format!("slave{i}"), chip));
        }
        let cfg = SimConfig {
            topology: Topology::ring(n + 1, self.fibre_m),
            nodes,
            faults: Vec::new(),
            seed: self.seed,
            delivery: self.delivery,
            traces: TraceConfig::default(),
        };
        Ok((cfg, hosts, plan))
    }
}
