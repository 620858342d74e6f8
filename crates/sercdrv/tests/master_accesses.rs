//! The master's bus accesses per cycle in phase 4, eight drives (the `stack-8` ring of
//! `sercon bench`: SERCON816, 16 Mbit/s, 250 µs, double-buffered AT and MDT containers, one
//! per drive, the captures' telegram type): every access the master makes goes through a
//! counting bus in front of the simulated chip, and the test bounds them per cycle.
//!
//! What a cycle needs (spec-notes "Master accesses per cycle"): the interrupt flags once
//! (410B §4.1 4H), each AT container's header word and words once (410B §4.2.1 VAL, RERR),
//! the MDT records and the transmit header's VAL (410B §4.2.1), and each service container's
//! control word only while it is in use (410B §4.2.4).

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::rc::Rc;

use sercdrv::master::{Master, MasterConfig, Progress};
use sercon_model::ChipConfig;
use sercon_regs::{Register, SerconBus, Variant};
use sercos_drive::database::IdnDatabase;
use sercos_drive::node::DriveNode;
use sercos_sim::{HostProgram, NodeConfig, SimConfig, Simulation, Topology, TraceConfig, Wake};
use sercos_wire::address::DriveAddress;
use sercos_wire::idn::Idn;
use sercos_wire::time::{BitRate, Duration, Instant};

/// One kind of bus access.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Access {
    ReadReg(u8),
    WriteReg(u8),
    ReadRam,
    WriteRam,
}

/// Accesses counted by kind (registers by address, RAM in total), and the RAM addresses
/// read and written in each wake.
#[derive(Debug, Default)]
struct Counts {
    by_kind: BTreeMap<Access, u64>,
    wakes: u64,
    /// Per wake: the RAM words read and written, in order.
    wake_reads: Vec<Vec<u16>>,
    wake_writes: Vec<Vec<u16>>,
}

impl Counts {
    fn total(&self) -> u64 {
        self.by_kind.values().sum()
    }

    fn of(&self, access: Access) -> u64 {
        self.by_kind.get(&access).copied().unwrap_or(0)
    }
}

/// The chip's bus as the master sees it, every access counted.
struct CountingBus<'a> {
    inner: &'a mut dyn SerconBus,
    counts: &'a mut Counts,
}

impl CountingBus<'_> {
    fn note(&mut self, access: Access) {
        *self.counts.by_kind.entry(access).or_default() += 1;
    }
}

impl SerconBus for CountingBus<'_> {
    fn read_register(&mut self, address: u8) -> u16 {
        self.note(Access::ReadReg(address & 0x3F));
        self.inner.read_register(address)
    }

    fn write_register(&mut self, address: u8, value: u16) {
        self.note(Access::WriteReg(address & 0x3F));
        self.inner.write_register(address, value)
    }

    fn read_ram(&mut self, address: u16) -> u16 {
        self.note(Access::ReadRam);
        if let Some(wake) = self.counts.wake_reads.last_mut() {
            wake.push(address);
        }
        self.inner.read_ram(address)
    }

    fn write_ram(&mut self, address: u16, value: u16) {
        self.note(Access::WriteRam);
        if let Some(wake) = self.counts.wake_writes.last_mut() {
            wake.push(address);
        }
        self.inner.write_ram(address, value)
    }
}

/// The master as the simulator's host program, its accesses counted.
struct CountedMaster {
    master: Rc<RefCell<Master>>,
    counts: Rc<RefCell<Counts>>,
}

impl HostProgram for CountedMaster {
    fn wake(&mut self, bus: &mut dyn SerconBus, now: Instant, why: Wake) -> Option<Instant> {
        let mut counts = self.counts.borrow_mut();
        counts.wakes += 1;
        counts.wake_reads.push(Vec::new());
        counts.wake_writes.push(Vec::new());
        let mut counting = CountingBus {
            inner: bus,
            counts: &mut counts,
        };
        self.master.borrow_mut().wake(&mut counting, now, why)
    }
}

/// A drive node as a host program.
struct Drive(DriveNode);

impl HostProgram for Drive {
    fn wake(&mut self, bus: &mut dyn SerconBus, now: Instant, why: Wake) -> Option<Instant> {
        self.0.wake(bus, now, why)
    }
}

struct Stack8 {
    sim: Simulation,
    master: Rc<RefCell<Master>>,
    counts: Rc<RefCell<Counts>>,
    drives: Vec<DriveAddress>,
    cycle: Duration,
    done: u64,
}

const CYCLE_US: u32 = 250;

