//! A master chip driven by hand (a static RAM image from `ram_layout::build` for the master
//! and the drvsc master client) and a slave chip run by the drive node (`DriveNode`, the
//! SERCDRV slave over an emulated drive), back to back on the line: master → slave →
//! master, fibre delay 1 µs, the slave's host woken whenever its INT0 is active (410B §2
//! INT0; 3H.0 INTFL0).
#![allow(dead_code)]

use sercdrv::ram_layout::{self, RamLayout, RamLayoutRequest, Role};
use sercdrv::service_channel::{Completion, ContainerSlot, Request, ServiceChannelMaster, Wiring};
use sercdrv::timing::{self, CycleTiming, DriveParameters, TimingRequest, TimingRules};
use sercon_model::serial_port::LineSegment;
use sercon_model::{Chip, ChipConfig};
use sercon_regs::host::{HostProgram, Wake};
use sercon_regs::{Ctrl1, Ctrl3, IntFlagsHi, Register, SerconBus, SerconBusExt, Variant};
use sercos_drive::database::IdnDatabase;
use sercos_drive::node::DriveNode;
use sercos_wire::address::DriveAddress;
use sercos_wire::attribute::Value;
use sercos_wire::idn::Idn;
use sercos_wire::time::{BitRate, Duration, Instant};

/// The slave's address.
pub const ADDRESS: u8 = 3;
/// P-0-0002, the emulated drive's bit rate.
pub const BIT_RATE: Idn = Idn::from_raw(0x8002);
/// S-0-0015, telegram type.
pub const TELEGRAM_TYPE: Idn = Idn::from_raw(15);

/// 410B §4.1 0CH.0 MSTEN, 0CH.1 MSTMASTER, 0CH.2 COMBLK0, 0CH.10 CYCSTART.
const MSTEN: u16 = 1;
const MSTMASTER: u16 = 1 << 1;
const COMBLK0: u16 = 1 << 2;
const CYCSTART: u16 = 1 << 10;

/// The line rate and cycle the tests use per variant: the 816 at 16 Mbit/s with a 250 µs
/// cycle, the 410B at 4 Mbit/s with 500 µs (the rates `ChipConfig`'s straps give a master
/// that leaves 1H alone).
pub fn rate_and_cycle(variant: Variant) -> (BitRate, u32) {
    match variant {
        Variant::Sercon816 => (BitRate::Mbit16, 250),
        Variant::Sercon410b => (BitRate::Mbit4, 500),
    }
}

/// The emulated drive's database: the catalogue with P-0-0002 set to the ring's rate.
pub fn database(variant: Variant) -> IdnDatabase {
    let mut db = IdnDatabase::standard();
    let (rate, _) = rate_and_cycle(variant);
    db.set_internal(BIT_RATE, &Value::Unsigned(u64::from(rate.mbit())))
        .expect("P-0-0002");
    db
}

/// The cycle the master plans for the drive with telegram type 2 (S-0-0036 command,
/// S-0-0040 feedback, 4 bytes each) from the drive's catalogue times.
pub fn plan(variant: Variant, db: &IdnDatabase) -> CycleTiming {
    let (rate, cycle) = rate_and_cycle(variant);
    let n = |raw: u16| db.number(Idn::from_raw(raw)).expect("time") as u16;
    timing::plan_cycle(&TimingRequest {
        bit_rate: rate,
        cycle_time_us: cycle,
        nc_cycle_time_us: cycle,
        drives: vec![DriveParameters {
            address: ADDRESS,
            t1min_us: n(3),
            t_atmt_us: n(4),
            t5_us: n(5),
            t_mtsy_us: n(88),
            t_mtsg_us: n(90),
            at_data_bytes: 4,
            mdt_data_bytes: 4,
        }],
        rules: TimingRules::default(),
    })
    .expect("plan")
}

/// A sent telegram: who sent it, when it started, ADR and data.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Sent {
    /// The master sent it.
    pub master: bool,
    /// Line start of the segment.
    pub start: Instant,
    /// ADR and data.
    pub bytes: Vec<u8>,
}

