//! The master client against the emulated drive's IDN database (`sercos_drive::IdnDatabase`)
//! served by the slave server, over two chip RAMs linked through the sercon-model service
//! containers (410B §4.2.4; sercos-facts.md "Service channel errors", "Procedure commands").

mod service_channel_support;

use sercdrv::idn_store::IdnStore;
use sercdrv::service_channel::{
    CommandStatus, Completion, ContainerSlot, ErrorKind, Request, ServiceChannelMaster,
    ServiceChannelSlave, Wiring,
};
use sercon_model::service_container::{ScMode, on_cycle, on_receive, on_transmit};
use sercon_regs::{IntFlagsHi, Variant};
use sercos_drive::database::IdnDatabase;
use sercos_drive::parameter::Parameter;
use sercos_wire::attribute::{Attribute, DataLength, DisplayFormat, Value};
use sercos_wire::idn::{Element, Idn};
use sercos_wire::service_error::ServiceError;
use sercos_wire::time::{Duration, Instant};
use service_channel_support::{RamBus, drive};

const LIMITED: Idn = Idn::from_raw(0x8064); // P-0-0100

struct Pair {
    master: RamBus,
    slave: RamBus,
    client: ServiceChannelMaster,
    server: ServiceChannelSlave,
    db: IdnDatabase,
    now: Instant,
}

impl Pair {
    fn new() -> Pair {
        let v = Variant::Sercon816;
        let mslot = ContainerSlot::new(v, 1, 0x300, 64).expect("slot");
        let sslot = ContainerSlot::new(v, 4, 0x600, 64).expect("slot");
        let mut master = RamBus::new(v);
        let mut slave = RamBus::new(v);
        let mut client = ServiceChannelMaster::new([(mslot, Wiring::Drive(drive(3)))]);
        client.init(&mut master);
        client.set_timeout(Some(Duration::from_secs(2)));
        let mut server = ServiceChannelSlave::new(sslot);
        server.init(&mut slave);
        let mut db = IdnDatabase::standard();
        let attribute = Attribute::new(DataLength::TwoBytes, DisplayFormat::UnsignedDecimal);
        let mut p = Parameter::new(
            LIMITED,
            "Limited value",
            attribute,
            "",
            0,
            &Value::Unsigned(5),
        )
        .expect("parameter");
        p.max = Some(Value::Unsigned(6000));
        db.insert(p);
        Pair {
            master,
            slave,
            client,
            server,
            db,
            now: Instant::ZERO,
        }
    }

    fn cycle(&mut self) -> Vec<Completion> {
        let v = Variant::Sercon816;
        let mut mdt = [0xE000u16, 0];
        let o = on_transmit(&mut self.master.ram, v, 1, ScMode::Master, &mut mdt);
        self.master.regs[5] |= u16::from(o.int_sc) << 1;
        let o = on_receive(&mut self.slave.ram, v, 4, ScMode::Slave, &mdt, true);
        self.slave.regs[5] |= u16::from(o.int_sc) << 4;
        let mut at = [0xC000u16, 0];
        on_transmit(&mut self.slave.ram, v, 4, ScMode::Slave, &mut at);
        let o = on_receive(&mut self.master.ram, v, 1, ScMode::Master, &at, true);
        self.master.regs[5] |= u16::from(o.int_sc) << 1;
        on_cycle(&mut self.master.ram, v, 1, ScMode::Master, 50, 50);
        let flags = IntFlagsHi::from_bits_retain(self.slave.regs[5]);
        self.server
            .on_interrupt(&mut self.slave, &mut self.db, flags);
        let change = self.db.command_change();
        self.server.set_command_change(&mut self.slave, change);
        let flags = IntFlagsHi::from_bits_retain(self.master.regs[5]);
        let done = self.client.on_interrupt(&mut self.master, flags, self.now);
        self.now = self.now.saturating_add(Duration::from_millis(2));
        done
    }

    fn transact(&mut self, request: Request) -> Completion {
        let ticket = self.client.submit(drive(3), request);
        for _ in 0..1000 {
            if let Some(done) = self.cycle().into_iter().find(|c| c.ticket == ticket) {
                return done;
            }
        }
        panic!("no completion");
    }
}

// sercos-facts.md "IDNs" (name, attribute, operation data) read from the emulated drive.
#[test]
fn reads_the_emulated_drives_parameters() {
    let mut pair = Pair::new();
    let cycle_time = Idn::COMMUNICATION_CYCLE_TIME;
    let name = pair.transact(Request::read(cycle_time, Element::Name));
    let expected = pair
        .db
        .read_element(cycle_time, Element::Name)
        .expect("name");
    assert_eq!(name.result.expect("name").words, expected);
    let value = pair.transact(Request::read_value(cycle_time));
    let response = value.result.expect("value");
    let attribute = response.attribute.expect("attribute first");
    assert_eq!(
        attribute
            .decode(&response.words)
            .ok()
            .and_then(|v| v.as_i128()),
        pair.db.number(cycle_time)
    );
    // S-0-0017, the IDN list of all operation data, is variable-length.
    let list = pair.transact(Request::read_value(Idn::from_raw(17)));
    let expected = pair
        .db
        .read_element(Idn::from_raw(17), Element::OperationData);
    assert_eq!(list.result.expect("list").words, expected.expect("list"));
}

// sercos-facts.md: 7007H operation data above maximum, from the drive's own check.
#[test]
fn the_emulated_drive_refuses_above_maximum() {
    let mut pair = Pair::new();
    let done = pair.transact(Request::write_value(LIMITED, vec![7000]));
    let error = done.result.expect_err("above maximum");
    assert_eq!(
        (error.drive, error.idn, error.element, error.kind),
        (
            drive(3),
            LIMITED,
            Element::OperationData,
            ErrorKind::Drive(ServiceError::OperationDataAboveMaximum)
        )
    );
    pair.transact(Request::write_value(LIMITED, vec![6000]))
        .result
        .expect("in range");
    assert_eq!(pair.db.number(LIMITED), Some(6000));
}

// sercos-facts.md "Procedure commands": S-0-0099 set (3), polled, cancelled (0); the
// change bit (status word bit 5) reaches the master as INT_CMD (410B §4.2.4).
#[test]
fn procedure_command_on_the_emulated_drive() {
    let mut pair = Pair::new();
    let command = Idn::from_raw(99);
    pair.transact(Request::set_command(command))
        .result
        .expect("set");
    for _ in 0..3 {
        pair.cycle();
    }
    assert_eq!(pair.client.take_command_changes(), vec![drive(3)]);
    let status = pair.transact(Request::command_status(command));
    let status = CommandStatus(status.result.expect("poll").words[0]);
    assert!(status.is_set() && status.is_finished(), "{status:?}");
    pair.transact(Request::cancel_command(command))
        .result
        .expect("cancel");
    let status = pair.transact(Request::command_status(command));
    assert_eq!(status.result.expect("poll").words, vec![0]);
}
