//! Service-channel errors, holds and timeouts between a master-mode and a slave-mode
//! service container (410B §4.2.4 both tables, §4.1 0DH; 816 §2.10.2.2).

mod service_channel_support;

use sercon_model::service_container::{ScInterrupts, ScMode, Variant, on_receive};
use service_channel_support::*;

fn open(link: &mut Link, drive: &mut Drive) {
    link.master_write(1, &[0x0024], 1);
    run(link, drive, 20, |log, _| {
        log.master_raised().contains(ScInterrupts::INT_END_WRBUF)
    });
}

// 410B §4.2.4 master INT_ERR "Slave reports error" (ERR_AT); slave ERR_AT "Error bit in AT".
#[test]
fn slave_error_reaches_the_master_as_int_err_with_the_code() {
    let mut link = Link::new(Variant::Sercon816);
    let mut drive = Drive::default();
    open(&mut link, &mut drive);
    drive.refuse_with = Some(0x7004); // operation data cannot be changed
    link.master_read(7, 0x40, 4, 1, false); // read buffer for the error code
    link.master_write(7, &[0x0003], 1);
    let logs = run(&mut link, &mut drive, 20, |log, _| {
        log.master_raised().contains(ScInterrupts::INT_ERR)
    });
    let last = logs.last().expect("ran");
    assert!(last.at[0] & 4 != 0, "AT status bit 2: error");
    assert!(last.master_rx.int_sc && last.master_rx.handshake);
    assert!(!last.master_rx.raised.contains(ScInterrupts::INT_END_WRBUF));
    let m = link.master_sc();
    assert!(m.int_err && m.err_at && m.m_busy);
    // The error code is kept at RDDATPT, which does not move.
    assert_eq!(link.master_word(0x40), 0x7004);
    assert_eq!(m.pointers.rddatpt, 0x40);
}

// 410B §4.2.4 slave INT_ELEM_CHANGE "Master has modified data element or read/write";
// BUSY_AT "also waiting for microprocessor interaction"; master BUSY_CNT counts BUSY cycles.
#[test]
fn element_change_holds_busy_until_the_slave_reacts() {
    let mut link = Link::new(Variant::Sercon410b);
    let mut drive = Drive::default();
    open(&mut link, &mut drive);
    drive.elements[3] = vec![0x1234, 0x0005];
    drive.asleep = true;
    link.master_read(3, BUF, 2, 1, true);
    for _ in 0..4 {
        let log = link.cycle();
        assert!(log.at[0] & 2 != 0, "busy while the drive sleeps");
        assert!(!log.master_rx.handshake);
    }
    let s = link.slave_sc();
    assert!(s.int_elem_change && s.busy_at);
    assert_eq!(
        (s.elem, s.ls),
        (3, false),
        "present transmission: element 3, read"
    );
    assert_eq!((s.elem_mdt, s.ls_mdt), (3, false));
    let m = link.master_sc();
    assert!(m.busy_cnt);
    assert_eq!(m.err_cnt, 4, "four busy cycles counted");
    drive.asleep = false;
    drive.react(&mut link);
    run(&mut link, &mut drive, 10, |log, _| {
        log.master_raised().contains(ScInterrupts::INT_END_RDBUF)
    });
    assert_eq!(link.master_buffer(BUF, 2), vec![0x1234, 0x0005]);
    assert_eq!(drive.seen.first(), Some(&ScInterrupts::INT_ELEM_CHANGE));
}

// 410B §4.1 0DH HS_TIMEOUT; §4.2.4 ERR_CNT, BUSY_CNT = 0, INT_HS_TIMEOUT.
#[test]
fn handshake_timeout_after_hs_timeout_cycles_without_answer() {
    let mut link = Link::new(Variant::Sercon816);
    let mut drive = Drive::default();
    open(&mut link, &mut drive);
    link.hs_timeout = 5;
    link.busy_timeout = 2;
    link.slave_silent = true;
    link.master_write(7, &[1, 2, 3], 1);
    let mut raised_at = Vec::new();
    for n in 1..=12u8 {
        let log = link.cycle();
        drive.react(&mut link);
        let m = link.master_sc();
        assert_eq!(
            m.err_cnt, n,
            "ERR_CNT counts handshake differences per cycle"
        );
        assert!(!m.busy_cnt);
        if log
            .master_cycle
            .raised
            .contains(ScInterrupts::INT_HS_TIMEOUT)
        {
            raised_at.push(n);
        }
    }
    assert_eq!(
        raised_at,
        vec![5],
        "raised once, when ERR_CNT reaches HS_TIMEOUT"
    );
    let m = link.master_sc();
    assert!(m.int_hs_timeout && m.m_busy && !m.int_busy_timeout);
    // The step is still repeated (same MHS) and a late answer is still taken.
    link.slave_silent = false;
    let log = link.cycle();
    assert!(log.master_rx.handshake);
    assert_eq!(link.master_sc().pointers.wrdatpt, BUF + 1);
    assert!(!link.cycle().master_tx.handshake, "M_BUSY: no new step");
}