/// The ring.
pub struct Ring {
    pub master: Chip,
    pub slave: Chip,
    pub node: DriveNode,
    pub client: ServiceChannelMaster,
    pub layout: RamLayout,
    pub timing: CycleTiming,
    pub delay: Duration,
    pub now: Instant,
    /// Telegrams each chip released itself (not repeated).
    pub sent: Vec<Sent>,
    pub completions: Vec<Completion>,
    /// Times the slave's host was woken by INT0.
    pub wakes: usize,
    slave_forwarding: Vec<Instant>,
}

impl Ring {
    /// Master and slave of `variant`; the master is laid out for phases 0-2 (block 0) and
    /// 3-4 (block 1) and starts cycling in phase 0.
    pub fn new(variant: Variant) -> Ring {
        let db = database(variant);
        let timing = plan(variant, &db);
        let (_, cycle) = rate_and_cycle(variant);
        let mut config = sercdrv::slave::SlaveConfig::new(variant, ADDRESS);
        config.bit_rate = rate_and_cycle(variant).0;
        config.noncyclic_cycle_us = cycle;
        let node = DriveNode::with_config(config, db).expect("node");
        let (master_cfg, slave_cfg) = match variant {
            Variant::Sercon816 => (ChipConfig::sercon816(), ChipConfig::sercon816()),
            Variant::Sercon410b => (ChipConfig::sercon410b(), ChipConfig::sercon410b()),
        };
        let mut master = Chip::new(master_cfg);
        let slave = Chip::new(slave_cfg);
        let layout = ram_layout::build(&RamLayoutRequest::new(variant, Role::Master, &timing))
            .expect("master layout");
        for w in &layout.writes {
            master.write_ram(w.address, w.word);
        }
        // Phases 0-2: the master's AT receive header checks the receive time (TCHK = 1,
        // window ±20 µs, 410B §4.1 18H/19H JTRDEL1/2), so a missing AT does not hold back
        // the MDT that the slave answers next cycle.
        let at_header = layout.map.blocks[0].telegrams[0].header;
        let w0 = master.read_ram(at_header);
        master.write_ram(at_header, w0 | 1 << 12);
        master.write(Register::Jtrdel1, 20);
        master.write(Register::Jtrdel2, 20);
        let sc = layout.map.service_containers[0];
        let slot = ContainerSlot::new(variant, sc.nsv, sc.address, sc.buffer_words).expect("slot");
        let mut client = ServiceChannelMaster::new([(
            slot,
            Wiring::Drive(DriveAddress::new(ADDRESS).expect("address")),
        )]);
        client.init(&mut master);
        client.set_timeout(Some(Duration::from_millis(400)));
        // 410B §4.1 0EH: 1 µs predivider; 1H.3 REPON = 0 (the master ends the ring).
        let mclk = u32::try_from(master.config().mclk_hz).expect("mclk");
        master.write(
            Register::MclkDiv,
            u16::try_from(mclk / 1_000_000 - 1).expect("div"),
        );
        let c1: Ctrl1 = master.read_reg();
        master.write_reg(c1.difference(Ctrl1::REPON));
        master.write(Register::Tscyc0, cycle as u16);
        master.write(Register::Tscyc1, cycle as u16);
        // Phase 0: MSTs only (410B §4.1 3H.8 ENTMT = 0; the MST goes out regardless).
        master.write(Register::Phas, 0xFF00);
        master.write_reg(Ctrl3::empty());
        master.write(Register::Ctrl0C, MSTEN | MSTMASTER | CYCSTART);
        Ring {
            master,
            slave,
            node,
            client,
            layout,
            timing,
            delay: Duration::from_micros(1),
            now: Instant::ZERO,
            sent: Vec::new(),
            completions: Vec::new(),
            wakes: 0,
            slave_forwarding: Vec::new(),
        }
        .started()
    }

    fn started(mut self) -> Ring {
        self.node.wake(&mut self.slave, Instant::ZERO, Wake::Start);
        self
    }

    /// The master sends `phase` in its MST from the next cycle on, with block 0 for phases
    /// 0-2 and block 1 for 3-4 (410B §4.1 0AH PHAS0, 0CH.2 COMBLK0), data telegrams from
    /// phase 1 on (3H.8 ENTMT).
    pub fn master_phase(&mut self, phase: u8) {
        self.master.write(Register::Phas, 0xFF00 | u16::from(phase));
        let block = if (3..=4).contains(&phase) { COMBLK0 } else { 0 };
        let entmt = if phase == 0 {
            Ctrl3::empty()
        } else {
            Ctrl3::ENTMT
        };
        self.master.write_reg(entmt);
        self.master
            .write(Register::Ctrl0C, MSTEN | MSTMASTER | block);
    }

