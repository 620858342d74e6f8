//! SERCDRV's service channel, master client and slave server, over two RAM images linked
//! record by record through the sercon-model service containers (410B §4.2.4).

mod service_channel_support;

use sercdrv::service_channel::{CommandStatus, ErrorKind, ReadLength, Request};
use sercon_regs::Variant;
use sercos_wire::attribute::{Attribute, DataLength, DisplayFormat};
use sercos_wire::idn::{Element, Idn};
use sercos_wire::service_error::{DescriptiveElement, ElementFault, ServiceError};
use sercos_wire::time::Duration;
use service_channel_support::*;

// sercos-facts.md "Variable-length data" (length words, then the bytes); "IDNs" element 2.
#[test]
fn reads_a_sixty_byte_name() {
    for variant in Variant::ALL {
        let mut ring = Ring::new(variant, 1, 251);
        let done = ring.transact(1, Request::read(NAMED, Element::Name));
        let response = done.result.expect("name read");
        assert_eq!(response.words, text_words(NAME60));
        assert_eq!(response.words.len(), 32);
        assert_eq!(done.idn, NAMED);
        assert_eq!(done.element, Element::Name);
        // Open (1 step), the two length words, then 30 words: at least 33 cycles.
        assert!(ring.cycles >= 33, "{} cycles", ring.cycles);
        let text: Vec<u8> = response.words[2..]
            .iter()
            .flat_map(|w| w.to_le_bytes())
            .take(usize::from(response.words[0]))
            .collect();
        assert_eq!(text, NAME60.to_vec());
    }
}

// sercos-facts.md "IDNs": the attribute is 32 bits (two words, low first).
#[test]
fn reads_an_attribute() {
    let mut ring = Ring::new(Variant::Sercon410b, 1, 16);
    let done = ring.transact(1, Request::read(TWO_WORDS, Element::Attribute));
    let response = done.result.expect("attribute read");
    let expected = Attribute::new(DataLength::FourBytes, DisplayFormat::SignedDecimal);
    assert_eq!(response.words, expected.to_words().to_vec());
    assert_eq!(response.attribute, Some(expected));
}

// The captures' master reads the attribute before operation data (capture transcript:
// "attribute (2 steps)", then "operation data"); its data length gives the word count.
#[test]
fn reads_operation_data_with_the_length_the_attribute_gives() {
    let mut ring = Ring::new(Variant::Sercon816, 1, 16);
    let done = ring.transact(1, Request::read_value(TWO_WORDS));
    let response = done.result.expect("value read");
    assert_eq!(response.words, vec![0x5678, 0x1234]);
    let attribute = response.attribute.expect("attribute read first");
    assert_eq!(attribute.fixed_words(), Some(2));
    // The unit (element 4) is text too.
    let unit = ring.transact(1, Request::read(TWO_WORDS, Element::Unit));
    assert_eq!(unit.result.expect("unit").words, text_words(b"deg"));
}

// sercos-telegrams.md MDT control word bits 5-0 (one info word per step); 410B §4.2.4.
#[test]
fn writes_a_one_word_value() {
    let mut ring = Ring::new(Variant::Sercon410b, 1, 16);
    let done = ring.transact(1, Request::write_value(ONE_WORD, vec![1234]));
    assert_eq!(done.result.expect("write").words, Vec::<u16>::new());
    let store = &ring.station(1).store;
    assert_eq!(store.params[&ONE_WORD].value, vec![1234]);
    assert_eq!(
        store.writes,
        vec![(ONE_WORD, Element::OperationData, vec![1234])]
    );
    let back = ring.transact(1, Request::read_value(ONE_WORD));
    assert_eq!(back.result.expect("read back").words, vec![1234]);
}