/// `cfg`'s master and `drives` emulated standard drives on a ring of 10 m fibres.
fn stack(cfg: MasterConfig) -> Stack8 {
    let variant = cfg.variant;
    let chip = || match variant {
        Variant::Sercon816 => ChipConfig::sercon816(),
        Variant::Sercon410b => ChipConfig::sercon410b(),
    };
    let drives = cfg.drives.clone();
    let (bit_rate, cycle_us) = (cfg.bit_rate, cfg.cycle_us);
    let master = Rc::new(RefCell::new(Master::new(cfg).expect("a valid master")));
    let counts = Rc::new(RefCell::new(Counts::default()));
    let mut nodes = vec![NodeConfig::new("master", chip())];
    let mut hosts: Vec<Box<dyn HostProgram>> = vec![Box::new(CountedMaster {
        master: master.clone(),
        counts: counts.clone(),
    })];
    for d in &drives {
        let mut sc = sercdrv::slave::SlaveConfig::new(variant, d.get());
        sc.bit_rate = bit_rate;
        sc.noncyclic_cycle_us = cycle_us;
        let node = DriveNode::with_config(sc, IdnDatabase::standard()).expect("a drive");
        nodes.push(NodeConfig::new(&format!("drive{}", d.get()), chip()));
        hosts.push(Box::new(Drive(node)));
    }
    let n = nodes.len();
    let sim = Simulation::new(
        SimConfig {
            topology: Topology::ring(n, 10),
            nodes,
            faults: Vec::new(),
            seed: 1,
            delivery: sercos_sim::Delivery::Fast,
            traces: TraceConfig::default(),
        },
        hosts,
    )
    .expect("a valid simulation");
    Stack8 {
        sim,
        master,
        counts,
        drives,
        cycle: Duration::from_micros(u64::from(cycle_us)),
        done: 0,
    }
}

impl Stack8 {
    fn run_to_phase4(&mut self) {
        for _ in 0..20_000 {
            let t = self.sim.now().saturating_add(self.cycle);
            self.sim.run_until(t).expect("the simulation runs");
            let m = self.master.borrow();
            assert_ne!(m.progress(), Progress::Halted, "{:#?}", m.status());
            if m.progress() == Progress::Cyclic {
                return;
            }
        }
        panic!("no phase 4");
    }

    /// `cycles` cycles as `sercon bench` runs them: before each, every drive gets a new
    /// velocity command (S-0-0036) and the control word "drive on, enable, restart"
    /// (sercos-telegrams.md control word bits 15-13).
    fn run(&mut self, cycles: u64) {
        self.run_with(cycles, |done, i| (done + i * 100) % 10_000);
    }

    /// [`Stack8::run`] with the velocity command `velocity(cycle, drive index)`.
    fn run_with(&mut self, cycles: u64, velocity: impl Fn(u64, u64) -> u64) {
        for _ in 0..cycles {
            {
                let mut m = self.master.borrow_mut();
                for (i, &d) in self.drives.iter().enumerate() {
                    let v = velocity(self.done, i as u64);
                    m.set_command(d, Idn::from_raw(36), v).expect("S-0-0036");
                    m.set_control_word(d, 0xE000).expect("control word");
                }
            }
            let t = self.sim.now().saturating_add(self.cycle);
            self.sim.run_until(t).expect("the simulation runs");
            self.done += 1;
        }
    }

    fn reset_counts(&mut self) {
        *self.counts.borrow_mut() = Counts::default();
    }
}

fn eight_drives() -> MasterConfig {
    let drives = (1..=8).filter_map(DriveAddress::new).collect();
    MasterConfig::new(Variant::Sercon816, BitRate::Mbit16, CYCLE_US, drives)
}

/// Per-cycle figures of `counts` over `cycles`, as text for the failure messages.
fn per_cycle(counts: &Counts, cycles: u64) -> String {
    let mut out = format!(
        "{:.1} accesses per cycle ({:.2} wakes):",
        counts.total() as f64 / cycles as f64,
        counts.wakes as f64 / cycles as f64
    );
    for (k, n) in &counts.by_kind {
        out.push_str(&format!(" {k:X?} {:.2};", *n as f64 / cycles as f64));
    }
    out
}

const MEASURED_CYCLES: u64 = 100;

/// The stack in plain cyclic operation (past S-0-0128 and the drives' ramp-up), counts
/// reset.
fn in_phase4(cfg: MasterConfig) -> Stack8 {
    let mut s = stack(cfg);
    s.run_to_phase4();
    s.run(20);
    s.reset_counts();
    s
}

/// Word addresses of the service containers' control words (SCPT0-7 at RAM words 2-9 name
/// each container's first word, 410B §4.2; five control words, §4.2.4).
fn service_control_words(s: &mut Stack8) -> Vec<u16> {
    let chip = s.sim.chip_mut(0).expect("the master's chip");
    (2..=9u16)
        .map(|scpt| chip.read_ram(scpt))
        .flat_map(|start| (0..5).map(move |i| start.wrapping_add(i)))
        .collect()
}

