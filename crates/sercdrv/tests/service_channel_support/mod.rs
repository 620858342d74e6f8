//! A master chip RAM and slave chip RAMs joined record by record through the sercon-model
//! service-container entry points (`on_transmit`, `on_receive`, `on_cycle`), standing in for
//! two chips and the line (410B §4.2.4; ERRATA "service info in a container"). Each cycle the
//! master's MDT record goes to the slave and the slave's AT record back; then the slave's
//! server and the master's client react to their INT_SC_n bits (5H, 410B §4.1).
#![allow(dead_code)]

use std::collections::BTreeMap;

use sercdrv::idn_store::IdnStore;
use sercdrv::service_channel::{
    Completion, ContainerSlot, Request, ServiceChannelMaster, ServiceChannelSlave, SlaveEvent,
    Ticket, Wiring,
};
use sercon_model::service_container::{ScMode, on_cycle, on_receive, on_transmit};
use sercon_regs::ram::service::NInfo;
use sercon_regs::{SerconBus, Variant};
use sercos_wire::address::DriveAddress;
use sercos_wire::attribute::{Attribute, DataLength, DisplayFormat};
use sercos_wire::idn::{Element, Idn};
use sercos_wire::service_error::{DescriptiveElement, ElementFault, ServiceError};
use sercos_wire::telegram::CommunicationPhase;
use sercos_wire::time::{Duration, Instant};

/// 5H, the interrupt flags INT_SC_0–7 (410B §4.1; write 1 to clear, ERRATA).
const INT_HI: u8 = 0x05;

/// A chip's RAM and registers behind the host bus.
#[derive(Debug, Clone)]
pub struct RamBus {
    pub ram: Vec<u16>,
    pub regs: [u16; 64],
}

impl RamBus {
    pub fn new(variant: Variant) -> RamBus {
        RamBus {
            ram: vec![0; usize::from(variant.ram_words())],
            regs: [0; 64],
        }
    }
}

impl SerconBus for RamBus {
    fn read_register(&mut self, address: u8) -> u16 {
        self.regs.get(usize::from(address)).copied().unwrap_or(0)
    }
    fn write_register(&mut self, address: u8, value: u16) {
        if let Some(r) = self.regs.get_mut(usize::from(address)) {
            if address == INT_HI {
                *r &= !value;
            } else {
                *r = value;
            }
        }
    }
    fn read_ram(&mut self, address: u16) -> u16 {
        self.ram.get(usize::from(address)).copied().unwrap_or(0)
    }
    fn write_ram(&mut self, address: u16, value: u16) {
        if let Some(w) = self.ram.get_mut(usize::from(address)) {
            *w = value;
        }
    }
}

/// One parameter of the test store.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Param {
    pub name: Vec<u8>,
    pub unit: Vec<u8>,
    pub attribute: Attribute,
    pub min: Option<u16>,
    pub max: Option<u16>,
    pub value: Vec<u16>,
}

/// Text as variable-length words: current length, maximum length, bytes low first
/// (sercos-facts.md, "Variable-length data").
pub fn text_words(text: &[u8]) -> Vec<u16> {
    let len = u16::try_from(text.len()).unwrap_or(u16::MAX);
    let mut words = vec![len, len];
    words.extend(
        text.chunks(2)
            .map(|c| u16::from(c[0]) | u16::from(c.get(1).copied().unwrap_or(0)) << 8),
    );
    words
}

/// A small IDN store with the checks of sercos-facts.md "Service channel errors".
#[derive(Debug, Clone, Default)]
pub struct TestStore {
    pub params: BTreeMap<Idn, Param>,
    /// Procedure command status words (bit 0 set, 1 enabled, 2 executed).
    pub commands: BTreeMap<Idn, u16>,
    pub writes: Vec<(Idn, Element, Vec<u16>)>,
}

pub const ONE_WORD: Idn = Idn::from_raw(0x0024); // S-0-0036
pub const NAMED: Idn = Idn::from_raw(0x8001); // P-0-0001
pub const AT_LIST: Idn = Idn::AT_CONFIGURATION_LIST; // S-0-0016
pub const TWO_WORDS: Idn = Idn::from_raw(0x0033); // S-0-0051
pub const COMMAND: Idn = Idn::from_raw(99); // S-0-0099
pub const NAME60: &[u8; 60] = b"Spindle drive 7, retrofit 2024, SERCON816 model, axis X-left";

