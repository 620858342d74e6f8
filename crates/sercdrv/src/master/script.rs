//! The service-channel work of phases 2 and 3 as queues of requests ("lanes"): one lane in
//! phase 2 (one drive after the other, as the captures' master does), one lane per drive in
//! phase 3 (all drives at once, each through its own service container).

use std::collections::VecDeque;

use sercos_wire::address::DriveAddress;
use sercos_wire::idn::{Element, Idn};

use crate::service_channel::{Request, Ticket};

/// Which timing value a read fills in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum TimingValue {
    /// S-0-0003 t1min.
    T1min,
    /// S-0-0004 tATMT.
    TAtmt,
    /// S-0-0005 t5.
    T5,
    /// S-0-0088 tMTSY.
    TMtsy,
    /// S-0-0090 tMTSG.
    TMtsg,
}

/// What a request is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Purpose {
    /// A timing value of the drive.
    Timing(TimingValue),
    /// Read for information; a refusal is not an error (S-0-0096).
    Optional,
    /// The attribute of the n-th IDN of the AT list: its data length.
    AtLength(usize),
    /// The attribute of the n-th IDN of the MDT list.
    MdtLength(usize),
    /// A write whose refusal stops the phase-up.
    Write,
    /// Start of a procedure command.
    CommandSet,
    /// A poll of a procedure command's status, the n-th.
    CommandPoll(u32),
    /// The acknowledgement (cancel) of a procedure command.
    CommandCancel,
    /// A tool's request (`Master::submit_service`) with the ticket the tool was given.
    Tool(Ticket),
}

/// One request of the phase-up.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Item {
    pub drive: DriveAddress,
    pub request: Request,
    pub purpose: Purpose,
}

impl Item {
    pub fn new(drive: DriveAddress, request: Request, purpose: Purpose) -> Item {
        Item {
            drive,
            request,
            purpose,
        }
    }

    /// The three steps of a procedure command: set (3), poll, cancel (0) (sercos-facts.md,
    /// "Procedure commands"; the captures' master: write 3, open, write 0).
    pub fn command(drive: DriveAddress, idn: Idn) -> [Item; 3] {
        [
            Item::new(drive, Request::set_command(idn), Purpose::CommandSet),
            Item::new(drive, Request::command_status(idn), Purpose::CommandPoll(1)),
            Item::new(drive, Request::cancel_command(idn), Purpose::CommandCancel),
        ]
    }

    /// Reads the attribute (element 3) of `idn`.
    pub fn attribute(drive: DriveAddress, idn: Idn, purpose: Purpose) -> Item {
        Item::new(drive, Request::read(idn, Element::Attribute), purpose)
    }
}

/// Requests carried out one after the other.
#[derive(Debug, Clone, Default)]
pub(crate) struct Lane {
    pub items: VecDeque<Item>,
    pub running: Option<(Ticket, Item)>,
}

impl Lane {
    pub fn new(items: impl IntoIterator<Item = Item>) -> Lane {
        Lane {
            items: items.into_iter().collect(),
            running: None,
        }
    }

    /// Whether everything is done.
    pub fn is_done(&self) -> bool {
        self.items.is_empty() && self.running.is_none()
    }

    /// The drive the lane works with now (running or next).
    pub fn drive(&self) -> Option<DriveAddress> {
        self.running
            .as_ref()
            .map(|(_, item)| item.drive)
            .or_else(|| self.items.front().map(|item| item.drive))
    }
}