// sercos-facts.md "Variable-length data": the captures' writes of S-0-0016 begin with the
// current and maximum length in bytes.
#[test]
fn writes_an_idn_list_and_reads_it_back() {
    let mut ring = Ring::new(Variant::Sercon816, 1, 251);
    let list = [0x000B, 0x0033, 0x8013]; // S-0-0011, S-0-0051, P-0-0019
    let done = ring.transact(1, Request::write_list(AT_LIST, &list));
    done.result.expect("list write");
    let expected = vec![6, 6, 0x000B, 0x0033, 0x8013];
    assert_eq!(ring.station(1).store.params[&AT_LIST].value, expected);
    let back = ring.transact(1, Request::read_value(AT_LIST));
    let response = back.result.expect("list read");
    assert_eq!(response.words, expected);
    assert_eq!(
        response.attribute.map(|a| a.data_length()),
        Some(DataLength::VariableWords)
    );
}

// sercos-facts.md "Service channel errors": 7007H operation data above maximum; 410B
// §4.2.4 ERR_AT / INT_ERR.
#[test]
fn refused_write_names_drive_idn_and_element() {
    let mut ring = Ring::new(Variant::Sercon816, 2, 16);
    let done = ring.transact(2, Request::write_value(ONE_WORD, vec![6001]));
    let error = done.result.expect_err("above maximum");
    assert_eq!(error.drive, drive(2));
    assert_eq!(error.idn, ONE_WORD);
    assert_eq!(error.element, Element::OperationData);
    assert_eq!(
        error.kind,
        ErrorKind::Drive(ServiceError::OperationDataAboveMaximum)
    );
    assert_eq!(error.service_error().map(ServiceError::code), Some(0x7007));
    let text = error.to_string();
    assert!(text.contains("drive 2"), "{text}");
    assert!(text.contains("S-0-0036"), "{text}");
    assert!(text.contains("7007"), "{text}");
    assert_eq!(ring.station(2).store.params[&ONE_WORD].value, vec![100]);
    // The channel works again after the error.
    let ok = ring.transact(2, Request::write_value(ONE_WORD, vec![6000]));
    ok.result.expect("in range");
    assert_eq!(ring.station(2).store.params[&ONE_WORD].value, vec![6000]);
}

// sercos-facts.md: 1001H IDN not present (refused while opening: element 1); x004H.
#[test]
fn unknown_idn_and_fixed_element_are_refused() {
    let mut ring = Ring::new(Variant::Sercon410b, 1, 16);
    let missing = Idn::from_raw(0x0777);
    let done = ring.transact(1, Request::read_value(missing));
    let error = done.result.expect_err("not present");
    assert_eq!(error.kind, ErrorKind::Drive(ServiceError::IdnNotPresent));
    assert_eq!(error.element, Element::Idn);
    let done = ring.transact(1, Request::write(NAMED, Element::Name, text_words(b"x")));
    let error = done.result.expect_err("name fixed");
    assert_eq!(
        error.kind,
        ErrorKind::Drive(ServiceError::Element(
            DescriptiveElement::Name,
            ElementFault::CannotBeChanged
        ))
    );
    assert_eq!(error.element, Element::Name);
    // A minimum the drive has not: 5001H, on element 5 (read without the attribute).
    let done = ring.transact(1, Request::read_words(NAMED, Element::Minimum, 1));
    assert_eq!(
        done.result.expect_err("no minimum").kind,
        ErrorKind::Drive(ServiceError::Element(
            DescriptiveElement::Minimum,
            ElementFault::NotPresent
        ))
    );
}

// sercos-facts.md "Procedure commands": 3 = set and enable, poll, 0 = cancel; status-word
// bit 5 signals the change (410B §4.2.4 CMD_AT / INT_CMD).
#[test]
fn procedure_command_set_poll_cancel() {
    let mut ring = Ring::new(Variant::Sercon816, 1, 16);
    assert!(ring.client.take_command_changes().is_empty());
    ring.transact(1, Request::set_command(COMMAND))
        .result
        .expect("set");
    // The drive raises the command change bit; the master's container reports INT_CMD.
    for _ in 0..3 {
        ring.cycle();
    }
    assert_eq!(ring.client.take_command_changes(), vec![drive(1)]);
    let status = ring.transact(1, Request::command_status(COMMAND));
    let status = CommandStatus(status.result.expect("poll").words[0]);
    assert!(status.is_executed(), "{status:?}");
    ring.transact(1, Request::cancel_command(COMMAND))
        .result
        .expect("cancel");
    let status = ring.transact(1, Request::command_status(COMMAND));
    assert_eq!(status.result.expect("poll").words, vec![0]);
    assert!(!ring.station(1).store.command_change());
    // No second change reported: the bit fell, it did not rise again.
    assert!(ring.client.take_command_changes().is_empty());
}

