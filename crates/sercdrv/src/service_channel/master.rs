//! The master's service-channel client: requests to drives, carried out in parallel through
//! the service containers, event-driven (no clock is read, nothing blocks).
//!
//! The service channel of one drive carries one transaction at a time (one handshake, MDT
//! control word bits 5–0, sercos-telegrams.md), but the eight service containers (410B
//! §4.2.4; 5H INT_SC_0–7, §4.1) serve eight drives at once. The scheduler hands the oldest
//! pending request of a drive without a running transfer to a free container: first one
//! wired to that drive, else one that can be routed to any drive (a [`ContainerRouter`]
//! then points the drive's data containers at it, NSV in 410B §4.2.2).

use std::collections::VecDeque;

use sercon_regs::ram::service::ScMaster;
use sercon_regs::{IntFlagsHi, ScTimeout, SerconBus, SerconBusExt};
use sercos_wire::address::DriveAddress;
use sercos_wire::time::{Duration, Instant};

use super::container::{BUF, ContainerSlot};
use super::error::{ErrorKind, ServiceChannelError};
use super::request::{Completion, Request, Ticket};
use super::transfer::{Progress, Transfer, clear_interrupts, close};

/// Which drive a master container serves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Wiring {
    /// The data containers of this drive always name this service container (NSV).
    Drive(DriveAddress),
    /// Any drive: the [`ContainerRouter`] connects it before each transfer.
    Any,
}

/// Connects a drive's service info to a service container: whoever owns the RAM layout
/// writes NSV (and SVFL) of the drive's MDT and AT data containers (410B §4.2.2).
pub trait ContainerRouter {
    /// Route the service info of `drive` through container `slot` from now on.
    fn route<B: SerconBus + ?Sized>(
        &mut self,
        bus: &mut B,
        slot: &ContainerSlot,
        drive: DriveAddress,
    );
}

/// No routing: every container is [`Wiring::Drive`], or the layout is fixed elsewhere.
#[derive(Debug, Clone, Copy, Default)]
pub struct FixedRouting;

impl ContainerRouter for FixedRouting {
    fn route<B: SerconBus + ?Sized>(&mut self, _: &mut B, _: &ContainerSlot, _: DriveAddress) {}
}

#[derive(Debug)]
struct Pending {
    ticket: Ticket,
    drive: DriveAddress,
    request: Request,
}

#[derive(Debug)]
struct Active {
    ticket: Ticket,
    drive: DriveAddress,
    request: Request,
    transfer: Transfer,
    deadline: Option<Instant>,
}

#[derive(Debug)]
struct MasterContainer {
    slot: ContainerSlot,
    wiring: Wiring,
    /// The drive routed to it last (for INT_CMD while idle).
    routed: Option<DriveAddress>,
    active: Option<Active>,
}

/// The master's service-channel client over up to eight master-mode service containers.
#[derive(Debug)]
pub struct ServiceChannelMaster<R: ContainerRouter = FixedRouting> {
    containers: Vec<MasterContainer>,
    pending: VecDeque<Pending>,
    next_ticket: u64,
    timeout: Option<Duration>,
    router: R,
    command_changes: Vec<DriveAddress>,
    /// Whether [`ServiceChannelMaster::poll`] reads INT_CMD of containers the host does
    /// not otherwise need to read ([`ServiceChannelMaster::set_watch_commands`]).
    watch_commands: bool,
}

impl ServiceChannelMaster<FixedRouting> {
    /// A client over `containers` (each a slot and which drive it serves), without a time
    /// limit and without routing.
    pub fn new(containers: impl IntoIterator<Item = (ContainerSlot, Wiring)>) -> Self {
        ServiceChannelMaster::with_router(containers, FixedRouting)
    }
}