impl TestStore {
    pub fn standard() -> TestStore {
        let mut store = TestStore::default();
        let word = Attribute::new(DataLength::TwoBytes, DisplayFormat::UnsignedDecimal);
        store.params.insert(
            ONE_WORD,
            Param {
                name: b"Velocity command value".to_vec(),
                unit: b"rpm".to_vec(),
                attribute: word,
                min: Some(0),
                max: Some(6000),
                value: vec![100],
            },
        );
        store.params.insert(
            NAMED,
            Param {
                name: NAME60.to_vec(),
                unit: Vec::new(),
                attribute: word,
                min: None,
                max: None,
                value: vec![7],
            },
        );
        store.params.insert(
            AT_LIST,
            Param {
                name: b"Configuration list of the AT".to_vec(),
                unit: Vec::new(),
                attribute: Attribute::new(DataLength::VariableWords, DisplayFormat::Idn),
                min: None,
                max: None,
                value: vec![0, 8],
            },
        );
        store.params.insert(
            TWO_WORDS,
            Param {
                name: b"Position feedback value 1".to_vec(),
                unit: b"deg".to_vec(),
                attribute: Attribute::new(DataLength::FourBytes, DisplayFormat::SignedDecimal),
                min: None,
                max: None,
                value: vec![0x5678, 0x1234],
            },
        );
        store.params.insert(
            COMMAND,
            Param {
                name: b"Reset class 1 diagnostic".to_vec(),
                unit: Vec::new(),
                attribute: word.with_procedure_command(true),
                min: None,
                max: None,
                value: vec![0],
            },
        );
        store
    }

    /// Whether a command has ended and not been cancelled (status word bit 5 in the AT).
    pub fn command_change(&self) -> bool {
        self.commands.values().any(|s| s & 4 != 0)
    }
}

impl IdnStore for TestStore {
    fn read_element(&self, idn: Idn, element: Element) -> Result<Vec<u16>, ServiceError> {
        let p = self.params.get(&idn).ok_or(ServiceError::IdnNotPresent)?;
        let absent = |e| ServiceError::Element(e, ElementFault::NotPresent);
        match element {
            Element::ServiceChannelClosed => Err(ServiceError::ServiceChannelNotOpen),
            Element::Idn => Ok(vec![idn.raw()]),
            Element::Name => Ok(text_words(&p.name)),
            Element::Attribute => Ok(p.attribute.to_words().to_vec()),
            Element::Unit => Ok(text_words(&p.unit)),
            Element::Minimum => p
                .min
                .map(|v| vec![v])
                .ok_or(absent(DescriptiveElement::Minimum)),
            Element::Maximum => p
                .max
                .map(|v| vec![v])
                .ok_or(absent(DescriptiveElement::Maximum)),
            Element::OperationData if p.attribute.is_procedure_command() => {
                Ok(vec![self.commands.get(&idn).copied().unwrap_or(0)])
            }
            Element::OperationData => Ok(p.value.clone()),
        }
    }

