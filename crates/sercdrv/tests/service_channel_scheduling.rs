//! The master's scheduler and interrupt handling on one chip RAM, without a line: routing of
//! free containers, INT_SC_n bits in 5H (410B §4.1), idle containers (410B §4.2.4).

mod service_channel_support;

use sercdrv::service_channel::{
    ContainerRouter, ContainerSlot, ErrorKind, Request, ServiceChannelMaster, Wiring,
};
use sercon_regs::ram::service::ScMaster;
use sercon_regs::{IntFlagsHi, SerconBus, Variant};
use sercos_wire::address::DriveAddress;
use sercos_wire::idn::Element;
use sercos_wire::time::{Duration, Instant};
use service_channel_support::*;

#[derive(Default)]
struct Recorder(Vec<(u8, u8)>);

impl ContainerRouter for Recorder {
    fn route<B: SerconBus + ?Sized>(
        &mut self,
        _: &mut B,
        slot: &ContainerSlot,
        drive: DriveAddress,
    ) {
        self.0.push((slot.nsv(), drive.get()));
    }
}

fn master_words(bus: &RamBus, at: u16) -> ScMaster {
    let a = usize::from(at);
    ScMaster::from_words([
        bus.ram[a],
        bus.ram[a + 1],
        bus.ram[a + 2],
        bus.ram[a + 3],
        bus.ram[a + 4],
    ])
}

// 410B §4.2: SCPTn = word 2 + n; §4.2.4 M_BUSY holds an idle container; element 0 =
// "service channel not active" (sercos-telegrams.md).
#[test]
fn init_installs_scpt_and_leaves_containers_idle() {
    let v = Variant::Sercon410b;
    let mut bus = RamBus::new(v);
    bus.ram.iter_mut().for_each(|w| *w = 0xFFFF);
    let slot = ContainerSlot::new(v, 3, 0x180, 20).expect("slot");
    let mut client = ServiceChannelMaster::new([(slot, Wiring::Drive(drive(1)))]);
    client.init(&mut bus);
    assert_eq!(bus.ram[5], 0x180, "SCPT3 is word 5");
    let m = master_words(&bus, 0x180);
    assert!(m.m_busy);
    assert_eq!(m.elem_mdt, 0);
    assert!(!m.int_err && !m.int_end_wrbuf && !m.int_cmd);
}

// A container wired to any drive is routed before each transfer; one transfer per
// container; the driver's time limit frees it for the next drive.
#[test]
fn routed_container_serves_drives_one_after_the_other() {
    let v = Variant::Sercon816;
    let mut bus = RamBus::new(v);
    let slot = ContainerSlot::new(v, 6, 0x500, 32).expect("slot");
    let mut client = ServiceChannelMaster::with_router([(slot, Wiring::Any)], Recorder::default());
    client.init(&mut bus);
    client.set_timeout(Some(Duration::from_millis(10)));
    let a = client.submit(drive(4), Request::read_value(ONE_WORD));
    let b = client.submit(drive(9), Request::read(NAMED, Element::Name));
    let t0 = Instant::ZERO;
    assert!(client.poll(&mut bus, t0).is_empty());
    assert_eq!(client.router_mut().0, vec![(6, 4)]);
    assert_eq!((client.running(), client.pending()), (1, 1));
    // The container is set up for the first step: open the IDN (element 1, write), M_BUSY 0.
    let m = master_words(&bus, 0x500);
    assert!(!m.m_busy && m.ls_mdt && m.setend);
    assert_eq!(m.elem_mdt, 1);
    assert_eq!(bus.ram[0x505], ONE_WORD.raw());
    // No line: the time limit ends it, and drive 9 gets the container.
    let t1 = t0.saturating_add(Duration::from_millis(10));
    let done = client.poll(&mut bus, t1);
    assert_eq!(done.len(), 1);
    assert_eq!(done[0].ticket, a);
    assert_eq!(
        done[0].result.clone().expect_err("late").kind,
        ErrorKind::Timeout
    );
    assert_eq!(client.router_mut().0, vec![(6, 4), (6, 9)]);
    let done = client.poll(&mut bus, t1.saturating_add(Duration::from_millis(10)));
    assert_eq!(done[0].ticket, b);
    assert!(client.is_idle());
    // Closed: element 0 and M_BUSY.
    let m = master_words(&bus, 0x500);
    assert!(m.m_busy);
    assert_eq!(m.elem_mdt, 0);
}

// 410B §4.1 5H: INT_SC_n flags, write 1 to clear (ERRATA "410B 4H/5H"); the client clears
// only its own containers' bits.
#[test]
fn interrupt_clears_only_its_own_container_bits() {
    let mut ring = Ring::new(Variant::Sercon816, 1, 16);
    let ticket = ring.client.submit(drive(1), Request::read_value(ONE_WORD));
    // Another driver's flag (container 7, not the client's) and the RMISS bit.
    ring.master.regs[5] |= (1 << 7) | (1 << 8);
    let mut saw_own = false;
    for _ in 0..20 {
        ring.cycle();
        saw_own |= ring.completions.iter().any(|c| c.ticket == ticket);
        assert_eq!(ring.master.regs[5] & 1, 0, "INT_SC_0 cleared");
        assert_eq!(ring.master.regs[5] & 0x180, 0x180, "others kept");
    }
    assert!(saw_own);
    let flags = IntFlagsHi::from_bits_retain(ring.master.regs[5]);
    assert!(flags.contains(IntFlagsHi::INT_SC_7));
}

// 410B §4.2.4 slave table: the slave's container after init (SCPT0, BUSY_AT 0, buffers).
#[test]
fn slave_reports_what_it_served() {
    let mut ring = Ring::new(Variant::Sercon410b, 1, 16);
    ring.transact(1, Request::read_value(ONE_WORD))
        .result
        .expect("read");
    ring.transact(1, Request::write_value(ONE_WORD, vec![5]))
        .result
        .expect("write");
    let _ = ring.transact(1, Request::write_value(ONE_WORD, vec![9999]));
    use sercdrv::service_channel::SlaveEvent::*;
    use sercos_wire::service_error::ServiceError;
    let events = &ring.station(1).events;
    assert_eq!(
        events,
        &vec![
            Opened(ONE_WORD),
            ReadStarted {
                idn: ONE_WORD,
                element: Element::Attribute
            },
            ReadStarted {
                idn: ONE_WORD,
                element: Element::OperationData
            },
            Opened(ONE_WORD),
            Written {
                idn: ONE_WORD,
                element: Element::OperationData
            },
            Opened(ONE_WORD),
            Refused {
                idn: Some(ONE_WORD),
                element: Element::OperationData,
                error: ServiceError::OperationDataAboveMaximum
            },
        ]
    );
    // Element 0 in the MDT after the transfers: the channel is closed.
    ring.cycle();
    assert_eq!(ring.station(1).server.open_idn(), None);
}
