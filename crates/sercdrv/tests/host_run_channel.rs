//! The host-run service channel (`HostRunChannel`, used by a master whose MDT records no
//! service container serves: spec-notes "Master DMA layout") against the chip-run one. The
//! same drives (their containers run by sercon-model's slave-mode rules, 410B §4.2.4 slave
//! table) answer the same requests once through master containers the chip runs
//! (`service_channel_support::Ring`: sercon-model's master-mode rules) and once through
//! containers the host runs with the shared rules (`sercon_regs::ram::service_rules`,
//! 410B §4.2.4 master table). Every request must end the same way (data or error, and the
//! element it failed on) and leave the drives in the same state.

mod service_channel_support;

use sercdrv::service_channel::{Completion, ErrorKind, HostRunChannel, Request, Ticket};
use sercon_regs::Variant;
use sercon_regs::ram::service::NInfo;
use sercos_wire::address::DriveAddress;
use sercos_wire::idn::{Element, Idn};
use sercos_wire::time::{Duration, Instant};
use service_channel_support::*;

/// The drives of a [`Ring`] served by a host-run channel instead of the master chip.
struct HostRunRing {
    variant: Variant,
    channel: HostRunChannel,
    stations: Vec<Station>,
    record_words: usize,
    now: Instant,
    cycles: u64,
    completions: Vec<Completion>,
}

impl HostRunRing {
    /// `drives` drives (slave containers as in [`Ring::new`]), `buffer` words per host-run
    /// buffer.
    fn new(variant: Variant, drives: u8, buffer: u16) -> HostRunRing {
        // One info word per record, as `Ring::new`.
        let ninfo = NInfo::from_count(1).expect("1-4");
        let stations: Vec<Station> = (1..=drives)
            .map(|n| Station::new(variant, drive(n), buffer, ninfo))
            .collect();
        let addresses: Vec<DriveAddress> = stations.iter().map(|s| s.address).collect();
        let channel =
            HostRunChannel::new(variant, &addresses, buffer, None).expect("containers fit");
        HostRunRing {
            variant,
            channel,
            stations,
            record_words: 1 + usize::from(ninfo.count()),
            now: Instant::ZERO,
            cycles: 0,
            completions: Vec::new(),
        }
    }

    /// One cycle as the master's host runs it: the MDT service info of every drive
    /// (`transmit`), the drives' answers (`receive`: `None` for a missing AT, 410B §4.2.4
    /// RECERR), the drives' processors, then the host's turn (`poll`).
    fn cycle(&mut self) {
        for station in &mut self.stations {
            let mut mdt = vec![0u16; self.record_words];
            mdt[0] = 0xE000;
            self.channel.transmit(station.address, &mut mdt);
            let at = station.exchange(self.variant, &mdt);
            self.channel.receive(station.address, at.as_deref());
        }
        for station in &mut self.stations {
            station.react();
        }
        let done = self.channel.poll(self.now);
        self.completions.extend(done);
        self.now = self.now.saturating_add(Duration::from_millis(2));
        self.cycles += 1;
    }

    fn run_until(&mut self, ticket: Ticket, limit: u64) -> Completion {
        for _ in 0..limit {
            if let Some(i) = self.completions.iter().position(|c| c.ticket == ticket) {
                return self.completions.remove(i);
            }
            self.cycle();
        }
        panic!("ticket {ticket:?} not done after {limit} cycles");
    }

    fn transact(&mut self, n: u8, request: Request) -> Completion {
        let ticket = self
            .channel
            .submit(drive(n), request)
            .expect("drive has a host-run container");
        self.run_until(ticket, 2000)
    }
}

/// What must agree between the two channels: drive, IDN, element, data or error.
fn outcome(c: &Completion) -> String {
    format!("{} {:?} {:?} {:?}", c.drive, c.idn, c.element, c.result)
}

/// The requests of the chip-run channel's own tests (service_channel_transfers.rs): reads of
/// text, attribute and value, writes of a value and a list, a refused write, an unknown IDN,
/// a fixed element, a procedure command.
fn requests() -> Vec<(u8, Request)> {
    vec![
        (1, Request::read(NAMED, Element::Name)),
        (2, Request::read(TWO_WORDS, Element::Attribute)),
        (1, Request::read_value(TWO_WORDS)),
        (2, Request::write_value(ONE_WORD, vec![1234])),
        (2, Request::read_value(ONE_WORD)),
        (1, Request::write_list(AT_LIST, &[0x000B, 0x0033, 0x8013])),
        (1, Request::read_value(AT_LIST)),
        (2, Request::write_value(ONE_WORD, vec![6001])),
        (1, Request::read_value(Idn::from_raw(0x0777))),
        (2, Request::write(NAMED, Element::Name, text_words(b"x"))),
        (1, Request::read_words(NAMED, Element::Minimum, 1)),
        (2, Request::set_command(COMMAND)),
        (2, Request::command_status(COMMAND)),
        (2, Request::cancel_command(COMMAND)),
    ]
}