impl<R: ContainerRouter> ServiceChannelMaster<R> {
    /// A client whose [`Wiring::Any`] containers are connected by `router`. A slot whose
    /// NSV repeats an earlier one is left out (one container, one user).
    pub fn with_router(
        containers: impl IntoIterator<Item = (ContainerSlot, Wiring)>,
        router: R,
    ) -> Self {
        let mut list: Vec<MasterContainer> = Vec::new();
        for (slot, wiring) in containers {
            if list.iter().all(|c| c.slot.nsv() != slot.nsv()) {
                list.push(MasterContainer {
                    slot,
                    wiring,
                    routed: match wiring {
                        Wiring::Drive(drive) => Some(drive),
                        Wiring::Any => None,
                    },
                    active: None,
                });
            }
        }
        ServiceChannelMaster {
            containers: list,
            pending: VecDeque::new(),
            next_ticket: 0,
            timeout: None,
            router,
            command_changes: Vec::new(),
            watch_commands: true,
        }
    }

    /// Gives every request at most `timeout` from the moment it gets a container; `None`
    /// leaves timing to the chip's HS_TIMEOUT / BUSY_TIMEOUT.
    pub fn set_timeout(&mut self, timeout: Option<Duration>) {
        self.timeout = timeout;
    }

    /// Whether [`ServiceChannelMaster::poll`] reads INT_CMD (410B §4.2.4, word 4) of the
    /// containers without a transfer and of those whose transfer does not wait for the host
    /// (on by default). Off, those containers cost no bus access per poll: a command change
    /// is then reported ([`ServiceChannelMaster::take_command_changes`]) only when its
    /// container is read for a transfer (started, or waiting with M_BUSY), so only for a
    /// user who polls procedure commands itself, as [`crate::master::Master`] does.
    pub fn set_watch_commands(&mut self, watch: bool) {
        self.watch_commands = watch;
    }

    /// The router.
    pub fn router_mut(&mut self) -> &mut R {
        &mut self.router
    }

    /// Writes SCPTn of every container and leaves it idle: element 0, M_BUSY = 1, NINFO,
    /// pointers at the buffer (410B §4.2, §4.2.4 master table).
    pub fn init<B: SerconBus + ?Sized>(&mut self, bus: &mut B) {
        for container in &mut self.containers {
            container.active = None;
            let slot = container.slot;
            slot.install(bus);
            let mut m = ScMaster {
                m_busy: true,
                ninfo_write: slot.ninfo(),
                ninfo_read: slot.ninfo(),
                ..ScMaster::default()
            };
            m.pointers.wrdatpt = BUF;
            m.pointers.wrdatlast = BUF;
            m.pointers.rddatpt = BUF;
            m.pointers.rddatlast = BUF;
            slot.store_all(bus, m.to_words());
        }
    }

    /// Writes the chip's service-channel timeouts, in communication cycles (0DH
    /// HS_TIMEOUT / BUSY_TIMEOUT, 410B §4.1; 0 = no timeout, spec-notes).
    pub fn set_chip_timeouts<B: SerconBus + ?Sized>(
        &self,
        bus: &mut B,
        hs_timeout: u8,
        busy_timeout: u8,
    ) {
        bus.write_reg(ScTimeout::new(hs_timeout, busy_timeout));
    }

    /// Queues `request` for `drive`; the completion names the ticket.
    pub fn submit(&mut self, drive: DriveAddress, request: Request) -> Ticket {
        let ticket = Ticket(self.next_ticket);
        self.next_ticket = self.next_ticket.wrapping_add(1);
        self.pending.push_back(Pending {
            ticket,
            drive,
            request,
        });
        ticket
    }

    /// Requests not yet given a container.
    pub fn pending(&self) -> usize {
        self.pending.len()
    }

    /// Requests running in a container.
    pub fn running(&self) -> usize {
        self.containers
            .iter()
            .filter(|c| c.active.is_some())
            .count()
    }

    /// Whether nothing is queued or running.
    pub fn is_idle(&self) -> bool {
        self.pending.is_empty() && self.running() == 0
    }

    /// The earliest time limit of a running request (when to poll at the latest).
    pub fn next_deadline(&self) -> Option<Instant> {
        self.containers
            .iter()
            .filter_map(|c| c.active.as_ref().and_then(|a| a.deadline))
            .min()
    }

    /// Drives whose AT showed a new command change bit (410B §4.2.4 INT_CMD; status word
    /// bit 5, sercos-facts.md "Procedure commands") since the last call.
    pub fn take_command_changes(&mut self) -> Vec<DriveAddress> {
        std::mem::take(&mut self.command_changes)
    }

