//! More drives than service containers: the eight containers (410B §4.2 SCPT0-7) are shared,
//! each routed to one drive at a time before a transfer ([`ContainerRouter`]).
//!
//! The router writes SVFL and NSV of the drive's phase 3-4 data containers (410B §4.2.2:
//! "SVFL: the data block uses a service container", NSV its number); the drive that had the
//! container before loses it (SVFL = 0). In phases 1-2 the master points its single MDT and
//! AT containers at the container of the addressed drive itself ([`MasterRouter::nsv_of`]).

use sercon_regs::SerconBus;
use sercon_regs::ram::container::ContainerControl;
use sercos_wire::address::DriveAddress;

use crate::service_channel::{ContainerRouter, ContainerSlot};

/// Service containers of the chip (410B §4.2: SCPT0-7).
pub(crate) const CONTAINERS: usize = 8;

/// Which drive each container serves, and where the drives' phase 3-4 data containers are.
#[derive(Debug, Clone, Default)]
pub(crate) struct MasterRouter {
    /// NSV → the drive routed to it last.
    routed: [Option<DriveAddress>; CONTAINERS],
    /// The phase 3-4 data containers (MDT, AT control word addresses) of each drive, once
    /// the cyclic block is laid out.
    cyclic: Vec<(DriveAddress, u16, u16)>,
}

impl MasterRouter {
    /// The container routed to `drive`, if any.
    pub(crate) fn nsv_of(&self, drive: DriveAddress) -> Option<u8> {
        self.routed
            .iter()
            .position(|r| *r == Some(drive))
            .and_then(|i| u8::try_from(i).ok())
    }

    /// The phase 3-4 data containers of the drives; the routes in effect are written into
    /// them (SVFL = 1 and NSV for a routed drive, SVFL = 0 for the others).
    pub(crate) fn set_cyclic<B: SerconBus + ?Sized>(
        &mut self,
        bus: &mut B,
        cyclic: Vec<(DriveAddress, u16, u16)>,
    ) {
        self.cyclic = cyclic;
        for (drive, mdt, at) in self.cyclic.clone() {
            let nsv = self.nsv_of(drive);
            write_route(bus, mdt, nsv);
            write_route(bus, at, nsv);
        }
    }

    fn containers_of(&self, drive: DriveAddress) -> Option<(u16, u16)> {
        self.cyclic
            .iter()
            .find(|(d, _, _)| *d == drive)
            .map(|&(_, mdt, at)| (mdt, at))
    }
}

impl ContainerRouter for MasterRouter {
    fn route<B: SerconBus + ?Sized>(
        &mut self,
        bus: &mut B,
        slot: &ContainerSlot,
        drive: DriveAddress,
    ) {
        let nsv = slot.nsv();
        let index = usize::from(nsv);
        let Some(current) = self.routed.get(index).copied() else {
            return;
        };
        if current == Some(drive) {
            return;
        }
        // The drive that had this container gives it up: its records carry no service
        // info from now on (410B §4.2.2 SVFL = 0).
        if let Some((mdt, at)) = current.and_then(|d| self.containers_of(d)) {
            write_route(bus, mdt, None);
            write_route(bus, at, None);
        }
        for r in &mut self.routed {
            if *r == Some(drive) {
                *r = None;
            }
        }
        if let Some(r) = self.routed.get_mut(index) {
            *r = Some(drive);
        }
        if let Some((mdt, at)) = self.containers_of(drive) {
            write_route(bus, mdt, Some(nsv));
            write_route(bus, at, Some(nsv));
        }
    }
}

/// SVFL and NSV of the data container at `control` (410B §4.2.2, control word 0).
fn write_route<B: SerconBus + ?Sized>(bus: &mut B, control: u16, nsv: Option<u8>) {
    let mut c = ContainerControl::from_word(bus.read_ram(control));
    c.svfl = nsv.is_some();
    c.nsv = nsv.unwrap_or(0);
    bus.write_ram(control, c.to_word());
}