// 410B §4.1 0DH BUSY_TIMEOUT; §4.2.4 BUSY_CNT = 1, INT_BUSY_TIMEOUT; ERR_CNT restarts when
// the counted kind changes and stops at 255.
#[test]
fn busy_timeout_counts_busy_cycles_and_err_cnt_saturates() {
    let mut link = Link::new(Variant::Sercon816);
    let mut drive = Drive::default();
    open(&mut link, &mut drive);
    link.hs_timeout = 3;
    link.busy_timeout = 7;
    drive.asleep = true;
    link.master_write(4, &[0x0055], 1);
    let mut busy_raised = Vec::new();
    for n in 1..=300u32 {
        let log = link.cycle();
        if log
            .master_cycle
            .raised
            .contains(ScInterrupts::INT_BUSY_TIMEOUT)
        {
            busy_raised.push(n);
        }
        assert!(
            !log.master_cycle
                .raised
                .contains(ScInterrupts::INT_HS_TIMEOUT)
        );
    }
    assert_eq!(busy_raised, vec![7]);
    let m = link.master_sc();
    assert!(m.busy_cnt && m.int_busy_timeout && !m.int_hs_timeout);
    assert_eq!(m.err_cnt, 255, "ERR_CNT stops at 255");

    // A handshake difference after busy cycles restarts the count with BUSY_CNT = 0.
    let mut s = link.slave_sc();
    s.busy_at = false;
    s.hs_at = !link.master_sc().hs_mdt;
    link.set_slave_sc(s);
    link.slave_silent = true;
    let mut m = link.master_sc();
    m.busy_at = false;
    m.hs_at = !m.hs_mdt;
    link.set_master_sc(m);
    link.cycle();
    let m = link.master_sc();
    assert!(!m.busy_cnt);
    assert_eq!(m.err_cnt, 1);
}

// 410B §4.2.4 RECERR "Last transmission was correct (0) or erroneous (1)" in both modes:
// on error nothing is taken from the record.
#[test]
fn corrupted_receptions_set_recerr_and_take_nothing() {
    let mut link = Link::new(Variant::Sercon816);
    let mut drive = Drive::default();
    open(&mut link, &mut drive);
    link.master_write(7, &[0xBEEF, 0xCAFE], 1);
    // First step: element change hold, then the drive sets up the read buffer.
    link.cycle();
    drive.react(&mut link);
    let slave_before = link.slave.clone();
    link.corrupt_mdt = true;
    let log = link.cycle();
    assert!(!log.slave_rx.handshake && log.slave_rx.info_words == 0);
    let s = link.slave_sc();
    assert!(s.recerr);
    // Only RECERR (word 1 bit 7) changed in the slave's RAM.
    let changed: Vec<usize> = (0..link.slave.len())
        .filter(|i| link.slave[*i] != slave_before[*i])
        .collect();
    assert_eq!(changed, vec![usize::from(SLAVE_SC) + 1]);
    assert_eq!(
        link.slave[usize::from(SLAVE_SC) + 1] ^ slave_before[usize::from(SLAVE_SC) + 1],
        0x80
    );

    // A corrupted AT: the master takes nothing (the step stays unacknowledged).
    link.corrupt_at = true;
    let log = link.cycle();
    assert!(log.slave_rx.handshake, "the slave took the step");
    assert!(!log.master_rx.handshake);
    let m = link.master_sc();
    assert!(m.recerr);
    assert_ne!(m.hs_at, m.hs_mdt, "HS_AT not taken from the bad AT");
    // The next good AT acknowledges and clears RECERR on both sides.
    let log = link.cycle();
    assert!(log.master_rx.handshake);
    assert!(!link.master_sc().recerr && !link.slave_sc().recerr);
}