    /// Handles the service-container interrupts `int_sc` (5H bits INT_SC_0–7, 410B §4.1),
    /// clears them in 5H (write 1 to clear, ERRATA "410B 4H/5H"), and polls.
    pub fn on_interrupt<B: SerconBus + ?Sized>(
        &mut self,
        bus: &mut B,
        int_sc: IntFlagsHi,
        now: Instant,
    ) -> Vec<Completion> {
        let mine = self
            .containers
            .iter()
            .filter_map(|c| IntFlagsHi::int_sc(c.slot.nsv()))
            .fold(IntFlagsHi::empty(), |acc, bit| acc | bit);
        let to_clear = int_sc & mine;
        if !to_clear.is_empty() {
            bus.clear_int_hi(to_clear);
        }
        self.poll(bus, now)
    }

    /// Looks at every container: finishes, continues or times out running transfers, then
    /// starts pending requests in free containers. Call it on INT_SC_n or once per cycle.
    pub fn poll<B: SerconBus + ?Sized>(&mut self, bus: &mut B, now: Instant) -> Vec<Completion> {
        let mut done = Vec::new();
        for container in &mut self.containers {
            service_container(
                container,
                bus,
                now,
                self.watch_commands,
                &mut self.command_changes,
                &mut done,
            );
        }
        self.schedule(bus, now, &mut done);
        done
    }

    /// Gives pending requests free containers, oldest first, one transfer per drive.
    fn schedule<B: SerconBus + ?Sized>(
        &mut self,
        bus: &mut B,
        now: Instant,
        done: &mut Vec<Completion>,
    ) {
        let mut waiting = VecDeque::new();
        let mut blocked: Vec<DriveAddress> = self
            .containers
            .iter()
            .filter_map(|c| c.active.as_ref().map(|a| a.drive))
            .collect();
        while let Some(pending) = self.pending.pop_front() {
            if blocked.contains(&pending.drive) {
                waiting.push_back(pending);
                continue;
            }
            let ninfo = self.ninfo_for(pending.drive);
            let transfer = match Transfer::plan(&pending.request, ninfo) {
                Ok(transfer) => transfer,
                Err(kind) => {
                    done.push(failed(&pending, pending.request.element(), kind));
                    continue;
                }
            };
            let Some(index) = self.free_container(pending.drive) else {
                // Keep the drive's order: its later requests wait too.
                blocked.push(pending.drive);
                waiting.push_back(pending);
                continue;
            };
            blocked.push(pending.drive);
            if let Some(container) = self.containers.get_mut(index) {
                if container.wiring == Wiring::Any {
                    self.router.route(bus, &container.slot, pending.drive);
                }
                container.routed = Some(pending.drive);
                start(
                    container,
                    bus,
                    now,
                    self.timeout,
                    pending,
                    transfer,
                    &mut self.command_changes,
                );
            }
        }
        self.pending = waiting;
    }

    /// NINFO of the container a request of `drive` would get (1 if none).
    fn ninfo_for(&self, drive: DriveAddress) -> u8 {
        self.free_container(drive)
            .and_then(|i| self.containers.get(i))
            .map_or(1, |c| c.slot.ninfo().count())
    }

    fn free_container(&self, drive: DriveAddress) -> Option<usize> {
        let free = |c: &MasterContainer| c.active.is_none();
        self.containers
            .iter()
            .position(|c| free(c) && c.wiring == Wiring::Drive(drive))
            .or_else(|| {
                self.containers
                    .iter()
                    .position(|c| free(c) && c.wiring == Wiring::Any)
            })
    }
}

fn failed(pending: &Pending, element: sercos_wire::idn::Element, kind: ErrorKind) -> Completion {
    Completion {
        ticket: pending.ticket,
        drive: pending.drive,
        idn: pending.request.idn(),
        element: pending.request.element(),
        result: Err(ServiceChannelError {
            drive: pending.drive,
            idn: pending.request.idn(),
            element,
            kind,
        }),
    }
}

/// Records INT_CMD of a container (410B §4.2.4) for the drive it serves.
fn note_command_change(container: &MasterContainer, m: &ScMaster, changes: &mut Vec<DriveAddress>) {
    if m.int_cmd {
        if let Some(drive) = container.routed {
            changes.push(drive);
        }
    }
}

