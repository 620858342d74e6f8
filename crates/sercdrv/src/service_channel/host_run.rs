//! The host-run service channel: service containers kept in the host's memory and run by
//! the host once per cycle with the chip's master-mode rules (410B §4.2.4, master table), for
//! drives whose MDT records no service container serves (one MDT transmit container for every
//! record: no per-drive SVFL/NSV, 410B §4.2.2; spec-notes "Master DMA layout").
//!
//! The requests, transfers and errors are the chip-run channel's own: each bank of eight
//! drives is a [`ServiceChannelMaster`] over eight containers in a [`SoftRam`], so the
//! scheduler and [`Transfer`](super::transfer) drive them unchanged. Per cycle the host
//! hands every drive's AT service info (status word, info word) to [`HostRunChannel::receive`]
//! and takes the MDT service info (control word bits 5-0, info word) from
//! [`HostRunChannel::transmit`]; between the two, [`HostRunChannel::poll`] finishes and
//! starts transfers, as the host does after INT_SC_n with the chip's containers.

use sercon_regs::SerconBus;
use sercon_regs::Variant;
use sercon_regs::ram::service::{SC_CONTROL_WORDS, ScMaster};
use sercon_regs::ram::service_rules::{ScAtBits, ScBufferWindow};
use sercos_wire::address::DriveAddress;
use sercos_wire::telegram::{ControlWord, StatusWord};
use sercos_wire::time::{Duration, Instant};

use super::container::{ContainerSlot, SlotError};
use super::master::{FixedRouting, ServiceChannelMaster, Wiring};
use super::request::{Completion, Request, Ticket};

/// Containers per bank: NSV is 3 bits (410B §4.2: SCPT0-7).
const BANK_CONTAINERS: usize = 8;

/// First word of the containers in a bank's RAM, after the 11 fixed words (410B §4.2).
const FIRST_CONTAINER: u16 = 16;

/// Tickets of the host-run channel have this bit set, so they never equal the chip-run
/// channel's (which count from 0).
const TICKET_TAG: u64 = 1 << 63;

/// A word array that stands for the dual-port RAM of one bank of host-run containers; its
/// registers read 0 and ignore writes (only the containers' RAM words are used).
#[derive(Debug, Clone)]
pub struct SoftRam {
    words: Vec<u16>,
}

impl SoftRam {
    /// A zeroed RAM of `variant`'s size.
    pub fn new(variant: Variant) -> SoftRam {
        SoftRam {
            words: vec![0; usize::from(variant.ram_words())],
        }
    }
}

impl SerconBus for SoftRam {
    fn read_register(&mut self, _address: u8) -> u16 {
        0
    }

    fn write_register(&mut self, _address: u8, _value: u16) {}

    fn read_ram(&mut self, address: u16) -> u16 {
        self.words.get(usize::from(address)).copied().unwrap_or(0)
    }

    fn write_ram(&mut self, address: u16, value: u16) {
        if let Some(w) = self.words.get_mut(usize::from(address)) {
            *w = value;
        }
    }
}

#[derive(Debug)]
struct Bank {
    ram: SoftRam,
    sc: ServiceChannelMaster<FixedRouting>,
    /// (drive, its container) of this bank.
    slots: Vec<(DriveAddress, ContainerSlot)>,
}

/// The host-run service channel of a set of drives, eight per bank, every drive with its own
/// container (no routing: all drives can run a transfer at once).
#[derive(Debug)]
pub struct HostRunChannel {
    banks: Vec<Bank>,
    /// Bank and slot of each drive by address (one look-up per drive and cycle).
    places: Vec<Option<(usize, ContainerSlot)>>,
    hs_timeout: u8,
    busy_timeout: u8,
}

