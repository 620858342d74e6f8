//! Service-channel transfers between a master-mode and a slave-mode service container,
//! cycle by cycle through `on_transmit` / `on_receive` / `on_cycle` (410B §1 "executed
//! automatically", §4.2.4 both tables).

mod service_channel_support;

use sercon_model::service_container::{ScInterrupts, Variant};
use service_channel_support::*;

const IDN_NAME_PARAM: u16 = 0x8001; // P-0-0001
const NAME: &[u8; 60] = b"Spindle drive 7, retrofit 2024, SERCON816 model, axis X-left";

/// Writes element 1 (the IDN) and returns the cycles it took.
fn open_idn(link: &mut Link, drive: &mut Drive, idn: u16) -> usize {
    link.master_write(1, &[idn], 1);
    let logs = run(link, drive, 50, |log, _| {
        log.master_raised().contains(ScInterrupts::INT_END_WRBUF)
    });
    assert_eq!(drive.idn, idn);
    logs.len()
}

// 410B §4.2.4 master table: HS_MDT toggling, L/S_MDT, SETEND → END_MDT, NINFO_WRITE,
// WRDATPT → WRDATLAST, INT_END_WRBUF; slave table: HS_AT, ELEM/L/S, INT_ELEM_CHANGE,
// INT_END_MDT, read buffer. sercos-facts.md: variable-length data.
#[test]
fn sixty_byte_name_written_then_read_back_one_info_word_per_step() {
    let mut link = Link::new(Variant::Sercon816);
    let mut drive = Drive::default();
    open_idn(&mut link, &mut drive, IDN_NAME_PARAM);

    let name = variable_length(NAME, 60);
    assert_eq!(name.len(), 32);
    link.master_write(2, &name, 1);
    let logs = run(&mut link, &mut drive, 200, |log, _| {
        log.master_raised().contains(ScInterrupts::INT_END_WRBUF)
    });

    // One acknowledged step per info word: 32 handshakes, each moving one word.
    let acks: Vec<_> = logs.iter().filter(|l| l.master_rx.handshake).collect();
    assert_eq!(acks.len(), 32);
    assert!(acks.iter().all(|l| l.master_tx.info_words == 1));
    // Two held cycles: the element change and the END_MDT check each hold BUSY_AT until
    // the drive reacts (spec-notes "Service containers").
    assert_eq!(logs.len(), 34);
    assert!(logs[32].at[0] & 2 != 0, "last write step: busy");
    assert_eq!(
        logs[32].at[0] & 1,
        logs[32].mdt[0] & 1,
        "last write step: AHS = MHS"
    );
    assert!(logs[0].at[0] & 2 != 0, "first AT: busy");
    assert_ne!(
        logs[0].at[0] & 1,
        logs[0].mdt[0] & 1,
        "first AT: AHS not yet = MHS"
    );
    // MHS toggles on every acknowledged step (sercos-telegrams.md MDT bit 0).
    let mhs: Vec<u16> = acks.iter().map(|l| l.mdt[0] & 1).collect();
    assert!(mhs.windows(2).all(|w| w[0] != w[1]));
    // Each MDT carries the next word; END_MDT only on the last (SETEND).
    let sent: Vec<u16> = acks.iter().map(|l| l.mdt[1]).collect();
    assert_eq!(sent, name);
    let ends: Vec<bool> = acks.iter().map(|l| l.mdt[0] & 4 != 0).collect();
    assert_eq!(ends.iter().filter(|e| **e).count(), 1);
    assert_eq!(ends.last(), Some(&true));
    // Host bits of the control word are kept; element 2, write.
    assert!(acks.iter().all(|l| l.mdt[0] & 0xE000 == 0xE000));
    assert!(
        acks.iter()
            .all(|l| (l.mdt[0] >> 3) & 7 == 2 && l.mdt[0] & 2 != 0)
    );
    assert_eq!(drive.elements[2], name);
    let m = link.master_sc();
    assert_eq!(m.pointers.wrdatpt, BUF + 32);
    assert!(m.m_busy && m.int_end_wrbuf && m.end_mdt);

    // Read it back: first the two length words, then the rest (M_BUSY holds in between).
    open_idn(&mut link, &mut drive, IDN_NAME_PARAM);
    link.master_read(2, BUF, 2, 1, false);
    let first = run(&mut link, &mut drive, 50, |log, _| {
        log.master_raised().contains(ScInterrupts::INT_END_RDBUF)
    });
    assert_eq!(first.iter().filter(|l| l.master_rx.handshake).count(), 2);
    let head = link.master_buffer(BUF, 2);
    assert_eq!(head, vec![60, 60]);
    // While M_BUSY is set the channel holds: MHS does not change.
    let held: Vec<u16> = (0..3).map(|_| link.cycle().mdt[0] & 1).collect();
    assert!(held.iter().all(|h| *h == held[0]));

    let rest = u8::try_from(head[0].div_ceil(2)).expect("short");
    let mut m = link.master_sc();
    m.pointers.rddatlast = BUF + 2 + rest - 1;
    m.setend = true;
    m.int_end_rdbuf = false;
    m.m_busy = false;
    link.set_master_sc(m);
    let second = run(&mut link, &mut drive, 100, |log, _| {
        log.master_raised().contains(ScInterrupts::INT_END_RDBUF)
    });
    let acks: Vec<_> = second.iter().filter(|l| l.master_rx.handshake).collect();
    assert_eq!(acks.len(), 30);
    assert!(acks.iter().all(|l| l.master_rx.info_words == 1));
    assert!(
        acks.last().is_some_and(|l| l.mdt[0] & 4 != 0),
        "END_MDT on the last read step"
    );
    assert_eq!(link.master_buffer(BUF, 32), name);
    assert!(drive.seen.contains(&ScInterrupts::INT_END_MDT));
}