    fn write_element(
        &mut self,
        idn: Idn,
        element: Element,
        words: &[u16],
    ) -> Result<(), ServiceError> {
        let p = self
            .params
            .get_mut(&idn)
            .ok_or(ServiceError::IdnNotPresent)?;
        match element {
            Element::ServiceChannelClosed => return Err(ServiceError::InvalidAccessToClosing),
            Element::Idn => return Err(ServiceError::InvalidAccessToElement1),
            Element::OperationData => {}
            other => {
                let e = DescriptiveElement::from_number(other.bits())
                    .ok_or(ServiceError::InvalidAccessToElement1)?;
                return Err(ServiceError::Element(e, ElementFault::CannotBeChanged));
            }
        }
        if let Some(n) = p.attribute.fixed_words() {
            if words.len() < n {
                return Err(ServiceError::OperationDataTooShort);
            }
            if words.len() > n {
                return Err(ServiceError::OperationDataTooLong);
            }
            let v = words.first().copied().unwrap_or(0);
            if p.min.is_some_and(|m| v < m) {
                return Err(ServiceError::OperationDataBelowMinimum);
            }
            if p.max.is_some_and(|m| v > m) {
                return Err(ServiceError::OperationDataAboveMaximum);
            }
        } else if words.len() < 2 {
            return Err(ServiceError::OperationDataTooShort);
        }
        if p.attribute.is_procedure_command() {
            match words.first() {
                // Set and enable: this drive executes at once (0007H).
                Some(3) => self.commands.insert(idn, 0x0007),
                Some(0) => self.commands.remove(&idn),
                _ => return Err(ServiceError::OperationDataInvalid),
            };
        } else {
            p.value = words.to_vec();
        }
        self.writes.push((idn, element, words.to_vec()));
        Ok(())
    }

    fn set_phase(&mut self, _phase: CommunicationPhase) {}
}

/// A drive: its chip, its server and its store.
pub struct Station {
    pub address: DriveAddress,
    pub bus: RamBus,
    pub server: ServiceChannelSlave,
    pub store: TestStore,
    pub nsv: u8,
    /// The drive sends no AT (gone from the ring).
    pub silent: bool,
    /// Its microprocessor does not react (BUSY stays).
    pub asleep: bool,
    pub events: Vec<SlaveEvent>,
}

impl Station {
    /// Drive `address` with its container 0 at 200H, `buffer` words per buffer and `ninfo`
    /// info words per record.
    pub fn new(variant: Variant, address: DriveAddress, buffer: u16, ninfo: NInfo) -> Station {
        let sslot = ContainerSlot::new(variant, 0, 0x200, buffer)
            .expect("slot")
            .with_ninfo(ninfo);
        let mut bus = RamBus::new(variant);
        let mut server = ServiceChannelSlave::new(sslot);
        server.init(&mut bus);
        Station {
            address,
            bus,
            server,
            store: TestStore::standard(),
            nsv: 0,
            silent: false,
            asleep: false,
            events: Vec::new(),
        }
    }

    /// The drive's chip takes `mdt` (MDT control word and info words) into its container
    /// and gives its AT record (status word and info words), `None` when it is silent
    /// (410B §4.2.4 slave table).
    pub fn exchange(&mut self, variant: Variant, mdt: &[u16]) -> Option<Vec<u16>> {
        let out = on_receive(
            &mut self.bus.ram,
            variant,
            self.nsv,
            ScMode::Slave,
            mdt,
            true,
        );
        raise(&mut self.bus, self.nsv, out.int_sc);
        let mut at = vec![0u16; mdt.len()];
        at[0] = 0xC000;
        on_transmit(&mut self.bus.ram, variant, self.nsv, ScMode::Slave, &mut at);
        (!self.silent).then_some(at)
    }

    /// The drive's processor reacts to its INT_SC_n bits (unless asleep).
    pub fn react(&mut self) {
        if self.asleep {
            return;
        }
        let flags = sercon_regs::IntFlagsHi::from_bits_retain(self.bus.regs[5]);
        let events = self
            .server
            .on_interrupt(&mut self.bus, &mut self.store, flags);
        self.events.extend(events);
        let change = self.store.command_change();
        self.server.set_command_change(&mut self.bus, change);
    }
}

/// One master chip and its drives, one master container per drive.
pub struct Ring {
    pub variant: Variant,
    pub master: RamBus,
    pub client: ServiceChannelMaster,
    pub stations: Vec<Station>,
    /// Master container NSV of each station.
    pub master_nsv: Vec<u8>,
    pub hs_timeout: u8,
    pub busy_timeout: u8,
    pub now: Instant,
    pub cycle_time: Duration,
    pub cycles: u64,
    pub completions: Vec<Completion>,
    /// Most containers busy at once.
    pub max_running: usize,
    /// Words per record: the control or status word and NINFO info words.
    pub record_words: usize,
}

pub fn drive(n: u8) -> DriveAddress {
    DriveAddress::new(n).expect("1-254")
}