impl HostRunChannel {
    /// Containers of `buffer_words` words for `drives` (the order of the banks), with the
    /// time limit `timeout` per request (as [`ServiceChannelMaster::set_timeout`]).
    pub fn new(
        variant: Variant,
        drives: &[DriveAddress],
        buffer_words: u16,
        timeout: Option<Duration>,
    ) -> Result<HostRunChannel, SlotError> {
        let stride = (SC_CONTROL_WORDS as u16).saturating_add(buffer_words);
        let mut banks = Vec::new();
        for chunk in drives.chunks(BANK_CONTAINERS) {
            let mut slots = Vec::new();
            for (nsv, &drive) in (0u8..).zip(chunk) {
                let address = FIRST_CONTAINER.saturating_add(stride.saturating_mul(u16::from(nsv)));
                slots.push((
                    drive,
                    ContainerSlot::new(variant, nsv, address, buffer_words)?,
                ));
            }
            let mut ram = SoftRam::new(variant);
            let mut sc = ServiceChannelMaster::new(
                slots
                    .iter()
                    .map(|&(drive, slot)| (slot, Wiring::Drive(drive))),
            );
            sc.set_timeout(timeout);
            sc.init(&mut ram);
            banks.push(Bank { ram, sc, slots });
        }
        // The first container of a drive serves it (addresses 1-254, sercos-telegrams.md).
        let mut places: Vec<Option<(usize, ContainerSlot)>> = vec![None; 256];
        for (i, bank) in banks.iter().enumerate() {
            for &(drive, slot) in &bank.slots {
                if let Some(place) = places.get_mut(usize::from(drive.get())) {
                    place.get_or_insert((i, slot));
                }
            }
        }
        Ok(HostRunChannel {
            banks,
            places,
            hs_timeout: 0,
            busy_timeout: 0,
        })
    }

    /// HS_TIMEOUT / BUSY_TIMEOUT in cycles, as the chip takes them from 0DH (410B §4.1; 0 =
    /// no timeout).
    pub fn set_timeouts(&mut self, hs_timeout: u8, busy_timeout: u8) {
        self.hs_timeout = hs_timeout;
        self.busy_timeout = busy_timeout;
    }

    /// Whether `drive` has a host-run container.
    pub fn serves(&self, drive: DriveAddress) -> bool {
        self.locate(drive).is_some()
    }

    fn locate(&self, drive: DriveAddress) -> Option<(usize, ContainerSlot)> {
        self.places.get(usize::from(drive.get())).copied().flatten()
    }

    /// Queues `request` for `drive`; `None` if the drive has no host-run container.
    pub fn submit(&mut self, drive: DriveAddress, request: Request) -> Option<Ticket> {
        let (index, _) = self.locate(drive)?;
        let bank = self.banks.get_mut(index)?;
        let inner = bank.sc.submit(drive, request);
        Some(outer_ticket(index, inner))
    }

    /// Whether nothing is queued or running.
    pub fn is_idle(&self) -> bool {
        self.banks.iter().all(|b| b.sc.is_idle())
    }

    /// The earliest time limit of a running request.
    pub fn next_deadline(&self) -> Option<Instant> {
        self.banks.iter().filter_map(|b| b.sc.next_deadline()).min()
    }

    /// Drives whose AT showed a new command change bit since the last call.
    pub fn take_command_changes(&mut self) -> Vec<DriveAddress> {
        self.banks
            .iter_mut()
            .flat_map(|b| b.sc.take_command_changes())
            .collect()
    }

    /// Finishes, continues or times out the running transfers and starts pending ones, as
    /// after the containers' interrupts (410B §4.2.4 M_BUSY: the host's turn).
    pub fn poll(&mut self, now: Instant) -> Vec<Completion> {
        let mut done = Vec::new();
        for (index, bank) in self.banks.iter_mut().enumerate() {
            for mut c in bank.sc.poll(&mut bank.ram, now) {
                c.ticket = outer_ticket(index, c.ticket);
                done.push(c);
            }
        }
        done
    }

    /// The AT service info of `drive`: `Some([status word, info words…])` received without
    /// error, `None` errored or missing (410B §4.2.4 RECERR).
    pub fn receive(&mut self, drive: DriveAddress, record: Option<&[u16]>) {
        let Some((index, slot)) = self.locate(drive) else {
            return;
        };
        let Some(bank) = self.banks.get_mut(index) else {
            return;
        };
        let mut m = slot.master(&mut bank.ram);
        match record {
            Some(record) => {
                // 410B §4.2.4 RECERR: last transmission was correct.
                m.recerr = false;
                take_at(&slot, &mut bank.ram, &mut m, record);
            }
            // 410B §4.2.4 RECERR: last transmission was erroneous; nothing is taken.
            None => m.recerr = true,
        }
        slot.store_all(&mut bank.ram, m.to_words());
    }