// 410B §4.2.4: NINFO_WRITE / NINFO_READ "Number of info words ... (1 to 4)".
#[test]
fn four_info_words_per_step_take_a_quarter_of_the_handshakes() {
    for variant in Variant::ALL {
        let mut link = Link::new(variant);
        let mut drive = Drive::default();
        let mut s = link.slave_sc();
        s.ninfo_read = sercon_regs::ram::service::NInfo::from_count(4).expect("4");
        s.ninfo_write = s.ninfo_read;
        link.set_slave_sc(s);
        open_idn(&mut link, &mut drive, IDN_NAME_PARAM);
        let name = variable_length(NAME, 64);
        link.master_write(2, &name, 4);
        let logs = run(&mut link, &mut drive, 100, |log, _| {
            log.master_raised().contains(ScInterrupts::INT_END_WRBUF)
        });
        let acks: Vec<_> = logs.iter().filter(|l| l.master_rx.handshake).collect();
        assert_eq!(acks.len(), 8);
        assert!(acks.iter().all(|l| l.master_tx.info_words == 4));
        assert_eq!(drive.elements[2], name);

        open_idn(&mut link, &mut drive, IDN_NAME_PARAM);
        link.master_read(2, BUF + 40, 32, 4, true);
        let logs = run(&mut link, &mut drive, 100, |log, _| {
            log.master_raised().contains(ScInterrupts::INT_END_RDBUF)
        });
        assert_eq!(logs.iter().filter(|l| l.master_rx.handshake).count(), 8);
        assert_eq!(link.master_buffer(BUF + 40, 32), name);
    }
}

// 410B §4.2.4 master table with a hand-written RAM image: one value written in one step
// (SETEND → END_MDT on the first and last step), slave INT_END_MDT holding BUSY_AT.
#[test]
fn one_word_value_written_in_one_step() {
    let mut link = Link::new(Variant::Sercon410b);
    let mut drive = Drive {
        idn: 0x0024,
        ..Drive::default()
    };
    // Master container at 100H: word 0 = ELEM_MDT 7 (38H) | L/S_MDT (2) | SETEND (40H),
    // HS_MDT 0, M_BUSY 0, NINFO_WRITE 1 word (code 0); word 1 = HS_AT 0; word 2 =
    // WRDATPT 5, WRDATLAST 5; word 3 = 0; word 4 = 0; buffer word 5 = the value 1234H.
    link.master[0x100..0x106].copy_from_slice(&[0x007A, 0x0000, 0x0505, 0x0000, 0x0000, 0x1234]);
    // Slave container at 300H: present transmission element 7, write (ELEM 70H | L/S 80H),
    // read buffer 5..=FFH (word 3 = FF05H).
    link.slave[0x300..0x305].copy_from_slice(&[0x00F0, 0x0000, 0x0000, 0xFF05, 0x0000]);

    let log = link.cycle();
    assert_eq!(log.mdt[0], 0xE000 | 0x3F, "MHS 1, write, last, element 7");
    assert_eq!(log.mdt[1], 0x1234);
    assert!(log.slave_rx.raised.contains(ScInterrupts::INT_END_MDT));
    assert_eq!(link.slave_word(5), 0x1234);
    // BUSY_AT holds the step for the slave's microprocessor (AHS already = MHS).
    assert_eq!(log.at[0] & 0b11, 0b11);
    assert!(!log.master_rx.handshake);
    drive.react(&mut link);
    assert_eq!(drive.elements[7], vec![0x1234]);
    let log = link.cycle();
    assert!(log.master_rx.handshake);
    assert!(log.master_rx.raised.contains(ScInterrupts::INT_END_WRBUF));
    // Master word 0 now: HS_MDT, END_MDT, M_BUSY, INT_END_WRBUF set.
    assert_eq!(
        link.master_word(0),
        0x007A | 0x0001 | 0x0004 | 0x0080 | 0x2000
    );
    assert_eq!(link.master_word(2), 0x0506, "WRDATPT moved past WRDATLAST");
}
