//! Slave mode (SCMASTER = 0): the container takes the MDT's service bits and info words
//! and answers in the AT (410B §4.2.4, slave table).

use sercon_regs::ram::service::ScSlave;

use super::buffer::{copy_in, copy_out};
use super::container_ram::ContainerRam;
use super::outcome::{ScInterrupts, ScOutcome};
use super::record_bits::{AtService, MdtService};

/// Fills the AT record: HS_AT, BUSY_AT, ERR_AT, CMD_AT and NINFO_WRITE words of the
/// write buffer. The container's words are not changed.
pub(super) fn transmit(ram: &mut ContainerRam<'_>, record: &mut [u16]) -> ScOutcome {
    let s = ScSlave::from_words(ram.controls());
    let mut out = ScOutcome::default();
    if let Some((first, info)) = record.split_first_mut() {
        // 410B §4.2.4 slave word 0 bits 0-3 go to AT status word bits 0-2 and 5 (ERRATA
        // "service info in a container": CMD_AT is status word bit 5).
        *first = AtService {
            ahs: s.hs_at,
            busy: s.busy_at,
            error: s.err_at,
            command_change: s.cmd_at,
        }
        .put_into(*first);
        // 410B §4.2.4 NINFO_WRITE, WRDATPT/WRDATLAST: the write buffer holds what the
        // slave sends (spec-notes: write buffer = transmitted words in both modes).
        out.info_words = copy_out(s.pointers.write_window(), ram, s.ninfo_write.count(), info);
    }
    out.ram_accesses = ram.accesses();
    out
}

/// Takes the MDT record's service bits and processes a new or held step.
pub(super) fn receive(ram: &mut ContainerRam<'_>, record: &[u16], ok: bool) -> ScOutcome {
    let before = ram.controls();
    let mut s = ScSlave::from_words(before);
    let mut out = ScOutcome::default();

    match record.split_first() {
        Some((control, info)) if ok => {
            // 410B §4.2.4 RECERR: last transmission was correct (0).
            s.recerr = false;
            take_mdt(ram, &mut s, MdtService::from_word(*control), info, &mut out);
        }
        _ => {
            // 410B §4.2.4 RECERR: last transmission was erroneous (1); nothing is taken.
            s.recerr = true;
        }
    }

    ram.store_controls(before, s.to_words());
    out.ram_accesses = ram.accesses();
    out
}

fn take_mdt(
    ram: &mut ContainerRam<'_>,
    s: &mut ScSlave,
    mdt: MdtService,
    info: &[u16],
    out: &mut ScOutcome,
) {
    let previous_mhs = s.hs_mdt;
    let previous_end = s.end_mdt;
    let toggled = mdt.mhs != previous_mhs;
    // 410B §4.2.4 slave word 1: HS_MDT, L/S_MDT, END_MDT, ELEM_MDT mirror the MDT.
    s.hs_mdt = mdt.mhs;
    s.ls_mdt = mdt.write;
    s.end_mdt = mdt.last;
    s.elem_mdt = mdt.element;

    if toggled && (s.hs_at != previous_mhs || s.busy_at) {
        // 410B §4.2.4 INT_SC_ERR: protocol error — the master started a new step before
        // the last one was acknowledged. The container holds BUSY_AT and takes nothing
        // (spec-notes).
        s.int_sc_err = true;
        s.busy_at = true;
        out.raise(ScInterrupts::INT_SC_ERR);
        return;
    }
    // A step is pending while AHS differs from MHS; BUSY_AT holds it for the
    // microprocessor (410B §4.2.4 BUSY_AT: "also waiting for microprocessor interaction").
    if s.hs_at == s.hs_mdt || s.busy_at {
        return;
    }

    let element = mdt.element & 7;
    if element != s.elem || mdt.write != s.ls || (toggled && previous_end) {
        // 410B §4.2.4 INT_ELEM_CHANGE: master has modified data element or read/write (or
        // starts a new transmission after END_MDT, spec-notes). ELEM and L/S become the
        // present transmission; BUSY_AT holds until the microprocessor has set up the
        // buffers and cleared it. The step stays pending and is taken afterwards.
        s.elem = element;
        s.ls = mdt.write;
        s.int_elem_change = true;
        s.busy_at = true;
        out.raise(ScInterrupts::INT_ELEM_CHANGE);
        return;
    }

    if s.ls {
        // Write by the master: NINFO_READ info words go to the read buffer at RDDATPT.
        let window = s.pointers.read_window();
        let count = s.ninfo_read.count();
        out.info_words = copy_in(window, ram, count, info);
        s.pointers.rddatpt = window.advanced(count);
        // 410B §4.2.4 HS_AT: the step is answered (AHS = MHS).
        s.hs_at = s.hs_mdt;
        out.handshake = true;
        if window.is_final(count) {
            // 410B §4.2.4 INT_END_RDBUF; BUSY_AT holds until the buffer is emptied.
            s.int_end_rdbuf = true;
            s.busy_at = true;
            out.raise(ScInterrupts::INT_END_RDBUF);
        }
        if mdt.last {
            // 410B §4.2.4 INT_END_MDT: master reports end via END_MDT; BUSY_AT holds so the
            // microprocessor can check the data and report an error in this step.
            s.int_end_mdt = true;
            s.busy_at = true;
            out.raise(ScInterrupts::INT_END_MDT);
        }
    } else {
        // Read by the master. A fresh step of the same transmission means the master has
        // taken the words offered so far: WRDATPT moves on by NINFO_WRITE.
        if toggled {
            s.pointers.wrdatpt = s.pointers.write_window().advanced(s.ninfo_write.count());
        }
        if s.pointers.write_window().is_exhausted() {
            // 410B §4.2.4 INT_END_WRBUF: end of write buffer is reached; BUSY_AT holds
            // until the microprocessor refills it (spec-notes).
            s.int_end_wrbuf = true;
            s.busy_at = true;
            out.raise(ScInterrupts::INT_END_WRBUF);
            return;
        }
        // 410B §4.2.4 HS_AT: answered; the AT carries the words at WRDATPT.
        s.hs_at = s.hs_mdt;
        out.handshake = true;
        if mdt.last {
            // 410B §4.2.4 INT_END_MDT (no hold on a read: nothing to check).
            s.int_end_mdt = true;
            out.raise(ScInterrupts::INT_END_MDT);
        }
    }
}