    /// Fills `record` (MDT control word, then info words) of `drive` for the next MDT: counts
    /// the cycle of an unacknowledged step, starts the next step when the last one is
    /// acknowledged and the host is not awaited, and puts the service bits and info words in
    /// (410B §4.2.4 master table). Bits 15-6 of the control word are kept.
    pub fn transmit(&mut self, drive: DriveAddress, record: &mut [u16]) {
        let Some((index, slot)) = self.locate(drive) else {
            return;
        };
        let (hs_timeout, busy_timeout) = (self.hs_timeout, self.busy_timeout);
        let Some(bank) = self.banks.get_mut(index) else {
            return;
        };
        let mut m = slot.master(&mut bank.ram);
        // 410B §4.2.4 ERR_CNT/BUSY_CNT, 410B §4.1 0DH: the cycle of an unacknowledged step
        // counts (the flags and M_BUSY are the host's to see; no interrupt line here).
        let _ = m.count_cycle(hs_timeout, busy_timeout);
        // 410B §4.2.4 M_BUSY, HS_MDT, SETEND: the next step starts when the last one is
        // acknowledged and the host is not awaited.
        m.start_step();
        if let Some((first, info)) = record.split_first_mut() {
            // 410B §4.2.4 HS_MDT, L/S_MDT, END_MDT, ELEM_MDT → MDT control word bits 5-0.
            *first = (*first & !MDT_SERVICE_BITS)
                | u16::from(m.hs_mdt)
                | u16::from(m.ls_mdt) << 1
                | u16::from(m.end_mdt) << 2
                | (u16::from(m.elem_mdt) & 7) << 3;
            // NINFO_WRITE info words from the write buffer at WRDATPT (0 past WRDATLAST).
            let window = m.pointers.write_window();
            for (slot_word, position) in
                info.iter_mut().zip(window.positions(m.ninfo_write.count()))
            {
                *slot_word = position.map_or(0, |p| buffer_word(&slot, &mut bank.ram, p));
            }
        }
        slot.store_all(&mut bank.ram, m.to_words());
    }
}

fn outer_ticket(bank: usize, inner: Ticket) -> Ticket {
    Ticket(TICKET_TAG | ((bank as u64) << 40) | (inner.0 & ((1 << 40) - 1)))
}

/// MDT control word bits 5-0 (sercos-telegrams.md; ERRATA "service info in a container").
const MDT_SERVICE_BITS: u16 = ControlWord::MHS
    | ControlWord::WRITE
    | ControlWord::LAST_TRANSMISSION
    | ControlWord::DATA_BLOCK_ELEMENT;

/// Buffer positions start after the control words; below they read 0 and take nothing.
fn buffer_word(slot: &ContainerSlot, ram: &mut SoftRam, position: u8) -> u16 {
    if usize::from(position) < SC_CONTROL_WORDS {
        0
    } else {
        slot.buffer_word(ram, position)
    }
}

fn store_info(
    slot: &ContainerSlot,
    ram: &mut SoftRam,
    window: ScBufferWindow,
    count: u8,
    info: &[u16],
) {
    for (word, position) in info.iter().zip(window.positions(count)) {
        if let Some(p) = position.filter(|p| usize::from(*p) >= SC_CONTROL_WORDS) {
            slot.write_buffer(ram, p, &[*word]);
        }
    }
}

/// Takes the AT's service bits and, on an acknowledged step, its info words (410B §4.2.4
/// master table, as the chip's container does).
fn take_at(slot: &ContainerSlot, ram: &mut SoftRam, m: &mut ScMaster, record: &[u16]) {
    let Some((&status, info)) = record.split_first() else {
        m.recerr = true;
        return;
    };
    // 410B §4.2.4 master table, the rules shared with the chip's container (sercon-regs);
    // HS_AT, BUSY_AT, ERR_AT, CMD_AT from AT status word bits 0, 1, 2, 5.
    let taken = m.take_at(ScAtBits {
        ahs: status & StatusWord::AHS != 0,
        busy: status & StatusWord::BUSY != 0,
        error: status & StatusWord::SERVICE_CHANNEL_ERROR != 0,
        command_change: status & StatusWord::COMMAND_CHANGE != 0,
    });
    if let Some((window, count)) = taken.info_to {
        store_info(slot, ram, window, count, info);
    }
}