// 410B §4.1 0DH HS_TIMEOUT and §4.2.4 INT_HS_TIMEOUT: the drive never answers.
#[test]
fn handshake_timeout_when_the_slave_never_answers() {
    let mut ring = Ring::new(Variant::Sercon410b, 1, 16);
    ring.hs_timeout = 10;
    ring.station(1).silent = true;
    let done = ring.transact(1, Request::read_value(ONE_WORD));
    let error = done.result.expect_err("no answer");
    assert_eq!(error.kind, ErrorKind::HandshakeTimeout);
    assert_eq!(error.element, Element::Idn, "stuck while opening");
    assert!(ring.cycles >= 10 && ring.cycles <= 12, "{}", ring.cycles);
}

// 410B §4.1 0DH BUSY_TIMEOUT: the drive's processor never reacts (BUSY stays set).
#[test]
fn busy_timeout_when_the_drive_stays_busy() {
    let mut ring = Ring::new(Variant::Sercon816, 1, 16);
    ring.busy_timeout = 5;
    ring.station(1).asleep = true;
    let done = ring.transact(1, Request::read_value(ONE_WORD));
    assert_eq!(done.result.expect_err("busy").kind, ErrorKind::BusyTimeout);
}

// The driver's own time limit (injected time, no clock read) with the chip's timeouts off.
#[test]
fn time_limit_when_the_chip_does_not_count() {
    let mut ring = Ring::new(Variant::Sercon816, 1, 16);
    ring.client.set_timeout(Some(Duration::from_millis(50)));
    ring.station(1).silent = true;
    let ticket = ring.client.submit(drive(1), Request::read_value(ONE_WORD));
    ring.cycle();
    assert_eq!(
        ring.client.next_deadline(),
        Some(sercos_wire::time::Instant::ZERO.saturating_add(Duration::from_millis(50)))
    );
    let done = ring.run_until(ticket, 100);
    assert_eq!(done.result.expect_err("late").kind, ErrorKind::Timeout);
    // 2 ms cycles: the limit runs out on the 26th poll (t = 50 ms).
    assert_eq!(ring.cycles, 26);
    assert!(ring.client.is_idle());
}

// 410B §4.2.4: eight service containers, each with its own handshake: two drives at once.
#[test]
fn two_drives_in_parallel_through_two_containers() {
    let mut ring = Ring::new(Variant::Sercon816, 2, 251);
    let a = ring
        .client
        .submit(drive(1), Request::read(NAMED, Element::Name));
    let b = ring
        .client
        .submit(drive(2), Request::read(NAMED, Element::Name));
    let done_a = ring.run_until(a, 200);
    let cycles_a = ring.cycles;
    let done_b = ring.run_until(b, 200);
    assert_eq!(ring.max_running, 2);
    assert_eq!(done_a.drive, drive(1));
    assert_eq!(done_b.drive, drive(2));
    assert_eq!(done_a.result.expect("a").words, text_words(NAME60));
    assert_eq!(done_b.result.expect("b").words, text_words(NAME60));
    // In parallel: the second ends within a couple of cycles of the first.
    assert!(
        ring.cycles <= cycles_a + 2,
        "{} vs {}",
        ring.cycles,
        cycles_a
    );

    // One sequential read for comparison takes about as long as both together.
    let mut single = Ring::new(Variant::Sercon816, 1, 251);
    single.transact(1, Request::read(NAMED, Element::Name));
    assert!(single.cycles * 2 > ring.cycles + 10);
}

// One drive's requests run one after the other, in the order submitted.
#[test]
fn requests_to_one_drive_keep_their_order() {
    let mut ring = Ring::new(Variant::Sercon410b, 1, 16);
    let t1 = ring
        .client
        .submit(drive(1), Request::write_value(ONE_WORD, vec![1]));
    let t2 = ring
        .client
        .submit(drive(1), Request::write_value(ONE_WORD, vec![2]));
    let t3 = ring.client.submit(drive(1), Request::read_value(ONE_WORD));
    assert_eq!(ring.client.pending(), 3);
    let r3 = ring.run_until(t3, 500);
    assert_eq!(r3.result.expect("read").words, vec![2]);
    let order: Vec<_> = ring.completions.iter().map(|c| c.ticket).collect();
    assert_eq!(order, vec![t1, t2]);
    assert_eq!(ring.max_running, 1);
}

