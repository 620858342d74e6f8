//! Property tests: arbitrary store contents, requests and RAM never make the service
//! channel panic, and every request ends (410B §4.2.4; "no panics from input").

mod service_channel_support;

use proptest::prelude::*;
use sercdrv::service_channel::{
    ContainerSlot, ReadLength, Request, ServiceChannelMaster, ServiceChannelSlave, Wiring,
};
use sercon_regs::{IntFlagsHi, Variant};
use sercos_wire::attribute::Attribute;
use sercos_wire::idn::{Element, Idn};
use sercos_wire::time::{Duration, Instant};
use service_channel_support::*;

fn param() -> impl Strategy<Value = Param> {
    (
        proptest::collection::vec(any::<u8>(), 0..70),
        any::<u32>(),
        proptest::option::of(any::<u16>()),
        proptest::option::of(any::<u16>()),
        proptest::collection::vec(any::<u16>(), 0..12),
    )
        .prop_map(|(name, attribute, min, max, value)| Param {
            name,
            unit: b"mm".to_vec(),
            attribute: Attribute::from_raw(attribute),
            min,
            max,
            value,
        })
}

fn request() -> impl Strategy<Value = Request> {
    let idn = prop_oneof![
        Just(ONE_WORD),
        Just(NAMED),
        Just(AT_LIST),
        Just(COMMAND),
        any::<u16>().prop_map(Idn::from_raw),
    ];
    let length = prop_oneof![
        Just(ReadLength::Auto),
        Just(ReadLength::Variable),
        (0u16..10).prop_map(ReadLength::Words),
    ];
    prop_oneof![
        (idn.clone(), 0u8..8, length).prop_map(|(idn, e, length)| Request::Read {
            idn,
            element: Element::from_bits(e),
            length,
        }),
        (idn, 0u8..8, proptest::collection::vec(any::<u16>(), 0..10)).prop_map(
            |(idn, e, words)| Request::Write {
                idn,
                element: Element::from_bits(e),
                words,
            }
        ),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(64)))]

    // Arbitrary store contents and request sequences: no panic, every request completes
    // (the time limit bounds reads whose length word is large), fixed-length reads return
    // the words asked for.
    #[test]
    fn arbitrary_stores_and_requests_end(
        params in proptest::collection::vec(param(), 4),
        requests in proptest::collection::vec((1u8..=2, request()), 1..8),
        buffer in 1u16..40,
        ninfo in 1u8..=4,
    ) {
        let mut ring = Ring::with_ninfo(Variant::Sercon816, 2, buffer, ninfo);
        for station in &mut ring.stations {
            for (idn, p) in [ONE_WORD, NAMED, AT_LIST, COMMAND].into_iter().zip(&params) {
                station.store.params.insert(idn, p.clone());
            }
        }
        ring.client.set_timeout(Some(Duration::from_millis(400)));
        let mut tickets = Vec::new();
        for (n, r) in &requests {
            tickets.push((ring.client.submit(drive(*n), r.clone()), r.clone()));
        }
        for _ in 0..(requests.len() as u64 * 220) {
            if ring.client.is_idle() {
                break;
            }
            ring.cycle();
        }
        prop_assert!(ring.client.is_idle());
        prop_assert_eq!(ring.completions.len(), requests.len());
        for (ticket, r) in tickets {
            let done = ring.completions.iter().find(|c| c.ticket == ticket);
            prop_assert!(done.is_some());
            if let (Some(done), Request::Read { length: ReadLength::Words(n), .. }) = (done, &r) {
                if let Ok(response) = &done.result {
                    prop_assert_eq!(response.words.len(), usize::from(*n));
                }
            }
        }
    }

    // Arbitrary RAM and register contents, changed between polls (a chip or a host gone
    // wrong): the client and the server never panic.
    #[test]
    fn arbitrary_ram_never_panics(
        ram in proptest::collection::vec(any::<u16>(), 2048),
        edits in proptest::collection::vec((0usize..2048, any::<u16>(), any::<u16>()), 1..40),
        address in 0u16..2048,
        nsv in 0u8..8,
        buffer in 1u16..=251,
        requests in proptest::collection::vec(request(), 0..6),
    ) {
        let v = Variant::Sercon816;
        let slot = ContainerSlot::new(v, nsv, address, buffer).expect("valid slot");
        let mut bus = RamBus::new(v);
        bus.ram.copy_from_slice(&ram);
        let mut client = ServiceChannelMaster::new([(slot, Wiring::Drive(drive(1)))]);
        client.set_timeout(Some(Duration::from_millis(30)));
        for r in requests {
            client.submit(drive(1), r);
        }
        let mut slave_bus = RamBus::new(v);
        slave_bus.ram.copy_from_slice(&ram);
        let mut server = ServiceChannelSlave::new(slot);
        let mut store = TestStore::standard();
        let mut now = Instant::ZERO;
        for (at, value, flags) in edits {
            bus.ram[at] = value;
            slave_bus.ram[at] = value.rotate_left(3);
            let flags = IntFlagsHi::from_bits_retain(flags);
            let _ = client.on_interrupt(&mut bus, flags, now);
            let _ = server.on_interrupt(&mut slave_bus, &mut store, flags);
            now = now.saturating_add(Duration::from_millis(2));
        }
        let _ = client.take_command_changes();
    }
}