    /// Runs `n` cycles of the master.
    pub fn cycles(&mut self, n: u32) {
        let cycle = u64::from(self.timing.cycle_time_us);
        let until = self.now + Duration::from_micros(cycle * u64::from(n));
        self.run_to(until);
    }

    /// Runs both chips and both hosts to `until`.
    pub fn run_to(&mut self, until: Instant) {
        let step = Duration::from_picos((self.delay.as_picos() / 2).max(1));
        let mut out: Vec<LineSegment> = Vec::new();
        while self.now < until {
            let next = (self.now + step).min(until);
            self.master.advance_to(next);
            self.master.take_line_output(&mut out);
            for seg in out.drain(..) {
                if seg.hint.is_some() {
                    self.sent.push(Sent {
                        master: true,
                        start: seg.start,
                        bytes: seg
                            .hint
                            .as_ref()
                            .map(|h| h.telegram.to_vec())
                            .unwrap_or_default(),
                    });
                    let latency = seg
                        .bit_time
                        .saturating_mul(sercon_model::serial_port::REPEATER_LATENCY_BITS);
                    self.slave_forwarding.push(seg.start + self.delay + latency);
                }
                self.slave.line_input(seg.delayed(self.delay));
            }
            self.slave.advance_to(next);
            self.slave.take_line_output(&mut out);
            for seg in out.drain(..) {
                if let Some(hint) = &seg.hint {
                    let forwarded = self.slave_forwarding.contains(&seg.start);
                    if !forwarded {
                        self.sent.push(Sent {
                            master: false,
                            start: seg.start,
                            bytes: hint.telegram.to_vec(),
                        });
                    }
                }
                self.master.line_input(seg.delayed(self.delay));
            }
            self.slave_forwarding
                .retain(|t| *t + Duration::from_micros(50) >= next);
            let mut frames = Vec::new();
            self.master.take_rx_frames(&mut frames);
            self.slave.take_rx_frames(&mut frames);
            // 410B §2 INT0: the slave's host runs while its interrupt output is active.
            let ctrl3: Ctrl3 = self.slave.read_reg();
            if ctrl3.contains(Ctrl3::INTFL0) {
                self.wakes += 1;
                self.node.wake(
                    &mut self.slave,
                    next,
                    Wake::Interrupt {
                        int0: true,
                        int1: false,
                    },
                );
            }
            // The master's host: the service-channel client on INT_SC_n (410B §4.1 5H).
            let hi: IntFlagsHi = self.master.read_reg();
            if !hi.is_empty() {
                let done = self.client.on_interrupt(&mut self.master, hi, next);
                self.completions.extend(done);
            }
            self.now = next;
        }
    }

    /// Submits `request` and runs until it completes (at most `limit` cycles).
    pub fn transact(&mut self, request: Request) -> Completion {
        let ticket = self
            .client
            .submit(DriveAddress::new(ADDRESS).expect("address"), request);
        for _ in 0..2000 {
            self.cycles(1);
            let done = self.client.poll(&mut self.master, self.now);
            self.completions.extend(done);
            if let Some(i) = self.completions.iter().position(|c| c.ticket == ticket) {
                return self.completions.remove(i);
            }
        }
        panic!("no completion for {ticket:?}");
    }

    /// ATs the slave sent itself since `from`.
    pub fn slave_ats_since(&self, from: Instant) -> Vec<&Sent> {
        self.sent
            .iter()
            .filter(|s| !s.master && s.start >= from)
            .collect()
    }

    /// MDTs (master telegrams other than the 2-byte MST) sent since `from`.
    pub fn master_mdts_since(&self, from: Instant) -> Vec<&Sent> {
        self.sent
            .iter()
            .filter(|s| s.master && s.start >= from && s.bytes.len() > 2)
            .collect()
    }

    /// The phase 3-4 records of the drive in the master's RAM.
    pub fn master_drive_ram(&self) -> sercdrv::ram_layout::DriveRam {
        *self.layout.map.drive(ADDRESS).expect("drive in the map")
    }
}
