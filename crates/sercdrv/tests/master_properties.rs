//! Property tests: nothing a bus read can return makes the master driver panic ("No panics
//! from input"), nor, on a real ring, the drives' slave driver. What the master reads of its chip (410B §4.1 flags, status and ring delay,
//! §4.2 RAM: the drives' ATs, the service containers' control and status words) comes in
//! the end from the line, that is from drives it does not control; a chaotic chip stands for
//! the worst of them.

mod chaos_bus;
mod master_support;

use chaos_bus::{ChaosBus, Versioned};
use proptest::prelude::*;
use sercdrv::master::{Master, MasterConfig, Progress, TELEGRAM_TYPE_CONFIGURED};
use sercon_regs::host::{HostProgram, Wake};
use sercon_regs::{SerconBus, Variant};
use sercos_wire::address::DriveAddress;
use sercos_wire::time::{BitRate, Duration, Instant};

/// A master of `variant` for drives 1..=`drives` at a rate the variant has (410B §4.1 1H:
/// 2 or 4 Mbit/s on the 410B) and telegram type `telegram_type` (S-0-0015).
fn master(variant: Variant, drives: u8, telegram_type: u16) -> Master {
    let rate = match variant {
        Variant::Sercon816 => BitRate::Mbit16,
        Variant::Sercon410b => BitRate::Mbit4,
    };
    let addresses = (1..=drives).filter_map(DriveAddress::new).collect();
    let mut cfg = MasterConfig::new(variant, rate, 1000, addresses);
    assert!(cfg.set_telegram_type(telegram_type));
    Master::new(cfg).expect("a valid configuration")
}

/// Runs `m` on `bus` for `wakes` wakes chosen by `kinds` (interrupts with INT0 or INT1,
/// deadlines, a power-on now and then), 250 µs apart, and checks what it reports.
fn run(m: &mut Master, bus: &mut dyn SerconBus, kinds: &[u8]) -> Result<(), TestCaseError> {
    let mut now = Instant::ZERO;
    m.wake(bus, now, Wake::Start);
    for k in kinds {
        now += Duration::from_micros(250);
        let why = match k % 16 {
            0 => Wake::PowerOn,
            1..=5 => Wake::Deadline,
            6 => Wake::Interrupt {
                int0: false,
                int1: true,
            },
            _ => Wake::Interrupt {
                int0: true,
                int1: false,
            },
        };
        // The next deadline, if any, lies ahead of the wake (or the master asks for none).
        if let Some(next) = m.wake(bus, now, why) {
            prop_assert!(next >= now, "deadline {next:?} before {now:?}");
        }
        // sercos-telegrams.md: phases 0-4.
        prop_assert!(m.phase() <= 4, "phase {}", m.phase());
        let status = m.status();
        prop_assert_eq!(status.drives.len(), m.config().drives.len());
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(64)))]

    // 410B §4.1: any flags, status, VERSION, TCYCDEL; §4.2: any RAM words — the master never
    // panics, never leaves phases 0-4 and never asks to be woken in the past.
    #[test]
    fn arbitrary_bus_contents_never_panic_the_master(
        seed in 1u64..,
        kinds in proptest::collection::vec(any::<u8>(), 1..200),
        v816 in any::<bool>(),
        drives in 1u8..=8,
    ) {
        let variant = if v816 { Variant::Sercon816 } else { Variant::Sercon410b };
        let mut m = master(variant, drives, TELEGRAM_TYPE_CONFIGURED);
        let mut bus = ChaosBus::new(seed, variant);
        run(&mut m, &mut bus, &kinds)?;
    }

    // The same with the VERSION register answering as the chip does (ERRATA "0H VERSION"),
    // so that the master gets past its start and meets arbitrary flags, ring delay, ATs and
    // service containers in every phase it reaches, with every telegram type (S-0-0015).
    #[test]
    fn arbitrary_flags_and_ram_after_a_good_start_never_panic_the_master(
        seed in 1u64..,
        kinds in proptest::collection::vec(any::<u8>(), 1..300),
        v816 in any::<bool>(),
        drives in 1u8..=8,
        telegram_type in 0u16..=7,
    ) {
        let variant = if v816 { Variant::Sercon816 } else { Variant::Sercon410b };
        let mut m = master(variant, drives, telegram_type);
        let mut bus = Versioned(ChaosBus::new(seed, variant), variant);
        run(&mut m, &mut bus, &kinds)?;
        // Past its start it is not left idle: it brings the ring up or says why it stopped.
        prop_assert!(m.progress() != Progress::Idle);
    }
}