// 410B §4.2.4 INT_END_WRBUF / INT_END_RDBUF: data longer than the buffer goes in chunks.
#[test]
fn data_longer_than_the_buffer_goes_in_chunks() {
    let mut ring = Ring::new(Variant::Sercon816, 1, 4);
    let list: Vec<u16> = (1..=37).collect();
    ring.transact(1, Request::write_list(AT_LIST, &list))
        .result
        .expect("long write");
    let mut expected = vec![74, 74];
    expected.extend(&list);
    assert_eq!(ring.station(1).store.params[&AT_LIST].value, expected);
    let back = ring.transact(1, Request::read_value(AT_LIST));
    assert_eq!(back.result.expect("long read").words, expected);
    let name = ring.transact(1, Request::read(NAMED, Element::Name));
    assert_eq!(name.result.expect("name").words, text_words(NAME60));
}

// A request that can't go on the line fails at once without taking a container.
#[test]
fn invalid_requests_fail_at_once() {
    let mut ring = Ring::new(Variant::Sercon410b, 1, 16);
    let done = ring.transact(1, Request::read(ONE_WORD, Element::ServiceChannelClosed));
    assert!(matches!(
        done.result.expect_err("element 0").kind,
        ErrorKind::InvalidRequest(_)
    ));
    let done = ring.transact(1, Request::write_value(ONE_WORD, Vec::new()));
    assert!(matches!(
        done.result.expect_err("empty").kind,
        ErrorKind::InvalidRequest(_)
    ));
    assert!(ring.cycles <= 2);
    let done = ring.transact(
        1,
        Request::Read {
            idn: ONE_WORD,
            element: Element::OperationData,
            length: ReadLength::Variable,
        },
    );
    // Reading a one-word value as variable-length data: the length word says 1234 bytes? No:
    // the value is 100, so 50 more words are read (zeros past the end).
    let words = done.result.expect("variable read").words;
    assert_eq!(words.len(), 52);
    assert_eq!(words[0], 100);
}

// 410B §4.2.4 NINFO_WRITE / NINFO_READ (1 to 4 info words per step): the same transfers
// with four words per record take a quarter of the steps; the slave drops the zeros that
// fill the last step (spec-notes "Driver service channel").
#[test]
fn four_info_words_per_record() {
    let mut one = Ring::new(Variant::Sercon816, 1, 251);
    one.transact(1, Request::read(NAMED, Element::Name))
        .result
        .expect("name");
    let mut four = Ring::with_ninfo(Variant::Sercon816, 1, 251, 4);
    let name = four.transact(1, Request::read(NAMED, Element::Name));
    assert_eq!(name.result.expect("name").words, text_words(NAME60));
    assert!(
        four.cycles * 2 < one.cycles,
        "{} vs {}",
        four.cycles,
        one.cycles
    );
    four.transact(1, Request::write_value(ONE_WORD, vec![42]))
        .result
        .expect("one word in a 4-word step");
    assert_eq!(four.station(1).store.params[&ONE_WORD].value, vec![42]);
    four.transact(1, Request::write_list(AT_LIST, &[1, 2, 3]))
        .result
        .expect("list");
    assert_eq!(
        four.station(1).store.params[&AT_LIST].value,
        vec![6, 6, 1, 2, 3]
    );
    let back = four.transact(1, Request::read_value(TWO_WORDS));
    assert_eq!(back.result.expect("two words").words, vec![0x5678, 0x1234]);
    // Really too long still fails: 3 words (padded to 4) to a one-word value.
    let done = four.transact(1, Request::write_value(ONE_WORD, vec![1, 2, 3]));
    assert_eq!(
        done.result.expect_err("too long").kind,
        ErrorKind::Drive(ServiceError::OperationDataTooLong)
    );
}