// 410B §4.2.4: the master table's rules give the same transfers whoever runs them.
#[test]
fn every_request_ends_as_with_the_chip_run_containers() {
    for variant in Variant::ALL {
        let mut chip = Ring::new(variant, 2, 251);
        let mut host = HostRunRing::new(variant, 2, 251);
        for (n, request) in requests() {
            let a = chip.transact(n, request.clone());
            let b = host.transact(n, request.clone());
            assert_eq!(outcome(&a), outcome(&b), "{variant:?} {request:?}");
        }
        // The drives were left the same: parameters, and what their servers wrote.
        for (a, b) in chip.stations.iter().zip(&host.stations) {
            assert_eq!(a.store.writes, b.store.writes, "{variant:?} {}", a.address);
            for (idn, p) in &a.store.params {
                assert_eq!(p.value, b.store.params[idn].value, "{variant:?} {idn:?}");
            }
        }
        // Not by chance: the requests did reach both, a write and an error among them.
        assert_eq!(host.stations[1].store.params[&ONE_WORD].value, vec![1234]);
        assert!(!host.stations[0].store.writes.is_empty());
    }
}

// 410B §4.2.4: NINFO, the buffers and their pointers work with a short host-run buffer
// (several buffer fills for one 60-byte name) as with the chip's.
#[test]
fn a_name_through_a_short_buffer_takes_the_same_cycles() {
    let mut chip = Ring::new(Variant::Sercon816, 1, 4);
    let mut host = HostRunRing::new(Variant::Sercon816, 1, 4);
    let a = chip.transact(1, Request::read(NAMED, Element::Name));
    let b = host.transact(1, Request::read(NAMED, Element::Name));
    assert_eq!(outcome(&a), outcome(&b));
    assert_eq!(b.result.expect("name").words, text_words(NAME60));
    // The host-run channel takes the AT in the cycle the chip would and starts the next
    // step in the MDT after it: the transfer needs exactly as many cycles.
    assert_eq!(host.cycles, chip.cycles, "host-run vs chip-run cycles");
}

// 410B §4.1 0DH HS_TIMEOUT, §4.2.4 INT_HS_TIMEOUT: a drive that never answers.
#[test]
fn handshake_timeout_when_the_drive_never_answers() {
    let mut host = HostRunRing::new(Variant::Sercon410b, 1, 16);
    host.channel.set_timeouts(10, 0);
    host.stations[0].silent = true;
    let done = host.transact(1, Request::read_value(ONE_WORD));
    let error = done.result.expect_err("no answer");
    assert_eq!(error.kind, ErrorKind::HandshakeTimeout);
    assert_eq!(error.element, Element::Idn, "stuck while opening");
    assert!(
        (10..=12).contains(&host.cycles),
        "{} cycles for HS_TIMEOUT 10",
        host.cycles
    );
}

// 410B §4.1 0DH BUSY_TIMEOUT: the drive's processor never reacts (BUSY stays set).
#[test]
fn busy_timeout_when_the_drive_stays_busy() {
    let mut host = HostRunRing::new(Variant::Sercon816, 1, 16);
    host.channel.set_timeouts(0, 5);
    host.stations[0].asleep = true;
    let done = host.transact(1, Request::read_value(ONE_WORD));
    assert_eq!(done.result.expect_err("busy").kind, ErrorKind::BusyTimeout);
    // After the timeout the drive wakes up: the channel serves it again.
    host.stations[0].asleep = false;
    let done = host.transact(1, Request::read_value(ONE_WORD));
    assert_eq!(done.result.expect("read").words, vec![100]);
}

// Eight containers per bank (NSV is 3 bits, 410B §4.2): drives 1-10 span two banks and all
// run at once; tickets of different banks never collide.
#[test]
fn two_banks_run_their_drives_at_once() {
    let mut host = HostRunRing::new(Variant::Sercon816, 10, 16);
    let tickets: Vec<Ticket> = (1..=10)
        .map(|n| {
            host.channel
                .submit(drive(n), Request::write_value(ONE_WORD, vec![u16::from(n)]))
                .expect("served")
        })
        .collect();
    let mut unique = tickets.clone();
    unique.sort_by_key(|t| t.0);
    unique.dedup();
    assert_eq!(unique.len(), 10, "tickets distinct: {tickets:?}");
    let mut single = HostRunRing::new(Variant::Sercon816, 1, 16);
    single.transact(1, Request::write_value(ONE_WORD, vec![1]));
    for t in tickets {
        host.run_until(t, 200).result.expect("write");
    }
    // All ten in parallel: about as long as one alone.
    assert!(
        host.cycles <= single.cycles + 2,
        "{} vs {}",
        host.cycles,
        single.cycles
    );
    for (n, s) in (1u16..).zip(&host.stations) {
        assert_eq!(s.store.params[&ONE_WORD].value, vec![n]);
    }
    assert!(host.channel.is_idle());
    assert!(
        host.channel
            .submit(drive(11), Request::read_value(ONE_WORD))
            .is_none(),
        "drive 11 has no container"
    );
}