// 410B §4.1 4H (flags read, written 1 to clear), §4.2.1 (AT: word 0 for RERR/VAL, then the
// words of the buffer VAL names, once; MDT: the changed words, then VAL), §4.2.4 (service
// containers without a transfer are not read).
#[test]
fn stack8_phase4_accesses_per_cycle() {
    let mut s = in_phase4(eight_drives());
    let services = service_control_words(&mut s);
    s.run(MEASURED_CYCLES);
    let counts = s.counts.borrow();
    let text = per_cycle(&counts, MEASURED_CYCLES);
    eprintln!("{text}");
    let per = |n: u64| n as f64 / MEASURED_CYCLES as f64;
    let ring = s.master.borrow().status();
    assert_eq!(ring.progress, Progress::Cyclic, "{ring:#?}");
    assert!(ring.drives.iter().all(|d| d.ats_missed == 0), "{ring:#?}");
    // Interrupt flags: read, cleared, read once more (a flag raised while serving gives no
    // new INT0 edge); the wake for INT0 falling reads nothing. No other register.
    let flags = Register::IntFlagsLo as u8;
    assert_eq!(per(counts.of(Access::ReadReg(flags))), 2.0, "{text}");
    assert_eq!(per(counts.of(Access::WriteReg(flags))), 1.0, "{text}");
    let registers = counts.total() - counts.of(Access::ReadRam) - counts.of(Access::WriteRam);
    assert_eq!(per(registers), 3.0, "{text}");
    // No RAM word is read twice in a wake, and no service container is looked at.
    for (reads, writes) in counts.wake_reads.iter().zip(&counts.wake_writes) {
        let mut sorted = reads.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), reads.len(), "a word read twice: {reads:?}");
        assert!(
            !reads.iter().chain(writes).any(|a| services.contains(a)),
            "a service container touched: {reads:?} {writes:?}"
        );
    }
    // Per drive: the AT header's word 0 and the AT's words but the service info, which the
    // chip's service container takes (status word and the AT list's data: S-0-0011,
    // S-0-0051, P-0-0019 = 5 words of the standard drive).
    let drives = s.drives.len() as f64;
    assert!(per(counts.of(Access::ReadRam)) <= drives * 6.0, "{text}");
    // MDT: each record's changed words (the velocity's low word moves every cycle, the
    // control word does not) and VAL; the whole record (4 words) is never rewritten.
    let writes = per(counts.of(Access::WriteRam));
    assert!(writes <= drives * 2.0 + 1.0, "{text}");
    assert!(writes >= drives + 1.0, "{text}");
    assert!(per(counts.total()) <= 65.0, "{text}");
}

/// Position feedback (S-0-0051) of every drive, from the last AT.
fn positions(s: &Stack8) -> Vec<i64> {
    let m = s.master.borrow();
    s.drives
        .iter()
        .map(|d| {
            let p = m.feedback(*d, Idn::from_raw(51)).expect("S-0-0051");
            i64::from(p as u32 as i32)
        })
        .collect()
}

// 410B §4.2.1 transmit VAL "Set by processor": commands that do not change leave both the
// buffers and VAL alone; the drives still get them, and a new command goes out at once.
#[test]
fn unchanged_commands_write_nothing() {
    let slow = |_: u64, i: u64| 1000 + 100 * i;
    let fast = |_: u64, i: u64| 4000 + 400 * i;
    let mut s = in_phase4(eight_drives());
    s.run_with(20, slow);
    s.reset_counts();
    let before = positions(&s);
    s.run_with(MEASURED_CYCLES, slow);
    let counts = s.counts.borrow();
    let text = per_cycle(&counts, MEASURED_CYCLES);
    assert_eq!(counts.of(Access::WriteRam), 0, "{text}");
    drop(counts);
    let middle = positions(&s);
    s.run_with(MEASURED_CYCLES, fast);
    let after = positions(&s);
    let status = s.master.borrow().status();
    for (i, d) in status.drives.iter().enumerate() {
        assert_eq!(d.ats_missed, 0, "{d:?}");
        // The position moves with the velocity each drive was sent (four times as fast
        // after the change; the drive's own ramp allows some slack).
        let slow_way = middle[i] - before[i];
        let fast_way = after[i] - middle[i];
        assert!(slow_way > 0, "drive {i}: {slow_way}");
        assert!(
            fast_way > 3 * slow_way && fast_way < 5 * slow_way,
            "drive {i}: {slow_way} then {fast_way}"
        );
    }
}