/// A host between the master driver and its chip that replaces a read now and then by a word
/// of the stream (`chaos`): the driver meets garbage at any point of a real phase-up, in
/// words a faulty chip or drive could leave (its writes go through).
struct Garbling {
    inner: Box<dyn HostProgram>,
    chaos: ChaosBus,
    /// A read is garbled when the stream's next word is below this (out of 65 536).
    below: u16,
}

struct GarblingBus<'a> {
    bus: &'a mut dyn SerconBus,
    chaos: &'a mut ChaosBus,
    below: u16,
}

impl GarblingBus<'_> {
    fn garble(&mut self, real: u16) -> u16 {
        if self.chaos.next() < self.below {
            self.chaos.next()
        } else {
            real
        }
    }
}

impl SerconBus for GarblingBus<'_> {
    fn read_register(&mut self, address: u8) -> u16 {
        let v = self.bus.read_register(address);
        self.garble(v)
    }
    fn write_register(&mut self, address: u8, value: u16) {
        self.bus.write_register(address, value);
    }
    fn read_ram(&mut self, address: u16) -> u16 {
        let v = self.bus.read_ram(address);
        self.garble(v)
    }
    fn write_ram(&mut self, address: u16, value: u16) {
        self.bus.write_ram(address, value);
    }
}

impl HostProgram for Garbling {
    fn wake(&mut self, bus: &mut dyn SerconBus, now: Instant, why: Wake) -> Option<Instant> {
        let mut garbling = GarblingBus {
            bus,
            chaos: &mut self.chaos,
            below: self.below,
        };
        self.inner.wake(&mut garbling, now, why)
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(6)))]

    // A real ring of a master and two emulated drives, the reads of one node's driver (the
    // master's, or drive 1's) garbled one in 16 to one in 4096: wherever the garbage lands
    // (registers, ATs, MDTs, service containers, in any phase), no driver panics, the
    // master never leaves phases 0-4, and the ring runs on.
    #[test]
    fn garbage_read_anywhere_in_a_phase_up_never_panics_a_driver(
        seed in 1u64..,
        one_in in prop_oneof![Just(16u32), Just(256), Just(4096)],
        v816 in any::<bool>(),
        garbled in 0usize..=1,
    ) {
        let variant = if v816 { Variant::Sercon816 } else { Variant::Sercon410b };
        let rate = match variant {
            Variant::Sercon816 => BitRate::Mbit16,
            Variant::Sercon410b => BitRate::Mbit4,
        };
        let addresses = (1..=2).filter_map(DriveAddress::new).collect();
        let cfg = MasterConfig::new(variant, rate, 1000, addresses);
        let below = u16::try_from(65_536 / one_in).unwrap_or(u16::MAX);
        let mut ring = master_support::ring_wrapped(
            cfg,
            master_support::standard_drives(2),
            Vec::new(),
            sercos_sim::Delivery::Fast,
            |node, inner| {
                if node != garbled {
                    return inner;
                }
                Box::new(Garbling {
                    inner,
                    chaos: ChaosBus::new(seed, variant),
                    below,
                })
            },
        );
        // A phase-up of two drives takes some 600 cycles of 1 ms.
        for _ in 0..8 {
            ring.run_cycles(100);
            let m = ring.master.borrow();
            prop_assert!(m.phase() <= 4, "phase {}", m.phase());
            for d in &ring.drives {
                let phase = d.borrow().phase().number();
                prop_assert!(phase <= 4, "a drive in phase {phase}");
            }
        }
    }
}
