//! SERCDRV's service channel: the master's client and the slave's server over the
//! SERCON's service containers (410B §4.2.4; 5H INT_SC_0–7, 0DH HS_TIMEOUT / BUSY_TIMEOUT,
//! 410B §4.1).
//!
//! Both sides are event-driven and generic over [`SerconBus`](sercon_regs::SerconBus):
//! call them on the container interrupt or once per cycle with the current
//! [`Instant`](sercos_wire::time::Instant); they never block and never read a clock.
//!
//! * [`ServiceChannelMaster`]: `submit(drive, Request) -> Ticket`, then
//!   `poll(bus, now)` / `on_interrupt(bus, int_sc, now)` return [`Completion`]s. Reads and
//!   writes of every element (variable-length data included), procedure commands
//!   ([`Request::set_command`], [`Request::command_status`], [`Request::cancel_command`],
//!   [`ServiceChannelMaster::take_command_changes`]), the drive's error codes as
//!   [`ServiceError`](sercos_wire::service_error::ServiceError) inside a
//!   [`ServiceChannelError`] naming drive, IDN and element, the chip's timeouts and a time
//!   limit, and up to eight drives at once.
//! * [`ServiceChannelSlave`]: serves the slave's container from an
//!   [`IdnStore`](crate::idn_store::IdnStore).
//!
//! * [`HostRunChannel`]: the same requests for drives whose MDT records no service
//!   container serves (one MDT container for every record): containers in host memory,
//!   run by the host once per cycle with the chip's rules.
//!
//! Where the containers live is a parameter ([`ContainerSlot`]). The readings chosen where
//! the documents are silent are in `docs/spec-notes.md`, "Driver service channel
//! (sercdrv)".

mod command;
mod container;
mod drive_index;
mod error;
mod host_run;
mod master;
mod request;
mod slave;
mod transfer;

pub use command::CommandStatus;
pub use container::{ContainerSlot, SlotError};
pub(crate) use drive_index::DriveIndex;
pub use error::{ErrorKind, ServiceChannelError};
pub use host_run::{HostRunChannel, SoftRam};
pub use master::{ContainerRouter, FixedRouting, ServiceChannelMaster, Wiring};
pub use request::{
    COMMAND_CANCEL, COMMAND_SET_AND_ENABLE, Completion, ReadLength, Request, Response, Ticket,
};
pub use slave::{ServiceChannelSlave, SlaveEvent};
