//! Property tests: nothing a bus read can return, and no parameter values the master can
//! write, make the slave driver panic ("No panics from input", 410B §4.1 registers and §4.2
//! RAM structures as the driver reads them).

mod chaos_bus;

use chaos_bus::{ChaosBus, Versioned};
use proptest::prelude::*;
use sercdrv::idn_store::IdnStore;
use sercdrv::ram_layout::{self, PhaseGroup, RamLayoutRequest, Role};
use sercdrv::slave::{
    AT_START, CYCLE_TIME, CyclicLengths, MDT_LENGTH, MDT_POSITION, MDT_START, SlaveConfig,
    SlaveDriver, cyclic_timing,
};
use sercon_regs::Variant;
use sercon_regs::host::{HostProgram, Wake};
use sercos_drive::database::IdnDatabase;
use sercos_drive::drive::EmulatedDrive;
use sercos_wire::idn::{Element, Idn};
use sercos_wire::service_error::ServiceError;
use sercos_wire::telegram::CommunicationPhase;
use sercos_wire::time::{Duration, Instant};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(64)))]

    // 410B §4.1: any flags, PHASREC, VERSION; §4.2: any RAM words — the driver never panics
    // and never leaves a phase 0-4.
    #[test]
    fn arbitrary_bus_contents_never_panic_the_slave(seed in 1u64.., wakes in 1usize..200, v816 in any::<bool>()) {
        let variant = if v816 { Variant::Sercon816 } else { Variant::Sercon410b };
        let mut bus = ChaosBus::new(seed, variant);
        let drive = EmulatedDrive::new(IdnDatabase::standard(), Instant::ZERO);
        let mut slave = SlaveDriver::new(SlaveConfig::new(variant, 5), drive).expect("config");
        let mut now = Instant::ZERO;
        slave.wake(&mut bus, now, Wake::Start);
        for _ in 0..wakes {
            now += Duration::from_micros(250);
            slave.wake(&mut bus, now, Wake::Interrupt { int0: true, int1: false });
        }
        prop_assert!(slave.phase().number() <= 4);
    }

    // The same with the VERSION register answering correctly, so the driver gets past
    // initialisation and serves arbitrary interrupts, PHASREC and RAM.
    #[test]
    fn arbitrary_interrupts_and_ram_after_a_good_start(seed in 1u64.., wakes in 1usize..300) {
        // ERRATA "0H VERSION": 0010H on the SERCON816.
        let mut bus = Versioned(ChaosBus::new(seed, Variant::Sercon816), Variant::Sercon816);
        let drive = EmulatedDrive::new(IdnDatabase::standard(), Instant::ZERO);
        let mut slave = SlaveDriver::new(SlaveConfig::new(Variant::Sercon816, 5), drive).expect("config");
        let mut now = Instant::ZERO;
        slave.wake(&mut bus, now, Wake::Start);
        prop_assert!(slave.failure().is_none());
        for _ in 0..wakes {
            now += Duration::from_micros(250);
            slave.wake(&mut bus, now, Wake::Interrupt { int0: true, int1: false });
        }
        // Without S-0-0127 executed the slave never reaches phase 3 or 4.
        prop_assert!(!slave.phase().is_cyclic(), "{:?}", slave.phase());
    }

    // sercos-facts.md S-0-0002/6/9/10/89: whatever the master wrote, the slave's phase 3-4
    // timing is either refused with an error or lays out (or is refused by the layout).
    #[test]
    fn arbitrary_cyclic_parameters_never_panic(
        values in proptest::array::uniform5(any::<u16>()),
        mdt in 0u16..3000, at in 0u16..3000, v816 in any::<bool>()
    ) {
        let variant = if v816 { Variant::Sercon816 } else { Variant::Sercon410b };
        let store = Numbers([
            (CYCLE_TIME, values[0]), (AT_START, values[1]), (MDT_POSITION, values[2]),
            (MDT_LENGTH, values[3]), (MDT_START, values[4]),
        ]);
        let config = SlaveConfig::new(variant, 9);
        let lengths = CyclicLengths { mdt_data_bytes: mdt, at_data_bytes: at };
        if let Ok(timing) = cyclic_timing(&config, &store, lengths) {
            let mut req = RamLayoutRequest::new(variant, Role::Slave { address: 9 }, &timing);
            req.blocks = [Some(PhaseGroup::NonCyclic), Some(PhaseGroup::Cyclic)];
            let _ = ram_layout::build(&req);
            prop_assert!(timing.drives[0].at.start_us < timing.mdt.start_us);
        }
    }
}

/// An IDN store of five numbers.
struct Numbers([(Idn, u16); 5]);

impl IdnStore for Numbers {
    fn read_element(&self, idn: Idn, _element: Element) -> Result<Vec<u16>, ServiceError> {
        self.0
            .iter()
            .find(|(i, _)| *i == idn)
            .map(|(_, v)| vec![*v])
            .ok_or(ServiceError::IdnNotPresent)
    }
    fn write_element(&mut self, _: Idn, _: Element, _: &[u16]) -> Result<(), ServiceError> {
        Ok(())
    }
    fn set_phase(&mut self, _phase: CommunicationPhase) {}
}
