//! Which words of the master's service containers a poll reads (410B §4.2.4: only the
//! control words tell what is going on; spec-notes "Master accesses per cycle").

use sercdrv::service_channel::{ContainerSlot, Request, ServiceChannelMaster, SoftRam, Wiring};
use sercon_regs::ram::service::ScMaster;
use sercon_regs::{SerconBus, Variant};
use sercos_wire::address::DriveAddress;
use sercos_wire::idn::Idn;
use sercos_wire::time::Instant;

/// A soft RAM that notes the word addresses read and written.
struct Counting {
    ram: SoftRam,
    reads: Vec<u16>,
    writes: Vec<u16>,
}

impl Counting {
    fn clear(&mut self) {
        self.reads.clear();
        self.writes.clear();
    }
}

impl SerconBus for Counting {
    fn read_register(&mut self, address: u8) -> u16 {
        self.ram.read_register(address)
    }

    fn write_register(&mut self, address: u8, value: u16) {
        self.ram.write_register(address, value)
    }

    fn read_ram(&mut self, address: u16) -> u16 {
        self.reads.push(address);
        self.ram.read_ram(address)
    }

    fn write_ram(&mut self, address: u16, value: u16) {
        self.writes.push(address);
        self.ram.write_ram(address, value)
    }
}

const VARIANT: Variant = Variant::Sercon816;
const FIRST: u16 = 0x100;
const SECOND: u16 = 0x140;

fn drive(n: u8) -> DriveAddress {
    DriveAddress::new(n).expect("a drive address")
}

fn setup() -> (ServiceChannelMaster, Counting) {
    let slots = [(0, FIRST, 1), (1, SECOND, 2)].map(|(nsv, address, d)| {
        let slot = ContainerSlot::new(VARIANT, nsv, address, 16).expect("a slot");
        (slot, Wiring::Drive(drive(d)))
    });
    let mut sc = ServiceChannelMaster::new(slots);
    let mut bus = Counting {
        ram: SoftRam::new(VARIANT),
        reads: Vec::new(),
        writes: Vec::new(),
    };
    sc.init(&mut bus);
    bus.clear();
    (sc, bus)
}

fn master_words(bus: &mut Counting, start: u16) -> ScMaster {
    let words = [0u16, 1, 2, 3, 4].map(|i| bus.ram.read_ram(start + i));
    ScMaster::from_words(words)
}

// 410B §4.2.4 INT_CMD (word 4 bit 12): with the watch on, an idle container costs one read
// (word 4); a change is reported once and cleared by writing word 4 alone.
#[test]
fn idle_containers_cost_word_4_or_nothing() {
    let (mut sc, mut bus) = setup();
    let now = Instant::ZERO;
    assert!(sc.poll(&mut bus, now).is_empty());
    assert_eq!(bus.reads, vec![FIRST + 4, SECOND + 4]);
    assert!(bus.writes.is_empty());
    // The chip notes the slave's command change bit in the second container.
    let mut m = master_words(&mut bus, SECOND);
    m.int_cmd = true;
    bus.ram.write_ram(SECOND + 4, m.to_words()[4]);
    bus.clear();
    sc.poll(&mut bus, now);
    assert_eq!(sc.take_command_changes(), vec![drive(2)]);
    assert_eq!(bus.writes, vec![SECOND + 4]);
    assert!(!master_words(&mut bus, SECOND).int_cmd);
    // Watch off: no access at all, and the bit stays for the chip's container.
    sc.set_watch_commands(false);
    let mut m = master_words(&mut bus, FIRST);
    m.int_cmd = true;
    bus.ram.write_ram(FIRST + 4, m.to_words()[4]);
    bus.clear();
    sc.poll(&mut bus, now);
    assert!(bus.reads.is_empty() && bus.writes.is_empty());
    assert!(sc.take_command_changes().is_empty());
}

// 410B §4.2.4 M_BUSY "Service container waits for interaction of microprocessor": a running
// transfer is looked at through word 0 until the chip hands it to the host.
#[test]
fn running_container_reads_word_0_until_m_busy() {
    let (mut sc, mut bus) = setup();
    sc.set_watch_commands(false);
    let now = Instant::ZERO;
    sc.submit(drive(1), Request::read_value(Idn::from_raw(3)));
    sc.poll(&mut bus, now);
    assert_eq!(sc.running(), 1);
    assert!(
        !master_words(&mut bus, FIRST).m_busy,
        "the step is the chip's"
    );
    bus.clear();
    sc.poll(&mut bus, now);
    assert_eq!(bus.reads, vec![FIRST]);
    assert!(bus.writes.is_empty());
    // The chip raises M_BUSY (here with no reason the transfer knows): all five words.
    let mut m = master_words(&mut bus, FIRST);
    m.m_busy = true;
    bus.ram.write_ram(FIRST, m.to_words()[0]);
    bus.clear();
    sc.poll(&mut bus, now);
    assert_eq!(
        bus.reads,
        vec![FIRST, FIRST + 1, FIRST + 2, FIRST + 3, FIRST + 4]
    );
    assert_eq!(sc.running(), 1);
}
