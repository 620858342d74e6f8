//! Master mode (SCMASTER = 1): the container sends the MDT's service bits and info words
//! and takes the AT's (410B §4.2.4, master table).

use sercon_regs::ram::service::ScMaster;
use sercon_regs::ram::service_rules::{ScAtBits, ScAtInterrupt, ScStepTimeout};

use super::buffer::{copy_in, copy_out};
use super::container_ram::ContainerRam;
use super::outcome::{ScInterrupts, ScOutcome};
use super::record_bits::{AtService, MdtService};

/// Fills the MDT record; starts a new step first if the last one is acknowledged and
/// the microprocessor is not awaited.
pub(super) fn transmit(ram: &mut ContainerRam<'_>, record: &mut [u16]) -> ScOutcome {
    let before = ram.controls();
    let mut m = ScMaster::from_words(before);
    // 410B §4.2.4 M_BUSY, HS_MDT, SETEND: a new step starts when the last one is
    // acknowledged and the microprocessor is not awaited (sercon-regs `start_step`).
    let mut out = ScOutcome {
        handshake: m.start_step(),
        ..ScOutcome::default()
    };

    if let Some((first, info)) = record.split_first_mut() {
        // 410B §4.2.4 HS_MDT, L/S_MDT, END_MDT, ELEM_MDT go to MDT control word bits 5-0.
        *first = MdtService {
            mhs: m.hs_mdt,
            write: m.ls_mdt,
            last: m.end_mdt,
            element: m.elem_mdt,
        }
        .put_into(*first);
        // 410B §4.2.4 NINFO_WRITE, WRDATPT/WRDATLAST: the info words come from the
        // write buffer at its present position.
        out.info_words = copy_out(m.pointers.write_window(), ram, m.ninfo_write.count(), info);
    }

    ram.store_controls(before, m.to_words());
    out.ram_accesses = ram.accesses();
    out
}

/// Takes the AT record's service bits and, on an acknowledged step, its info words.
pub(super) fn receive(ram: &mut ContainerRam<'_>, record: &[u16], ok: bool) -> ScOutcome {
    let before = ram.controls();
    let mut m = ScMaster::from_words(before);
    let mut out = ScOutcome::default();

    match record.split_first() {
        Some((status, info)) if ok => {
            // 410B §4.2.4 RECERR: last transmission was correct (0).
            m.recerr = false;
            take_at(ram, &mut m, AtService::from_word(*status), info, &mut out);
        }
        _ => {
            // 410B §4.2.4 RECERR: last transmission was erroneous (1); nothing is taken.
            m.recerr = true;
        }
    }

    ram.store_controls(before, m.to_words());
    out.ram_accesses = ram.accesses();
    out
}

fn take_at(
    ram: &mut ContainerRam<'_>,
    m: &mut ScMaster,
    at: AtService,
    info: &[u16],
    out: &mut ScOutcome,
) {
    // 410B §4.2.4 master table, the rules shared with a host-run container (sercon-regs).
    let taken = m.take_at(ScAtBits {
        ahs: at.ahs,
        busy: at.busy,
        error: at.error,
        command_change: at.command_change,
    });
    if taken.int_cmd {
        out.raise(ScInterrupts::INT_CMD);
    }
    if taken.handshake {
        out.handshake = true;
    }
    if let Some(raised) = taken.raised {
        out.raise(match raised {
            ScAtInterrupt::ScErr => ScInterrupts::INT_SC_ERR,
            ScAtInterrupt::Err => ScInterrupts::INT_ERR,
            ScAtInterrupt::EndWrbuf => ScInterrupts::INT_END_WRBUF,
            ScAtInterrupt::EndRdbuf => ScInterrupts::INT_END_RDBUF,
        });
    }
    if let Some((window, count)) = taken.info_to {
        out.info_words = copy_in(window, ram, count, info);
    }
}

/// Counts one communication cycle of an unacknowledged step (ERR_CNT, BUSY_CNT) and
/// raises the timeouts of 0DH.
pub(super) fn cycle(ram: &mut ContainerRam<'_>, hs_timeout: u8, busy_timeout: u8) -> ScOutcome {
    let before = ram.controls();
    let mut m = ScMaster::from_words(before);
    let mut out = ScOutcome::default();

    // 410B §4.2.4 ERR_CNT/BUSY_CNT and 410B §4.1 0DH HS_TIMEOUT/BUSY_TIMEOUT: counted by
    // sercon-regs `count_cycle`, which also sets the flag and M_BUSY.
    match m.count_cycle(hs_timeout, busy_timeout) {
        Some(ScStepTimeout::Handshake) => out.raise(ScInterrupts::INT_HS_TIMEOUT),
        Some(ScStepTimeout::Busy) => out.raise(ScInterrupts::INT_BUSY_TIMEOUT),
        None => {}
    }

    ram.store_controls(before, m.to_words());
    out.ram_accesses = ram.accesses();
    out
}