fn start<B: SerconBus + ?Sized>(
    container: &mut MasterContainer,
    bus: &mut B,
    now: Instant,
    timeout: Option<Duration>,
    pending: Pending,
    mut transfer: Transfer,
    changes: &mut Vec<DriveAddress>,
) {
    let slot = container.slot;
    let m = slot.master(bus);
    note_command_change(container, &m, changes);
    transfer.load(&slot, bus, m);
    container.active = Some(Active {
        ticket: pending.ticket,
        drive: pending.drive,
        request: pending.request,
        transfer,
        deadline: timeout.map(|t| now.saturating_add(t)),
    });
}

/// Word 4 of a master container with INT_CMD (4.12, 410B §4.2.4) cleared, if it was set.
fn without_int_cmd(word4: u16) -> Option<u16> {
    let mut m = ScMaster::from_words([0, 0, 0, 0, word4]);
    if !m.int_cmd {
        return None;
    }
    m.int_cmd = false;
    let [_, _, _, _, cleared] = m.to_words();
    Some(cleared)
}

/// Looks at INT_CMD alone (word 4, 410B §4.2.4): notes a command change of the drive the
/// container serves and clears the bit.
fn watch_int_cmd<B: SerconBus + ?Sized>(
    container: &MasterContainer,
    bus: &mut B,
    changes: &mut Vec<DriveAddress>,
) {
    let slot = container.slot;
    let word4 = slot.control_word(bus, 4);
    if let Some(cleared) = without_int_cmd(word4) {
        if let Some(drive) = container.routed {
            changes.push(drive);
        }
        slot.write_control_word(bus, 4, cleared);
    }
}

/// One container's turn in [`ServiceChannelMaster::poll`]: what the host must read of it
/// and no more (spec-notes "Master accesses per cycle").
///
/// * Idle (no transfer): nothing happens in it but INT_CMD (410B §4.2.4: the chip raises
///   it when the slave sets the command modification bit); word 4 is read for it when
///   `watch_commands`, else the container is not read at all.
/// * Running: word 0 tells whether the chip waits for the host (M_BUSY, 410B §4.2.4:
///   "Service container waits for interaction of microprocessor"); only then are words
///   1-4 read. While it does not, word 4 is read for INT_CMD when `watch_commands`.
fn service_container<B: SerconBus + ?Sized>(
    container: &mut MasterContainer,
    bus: &mut B,
    now: Instant,
    watch_commands: bool,
    changes: &mut Vec<DriveAddress>,
    done: &mut Vec<Completion>,
) {
    let slot = container.slot;
    let Some(mut active) = container.active.take() else {
        if watch_commands {
            watch_int_cmd(container, bus, changes);
        }
        return;
    };
    let word0 = slot.control_word(bus, 0);
    // 410B §4.2.4 M_BUSY: the chip waits for the microprocessor after an interrupt.
    let progress = if ScMaster::from_words([word0, 0, 0, 0, 0]).m_busy {
        let mut m = slot.master_after(bus, word0);
        note_command_change(container, &m, changes);
        // Noted once: the words the transfer writes back carry it cleared.
        m.int_cmd = false;
        active.transfer.on_event(&slot, bus, m)
    } else {
        if watch_commands {
            watch_int_cmd(container, bus, changes);
        }
        Progress::Running
    };
    let progress = match progress {
        Progress::Running if active.deadline.is_some_and(|d| now >= d) => {
            Progress::Done(Err((active.transfer.element(), ErrorKind::Timeout)))
        }
        other => other,
    };
    match progress {
        Progress::Running => container.active = Some(active),
        Progress::Done(result) => {
            // Close: element 0 and M_BUSY (read again: on_event may have written).
            let now_m = slot.master(bus);
            let mut closing = now_m;
            clear_interrupts(&mut closing);
            close(&slot, bus, closing);
            done.push(Completion {
                ticket: active.ticket,
                drive: active.drive,
                idn: active.request.idn(),
                element: active.request.element(),
                result: result.map_err(|(element, kind)| ServiceChannelError {
                    drive: active.drive,
                    idn: active.request.idn(),
                    element,
                    kind,
                }),
            });
        }
    }
}