impl Ring {
    /// `drives` drives; master container n (at 100H + 100H·n) serves drive n + 1; each
    /// slave's container 0 sits at 200H. `buffer` words per buffer.
    pub fn new(variant: Variant, drives: u8, buffer: u16) -> Ring {
        Ring::with_ninfo(variant, drives, buffer, 1)
    }

    /// As [`Ring::new`] with `ninfo` info words per record on both sides.
    pub fn with_ninfo(variant: Variant, drives: u8, buffer: u16, ninfo: u8) -> Ring {
        let ninfo = NInfo::from_count(ninfo).expect("1-4");
        let mut slots = Vec::new();
        let mut stations = Vec::new();
        let mut master_nsv = Vec::new();
        for i in 0..drives {
            let address = drive(i + 1);
            let nsv = i;
            let base = 0x040 + 0x70 * u16::from(i);
            let slot = ContainerSlot::new(variant, nsv, base, buffer.min(0x6B))
                .expect("slot")
                .with_ninfo(ninfo);
            slots.push((slot, Wiring::Drive(address)));
            master_nsv.push(nsv);
            stations.push(Station::new(variant, address, buffer, ninfo));
        }
        let mut master = RamBus::new(variant);
        let mut client = ServiceChannelMaster::new(slots);
        client.init(&mut master);
        Ring {
            variant,
            master,
            client,
            stations,
            master_nsv,
            hs_timeout: 0,
            busy_timeout: 0,
            now: Instant::ZERO,
            cycle_time: Duration::from_millis(2),
            cycles: 0,
            completions: Vec::new(),
            max_running: 0,
            record_words: 1 + usize::from(ninfo.count()),
        }
    }

    /// One communication cycle: records exchanged, then the hosts react.
    pub fn cycle(&mut self) {
        let v = self.variant;
        let words = self.record_words;
        for (station, &mnsv) in self.stations.iter_mut().zip(&self.master_nsv) {
            let mut mdt = vec![0u16; words];
            mdt[0] = 0xE000;
            let out = on_transmit(&mut self.master.ram, v, mnsv, ScMode::Master, &mut mdt);
            raise(&mut self.master, mnsv, out.int_sc);
            if let Some(at) = station.exchange(v, &mdt) {
                let out = on_receive(&mut self.master.ram, v, mnsv, ScMode::Master, &at, true);
                raise(&mut self.master, mnsv, out.int_sc);
            }
            let out = on_cycle(
                &mut self.master.ram,
                v,
                mnsv,
                ScMode::Master,
                self.hs_timeout,
                self.busy_timeout,
            );
            raise(&mut self.master, mnsv, out.int_sc);
        }
        for station in &mut self.stations {
            station.react();
        }
        let flags = sercon_regs::IntFlagsHi::from_bits_retain(self.master.regs[5]);
        let done = self.client.on_interrupt(&mut self.master, flags, self.now);
        self.max_running = self.max_running.max(self.client.running());
        self.completions.extend(done);
        self.now = self.now.saturating_add(self.cycle_time);
        self.cycles += 1;
    }

    /// Runs cycles until `ticket` completes (at most `limit`); returns it.
    pub fn run_until(&mut self, ticket: Ticket, limit: u64) -> Completion {
        for _ in 0..limit {
            if let Some(i) = self.completions.iter().position(|c| c.ticket == ticket) {
                return self.completions.remove(i);
            }
            self.cycle();
        }
        panic!("ticket {ticket:?} not done after {limit} cycles");
    }

    /// Submits `request` to drive `n` and runs it to completion.
    pub fn transact(&mut self, n: u8, request: Request) -> Completion {
        let ticket = self.client.submit(drive(n), request);
        self.run_until(ticket, 2000)
    }

    pub fn station(&mut self, n: u8) -> &mut Station {
        &mut self.stations[usize::from(n - 1)]
    }
}

fn raise(bus: &mut RamBus, nsv: u8, int_sc: bool) {
    if int_sc {
        // 410B §4.1 5H: INT_SC_n.
        bus.regs[5] |= 1 << nsv;
    }
}