// 410B §4.2.4 INT_SC_ERR "Interrupt due to protocol error", both modes.
#[test]
fn protocol_errors_raise_int_sc_err() {
    // Master: the slave withdraws an acknowledgement without a new MHS.
    let mut link = Link::new(Variant::Sercon816);
    let mut drive = Drive::default();
    open(&mut link, &mut drive);
    let m = link.master_sc();
    let mut at = vec![AT_HOST_BITS | u16::from(!m.hs_mdt), 0];
    let out = on_receive(
        &mut link.master,
        link.variant,
        MASTER_NSV,
        ScMode::Master,
        &at,
        true,
    );
    assert!(out.raised.contains(ScInterrupts::INT_SC_ERR) && out.int_sc);
    assert!(link.master_sc().int_sc_err);
    // The same again is no new error (already unacknowledged).
    at[1] = 9;
    let out = on_receive(
        &mut link.master,
        link.variant,
        MASTER_NSV,
        ScMode::Master,
        &at,
        true,
    );
    assert!(out.raised.is_empty());

    // Slave: the master toggles MHS while the slave is still busy.
    let mut link = Link::new(Variant::Sercon410b);
    // No drive reacts: the slave stays busy after the element change.
    link.master_write(1, &[0x0024], 1);
    link.cycle(); // element change: slave busy
    let s = link.slave_sc();
    let mdt = vec![MDT_HOST_BITS | u16::from(!s.hs_mdt) | 0x0A, 0x0024];
    let out = on_receive(
        &mut link.slave,
        link.variant,
        SLAVE_NSV,
        ScMode::Slave,
        &mdt,
        true,
    );
    assert!(out.raised.contains(ScInterrupts::INT_SC_ERR));
    let s = link.slave_sc();
    assert!(s.int_sc_err && s.busy_at);
    assert_eq!(link.slave_word(5), 0, "nothing taken");
}

// 410B §4.2.4 INT_CMD "Slave has set command modification bit" (AT status bit 5, CMD_AT).
#[test]
fn command_change_bit_raises_int_cmd_once_per_rising_edge() {
    let mut link = Link::new(Variant::Sercon816);
    let mut drive = Drive::default();
    open(&mut link, &mut drive);
    let mut raised = Vec::new();
    for n in 0..6 {
        let mut s = link.slave_sc();
        s.cmd_at = n == 1 || n == 2 || n == 4;
        link.set_slave_sc(s);
        let log = link.cycle();
        assert_eq!(
            log.at[0] & 0x20 != 0,
            s.cmd_at,
            "CMD_AT is status word bit 5"
        );
        if log.master_rx.raised.contains(ScInterrupts::INT_CMD) {
            raised.push(n);
        }
    }
    assert_eq!(raised, vec![1, 4]);
    assert!(link.master_sc().int_cmd);
}

// 816 §2.10.2.2: INT_RSCEND marks the end of service-container work after a receive
// telegram; the 410B has no such interrupt.
#[test]
fn rscend_only_on_the_816() {
    for (variant, expected) in [(Variant::Sercon410b, false), (Variant::Sercon816, true)] {
        let mut link = Link::new(variant);
        let log = link.cycle();
        assert_eq!(log.slave_rx.rscend, expected);
        assert_eq!(log.master_rx.rscend, expected);
        assert!(!log.master_tx.rscend && !log.master_cycle.rscend);
    }
}

// spec-notes "Service containers": buffer positions below offset 5 are the control words;
// data never overwrites them.
#[test]
fn buffer_pointers_below_the_buffer_do_not_overwrite_control_words() {
    let mut link = Link::new(Variant::Sercon816);
    let mut drive = Drive::default();
    open(&mut link, &mut drive);
    drive.elements[7] = vec![0xFFFF, 0xFFFF, 0xFFFF];
    link.master_read(7, 0, 3, 1, true);
    let logs = run(&mut link, &mut drive, 20, |log, _| {
        log.master_raised().contains(ScInterrupts::INT_END_RDBUF)
    });
    assert_eq!(logs.iter().filter(|l| l.master_rx.handshake).count(), 3);
    assert!(logs.iter().all(|l| l.master_rx.info_words == 0));
    let m = link.master_sc();
    assert_eq!(m.pointers.rddatpt, 3);
    assert_eq!(m.err_cnt, 0);
}
