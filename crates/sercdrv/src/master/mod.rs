//! SERCDRV master: chip initialisation, phase-up 0 → 4, cyclic data, errors and recovery,
//! event-driven over [`SerconBus`] only (it runs unchanged on a real chip mapped into memory).
//!
//! [`Master`] implements [`HostProgram`]: it is woken on INT0 (INT_COMEND once per cycle,
//! INT_FIBBR) and at its deadlines, never blocks and never reads a clock.
//!
//! * Phase 0: MSTs until the ring is closed (no FIBBR, the MST comes back: TCYCDEL, 410B
//!   §4.1 11H); the ring delay places the receive windows of the ATs.
//! * Phase 1: one MDT per cycle to each configured address in turn, noting which drives
//!   answer with their AT in the next cycle (receive header ACHK = 0 stores the address).
//! * Phase 2: the service channel with one drive after the other: the timing parameters
//!   (S-0-0003, -0004, -0088, -0096, -0005, -0090) and the data lengths of the cyclic IDNs,
//!   then the cycle's timing and layout ([`crate::timing::plan_cycle`]) written as S-0-0001,
//!   -0002, -0006, -0089, -0008, -0007, -0009, -0010, -0015, -0016, -0024, then S-0-0099
//!   and S-0-0127 run on every drive.
//! * Phase 3: broadcast MDT, S-0-0128 on every drive at once. Phase 4: cyclic operation.
//!
//! Readings chosen where the documents are silent: `docs/spec-notes.md`, "Driver master
//! (sercdrv)".

mod chip_init;
mod config;
mod cyclic;
mod error;
mod routing;
mod script;
mod status;

pub use config::{MasterConfig, TELEGRAM_TYPE_CONFIGURED, standard_telegram};
pub use error::{MasterError, MasterErrorKind};
pub use status::{DriveStatus, MasterStatus, Progress};

use sercon_regs::host::{HostProgram, Wake};
use sercon_regs::ram::COMPT1;
use sercon_regs::ram::container::ContainerControl;
use sercon_regs::ram::header::{Buffering, Header, HeaderKind, RxHeader, TxEnable, TxHeader};
use sercon_regs::{Ctrl2, IntFlagsLo, Jtrdel1, Jtrdel2, SerconBus, SerconBusExt, Tcycdel};
use sercos_wire::address::DriveAddress;
use sercos_wire::idn::Idn;
use sercos_wire::time::Instant;

use crate::ram_layout::{
    self, MasterBudget, MdtContainers, PhaseGroup, RamLayout, RamLayoutError, RamLayoutRequest,
    Role,
};
use crate::service_channel::{
    CommandStatus, Completion, ContainerSlot, DriveIndex, HostRunChannel, Request,
    ServiceChannelMaster, Ticket, Wiring,
};
use crate::timing::{self, CycleTiming, DriveParameters, MdtPlacement, TimingRequest};

use chip_init::{init_chip, select_block, set_phase, start_cycles};
use cyclic::{CyclicImage, DriveCyclic};
use routing::{CONTAINERS, MasterRouter};
use script::{Item, Lane, Purpose, TimingValue};

/// Most drives the master serves: the addresses 1-254 (sercos-telegrams.md, ADR). Up to
/// eight drives have a service container each (410B §4.2: SCPT0-7); with more, the eight
/// are shared, routed to a drive before each transfer (spec-notes "Driver master").
pub const MAX_DRIVES: usize = 254;

/// Smallest service-container buffer the master shrinks to so that a large ring fits
/// (spec-notes "Master DMA layout": a list of up to six IDNs in one buffer fill).
pub const MIN_SERVICE_BUFFER_WORDS: u16 = 8;

/// How the phase 3-4 data are held (410B §4.2.1 DMA/DBUF, §4.2.2 containers).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CyclicLayout {
    /// Buffering of the cyclic data.
    pub buffering: Buffering,
    /// One MDT container per drive or one for every record.
    pub mdt: MdtContainers,
}

/// S-0-0099, reset class 1 diagnostic (sercos-facts.md, "Timing parameters" table).
const RESET_CLASS_1: Idn = Idn::from_raw(99);
/// S-0-0096, slave arrangement (read by the captures' master; not every drive has it).
const SLAVE_ARRANGEMENT: Idn = Idn::from_raw(96);

/// Where the phase-up is, with its own progress.
#[derive(Debug, Clone)]
enum State {
    Idle,
    Phase0 {
        closed: u32,
    },
    Phase1 {
        next: usize,
        checked: u32,
    },
    Phase2Read,
    Phase2Config,
    /// Configured, held in phase 2 ([`MasterConfig::hold_in_phase2`]).
    Phase2Held,
    Phase3 {
        silent: u32,
    },
    Phase4 {
        silent: u32,
    },
    Halted,
}

/// Addresses of the phase 0-2 block (410B §4.2.1, §4.2.2) the driver rewrites per cycle.
#[derive(Debug, Clone, Copy)]
struct NonCyclicPlaces {
    at_header: u16,
    at_container: u16,
    mdt_header: u16,
    mdt_container: u16,
}

/// What the master knows about one drive.
#[derive(Debug, Clone)]
struct DriveInfo {
    status: DriveStatus,
    nsv: u8,
    params: DriveParameters,
    at_words: Vec<Option<usize>>,
    mdt_words: Vec<Option<usize>>,
}

/// The SERCOS master driver.
#[derive(Debug)]
pub struct Master {
    cfg: MasterConfig,
    state: State,
    phase: u8,
    drives: Vec<DriveInfo>,
    /// Positions in `drives` by address.
    index: DriveIndex,
    layout: Option<RamLayout>,
    places: Option<NonCyclicPlaces>,
    sc: Option<ServiceChannelMaster<MasterRouter>>,
    /// The host-run service channel of phases 3-4 when one MDT container holds every
    /// record (410B §4.2.2: no per-drive SVFL/NSV).
    host_sc: Option<HostRunChannel>,
    /// Words of each service container's buffer in the RAM (the configured size, or less
    /// so that the ring fits, [`MIN_SERVICE_BUFFER_WORDS`]).
    service_buffer_words: u16,
    /// The phase 3-4 layout chosen in phase 2.
    cyclic_layout: CyclicLayout,
    lanes: Vec<Lane>,
    /// Requests of tools ([`Master::submit_service`]), one at a time, and their results.
    tool: Lane,
    tool_done: Vec<Completion>,
    tool_tickets: u64,
    timing: Option<CycleTiming>,
    cyclic: Option<CyclicImage>,
    ring_delay_us: u16,
    /// Drive of this cycle's MDT (phases 1-2) and of the previous one.
    addressed: Option<DriveAddress>,
    previous: Option<DriveAddress>,
    /// The service container the MDT of this cycle (phases 1-2) was pointed at: the AT of
    /// the next cycle answers that MDT, so its service info belongs in the same container.
    addressed_nsv: Option<u8>,
    /// The phase-2 lane addressed last (parallel phase 2, [`Master::phase2_lanes`]).
    turn: usize,
    errors: Vec<MasterError>,
    last_error: Option<MasterError>,
    cycles: u64,
    service_requests: u64,
    restarts: u32,
    /// INT_FIBBR came since the last cycle end.
    fibbr_seen: bool,
    /// Cycles with INT_FIBBR since the start.
    dark_total: u64,
}

impl Master {
    /// A master for `cfg`, or why the configuration cannot run.
    pub fn new(cfg: MasterConfig) -> Result<Master, MasterError> {
        let bad = |what| Err(MasterError::ring(0, MasterErrorKind::Config(what)));
        if cfg.drives.is_empty() {
            return bad("no drives");
        }
        if cfg.drives.len() > MAX_DRIVES {
            return bad("more than 254 drives (addresses 1-254)");
        }
        if !cfg.telegram_type_ok() {
            return bad(
                "telegram type (S-0-0015): 0-6 with their standard lists, or 7 (S-0-0016/S-0-0024)",
            );
        }
        if !cfg.slot_buffer_ok() {
            return bad("service buffer length (1-251 words)");
        }
        let mut seen = Vec::new();
        for d in &cfg.drives {
            if seen.contains(d) {
                return bad("a drive address appears twice");
            }
            seen.push(*d);
        }
        let service_buffer_words = fitting_service_buffer(&cfg)?;
        let cyclic_layout = CyclicLayout {
            buffering: cfg.buffering,
            mdt: cfg.mdt_containers,
        };
        let drives = cfg
            .drives
            .iter()
            .enumerate()
            .map(|(i, &address)| DriveInfo {
                status: DriveStatus {
                    address,
                    answered: false,
                    ats_received: 0,
                    ats_missed: 0,
                },
                nsv: (i % CONTAINERS) as u8,
                params: default_params(address.get()),
                at_words: vec![None; cfg.at_list.len()],
                mdt_words: vec![None; cfg.mdt_list.len()],
            })
            .collect();
        let index = DriveIndex::new(cfg.drives.iter().copied());
        Ok(Master {
            cfg,
            state: State::Idle,
            phase: 0,
            drives,
            index,
            layout: None,
            places: None,
            sc: None,
            host_sc: None,
            service_buffer_words,
            cyclic_layout,
            lanes: Vec::new(),
            tool: Lane::default(),
            tool_done: Vec::new(),
            tool_tickets: 0,
            timing: None,
            cyclic: None,
            ring_delay_us: 0,
            addressed: None,
            previous: None,
            addressed_nsv: None,
            turn: 0,
            errors: Vec::new(),
            last_error: None,
            cycles: 0,
            service_requests: 0,
            restarts: 0,
            fibbr_seen: false,
            dark_total: 0,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &MasterConfig {
        &self.cfg
    }

    /// The communication phase sent in the MST.
    pub fn phase(&self) -> u8 {
        self.phase
    }

    /// A snapshot: phase, progress, drives, counters, last error.
    pub fn status(&self) -> MasterStatus {
        MasterStatus {
            phase: self.phase,
            progress: self.progress(),
            drives: self.drives.iter().map(|d| d.status).collect(),
            cycles: self.cycles,
            service_requests: self.service_requests,
            restarts: self.restarts,
            dark_cycles: self.dark_total,
            last_error: self.last_error.clone(),
        }
    }

    /// Where the phase-up stands.
    pub fn progress(&self) -> Progress {
        match self.state {
            State::Idle => Progress::Idle,
            State::Phase0 { .. } => Progress::WaitingForRing,
            State::Phase1 { .. } => Progress::DetectingDrives,
            State::Phase2Read => Progress::ReadingParameters,
            State::Phase2Config => Progress::Configuring,
            State::Phase2Held => Progress::HeldInPhase2,
            State::Phase3 { .. } => Progress::CheckingPhase4,
            State::Phase4 { .. } => Progress::Cyclic,
            State::Halted => Progress::Halted,
        }
    }

    /// Sets [`MasterConfig::hold_in_phase2`]: whether the master stays in phase 2 once it
    /// has configured the drives. Takes effect at the end of the next phase-2
    /// configuration (set it before the start).
    pub fn set_hold_in_phase2(&mut self, hold: bool) {
        self.cfg.hold_in_phase2 = hold;
    }

    /// Whether tool requests ([`Master::submit_service`]) are carried out now: in cyclic
    /// operation (phase 4) and when held in phase 2; they wait in every other state.
    pub fn serves_tools(&self) -> bool {
        matches!(self.state, State::Phase4 { .. } | State::Phase2Held)
    }

    /// Queues a service-channel request of a tool (an IDN read or write, e.g. `sercon idn`)
    /// for `drive`. Requests run one at a time, in order, through the drive's service
    /// container once [`Master::serves_tools`] (phase 4, or phase 2 when held there); a
    /// drive's refusal or a timeout does not stop the master, it comes back in the
    /// completion ([`Master::take_service_completions`]), whose ticket is the one
    /// returned here. A request still running when the master restarts from phase 0 is
    /// carried out again once it serves tools again.
    pub fn submit_service(
        &mut self,
        drive: DriveAddress,
        request: Request,
    ) -> Result<Ticket, MasterError> {
        if !self.drives.iter().any(|d| d.status.address == drive) {
            return Err(self.error(
                Some(drive),
                Some(request.idn()),
                MasterErrorKind::Config("drive not configured"),
            ));
        }
        self.tool_tickets = self.tool_tickets.saturating_add(1);
        let ticket = Ticket(self.tool_tickets);
        self.tool
            .items
            .push_back(Item::new(drive, request, Purpose::Tool(ticket)));
        Ok(ticket)
    }

    /// Tool requests finished since the last call, oldest first, each with the ticket
    /// [`Master::submit_service`] returned.
    pub fn take_service_completions(&mut self) -> Vec<Completion> {
        std::mem::take(&mut self.tool_done)
    }

    /// Errors reported since the last call, oldest first.
    pub fn take_errors(&mut self) -> Vec<MasterError> {
        std::mem::take(&mut self.errors)
    }

    /// The cycle's timing, once planned in phase 2.
    pub fn timing(&self) -> Option<&CycleTiming> {
        self.timing.as_ref()
    }

    /// The phase 3-4 layout: the configured one, or the one chosen in phase 2 because the
    /// configured one did not fit ([`MasterConfig::layout_fallback`]).
    pub fn cyclic_layout(&self) -> CyclicLayout {
        self.cyclic_layout
    }

    /// Words of each service container's buffer in the RAM (the configured size, or less
    /// so that a large ring fits).
    pub fn service_buffer_words(&self) -> u16 {
        self.service_buffer_words
    }

    /// Whether the host runs the drives' service channel itself (phases 3-4 with one MDT
    /// container for every record).
    pub fn host_runs_service_channel(&self) -> bool {
        self.host_sc.is_some()
    }

    /// The measured ring delay, µs (TCYCDEL, 410B §4.1 11H).
    pub fn ring_delay_us(&self) -> u16 {
        self.ring_delay_us
    }

    /// Sets the command value `idn` of `drive` (an IDN of the MDT list); it goes out from
    /// the next cycle on. Values are words low first (1, 2 or 4 words by the attribute).
    pub fn set_command(
        &mut self,
        drive: DriveAddress,
        idn: Idn,
        value: u64,
    ) -> Result<(), CyclicError> {
        let d = self.cyclic_drive_mut(drive)?;
        let item = *d
            .mdt_items
            .iter()
            .find(|i| i.idn == idn)
            .ok_or(CyclicError::NotConfigured { drive, idn })?;
        if cyclic::put_value(&mut d.record, &item, value) {
            Ok(())
        } else {
            Err(CyclicError::NotConfigured { drive, idn })
        }
    }

    /// Sets the control word of `drive`'s MDT record (bits 15-6; the service-channel bits
    /// 5-0 are the chip's, ERRATA "service info in a container").
    pub fn set_control_word(&mut self, drive: DriveAddress, word: u16) -> Result<(), CyclicError> {
        let d = self.cyclic_drive_mut(drive)?;
        if let Some(w) = d.record.first_mut() {
            *w = word & !0x003F;
        }
        Ok(())
    }

    /// The feedback value `idn` of `drive` (an IDN of the AT list) from the last AT
    /// received whole, words low first.
    pub fn feedback(&self, drive: DriveAddress, idn: Idn) -> Result<u64, CyclicError> {
        let d = self.cyclic_drive(drive)?;
        let item = d
            .at_items
            .iter()
            .find(|i| i.idn == idn)
            .ok_or(CyclicError::NotConfigured { drive, idn })?;
        cyclic::value_of(&d.received, item).ok_or(CyclicError::NoData(drive))
    }

    /// The status word of `drive`'s last AT received whole (sercos-telegrams.md, AT).
    pub fn status_word(&self, drive: DriveAddress) -> Result<u16, CyclicError> {
        let d = self.cyclic_drive(drive)?;
        d.received
            .first()
            .copied()
            .ok_or(CyclicError::NoData(drive))
    }

    /// `drive`'s cyclic data, once the phase 3–4 layout exists.
    fn cyclic_drive(&self, drive: DriveAddress) -> Result<&cyclic::DriveCyclic, CyclicError> {
        self.cyclic
            .as_ref()
            .ok_or(CyclicError::NotCyclic)?
            .drive(drive)
            .ok_or(CyclicError::UnknownDrive(drive))
    }

    /// `drive`'s cyclic data for a change, once the phase 3–4 layout exists.
    fn cyclic_drive_mut(
        &mut self,
        drive: DriveAddress,
    ) -> Result<&mut cyclic::DriveCyclic, CyclicError> {
        self.cyclic
            .as_mut()
            .ok_or(CyclicError::NotCyclic)?
            .drive_mut(drive)
            .ok_or(CyclicError::UnknownDrive(drive))
    }

    /// Puts a tool request that was running back at the head of its queue (the service
    /// channel is started afresh).
    fn requeue_tool(&mut self) {
        if let Some((_, item)) = self.tool.running.take() {
            self.tool.items.push_front(item);
        }
    }

    fn report(&mut self, error: MasterError) {
        self.last_error = Some(error.clone());
        self.errors.push(error);
    }

    fn halt(&mut self, error: MasterError) {
        self.report(error);
        self.state = State::Halted;
    }

    fn error(
        &self,
        drive: Option<DriveAddress>,
        idn: Option<Idn>,
        kind: MasterErrorKind,
    ) -> MasterError {
        MasterError {
            drive,
            phase: self.phase,
            idn,
            kind,
        }
    }

    // ----- start -------------------------------------------------------------------------

    fn start<B: SerconBus + ?Sized>(&mut self, bus: &mut B) -> Result<(), MasterError> {
        init_chip(bus, &self.cfg).map_err(|k| MasterError::ring(0, k))?;
        let prelim = self.plan(self.drives.iter().map(|d| d.params).collect())?;
        let layout = self
            .build_layout(
                &prelim,
                [Some(PhaseGroup::NonCyclic), None],
                self.cyclic_layout,
            )
            .map_err(|k| MasterError::ring(0, MasterErrorKind::Layout(k)))?;
        for w in &layout.writes {
            bus.write_ram(w.address, w.word);
        }
        self.places = noncyclic_places(&layout);
        let places = self.places.ok_or(MasterError::ring(
            0,
            MasterErrorKind::Config("layout without phase 0-2 block"),
        ))?;
        // Receive window of the AT, placed by the ring delay once measured (spec-notes).
        let window = window_us(&self.cfg);
        bus.write_reg(Jtrdel1(window));
        bus.write_reg(Jtrdel2(window));
        set_at_window(
            bus,
            self.cfg.variant,
            places.at_header,
            prelim.noncyclic.at.start_us,
            0,
        );
        set_mdt(bus, self.cfg.variant, places, None, TxEnable::Off);
        self.sc = Some(self.service_channel(&layout)?);
        if let Some(sc) = self.sc.as_mut() {
            sc.init(bus);
        }
        self.layout = Some(layout);
        self.phase = 0;
        set_phase(bus, 0);
        start_cycles(bus, false);
        self.state = State::Phase0 { closed: 0 };
        Ok(())
    }

    fn plan(&self, drives: Vec<DriveParameters>) -> Result<CycleTiming, MasterError> {
        self.plan_with(drives, self.cfg.timing_rules)
    }

    fn plan_with(
        &self,
        drives: Vec<DriveParameters>,
        rules: timing::TimingRules,
    ) -> Result<CycleTiming, MasterError> {
        timing::plan_cycle(&TimingRequest {
            bit_rate: self.cfg.bit_rate,
            cycle_time_us: self.cfg.cycle_us,
            nc_cycle_time_us: self.cfg.nc_cycle_us,
            drives,
            rules,
        })
        .map_err(|e| self.error(None, None, MasterErrorKind::Timing(e)))
    }

    /// The layout of `blocks` with the phase 3-4 data held as `cyclic` says.
    fn build_layout(
        &self,
        timing: &CycleTiming,
        blocks: [Option<PhaseGroup>; 2],
        cyclic: CyclicLayout,
    ) -> Result<RamLayout, RamLayoutError> {
        let mut req = RamLayoutRequest::new(self.cfg.variant, Role::Master, timing);
        req.blocks = blocks;
        req.buffering = cyclic.buffering;
        req.service_buffer_words = self.service_buffer_words;
        ram_layout::build_with(&req, cyclic.mdt)
    }

    /// Plans the cycle for `params` and chooses the phase 3-4 layout: the configured one if
    /// it fits, else (with [`MasterConfig::layout_fallback`]) DMA with one MDT container
    /// for every record. With DMA the MDT follows the ATs at once, so that the host has the
    /// rest of the cycle for the FIFOs (spec-notes "Master DMA layout").
    fn plan_and_choose(
        &self,
        params: Vec<DriveParameters>,
    ) -> Result<(CycleTiming, CyclicLayout), MasterError> {
        let blocks = [Some(PhaseGroup::NonCyclic), Some(PhaseGroup::Cyclic)];
        let rules_for = |layout: CyclicLayout| {
            let mut rules = self.cfg.timing_rules;
            if layout.buffering == Buffering::Dma {
                rules.mdt_placement = MdtPlacement::AfterAts;
            }
            rules
        };
        let wanted = CyclicLayout {
            buffering: self.cfg.buffering,
            mdt: self.cfg.mdt_containers,
        };
        let timing = self.plan_with(params.clone(), rules_for(wanted))?;
        let refusal = match self.build_layout(&timing, blocks, wanted) {
            Ok(_) => return Ok((timing, wanted)),
            Err(e) => e,
        };
        let fallback = CyclicLayout {
            buffering: Buffering::Dma,
            mdt: MdtContainers::Single,
        };
        let layout_error = |e: RamLayoutError| match e {
            RamLayoutError::DoesNotFit {
                needed, available, ..
            } => MasterErrorKind::RingDoesNotFit {
                drives: self.drives.len(),
                needed,
                available,
            },
            other => MasterErrorKind::Layout(other),
        };
        if !self.cfg.layout_fallback || wanted == fallback {
            return Err(self.error(None, None, layout_error(refusal)));
        }
        let timing = self.plan_with(params, rules_for(fallback))?;
        self.build_layout(&timing, blocks, fallback)
            .map_err(|e| self.error(None, None, layout_error(e)))?;
        Ok((timing, fallback))
    }

    /// The cycle's timing and phase 3-4 layout phase 2 will choose if the drives report
    /// `params` (their timing parameters and data lengths, one per configured drive):
    /// what [`Master`] computes after reading them, to be asked before the start so that a
    /// cycle too short for the drives is known at once (spec-notes "Driver master").
    pub fn plan_for(
        &self,
        params: Vec<DriveParameters>,
    ) -> Result<(CycleTiming, CyclicLayout), MasterError> {
        self.plan_and_choose(params)
    }

    /// Whether the drives share the service containers (more drives than containers).
    fn shared_containers(&self) -> bool {
        self.drives.len() > CONTAINERS
    }

    fn service_channel(
        &self,
        layout: &RamLayout,
    ) -> Result<ServiceChannelMaster<MasterRouter>, MasterError> {
        let shared = self.shared_containers();
        let mut containers = Vec::new();
        for place in &layout.map.service_containers {
            let Some(drive) = place.drive.and_then(DriveAddress::new) else {
                continue;
            };
            // Up to eight drives: one container each for good; more: any container for
            // any drive, routed before each transfer (410B §4.2.2 NSV).
            let wiring = if shared {
                Wiring::Any
            } else {
                Wiring::Drive(drive)
            };
            let slot = ContainerSlot::new(
                self.cfg.variant,
                place.nsv,
                place.address,
                place.buffer_words,
            )
            .map_err(|_| {
                self.error(
                    Some(drive),
                    None,
                    MasterErrorKind::Config("service container"),
                )
            })?;
            containers.push((slot, wiring));
        }
        let mut sc = ServiceChannelMaster::with_router(containers, MasterRouter::default());
        sc.set_timeout(Some(self.cfg.service_timeout));
        // The master polls procedure commands through their status (sercos-facts.md
        // "Procedure commands"), never INT_CMD: a container it has nothing running in, or
        // whose transfer does not wait for it (410B §4.2.4 M_BUSY), costs no bus access.
        sc.set_watch_commands(false);
        Ok(sc)
    }

    /// Back to phase 0 after `error`: MSTs of phase 0 with the phase 0-2 block, the service
    /// channel and the drives' state forgotten, the ring brought up again by itself.
    fn restart<B: SerconBus + ?Sized>(&mut self, bus: &mut B, error: MasterError) {
        self.report(error);
        self.restarts = self.restarts.saturating_add(1);
        self.phase = 0;
        set_phase(bus, 0);
        select_block(bus, false);
        if let Some(places) = self.places {
            set_mdt(bus, self.cfg.variant, places, None, TxEnable::Off);
        }
        if let Some(layout) = self.layout.as_ref() {
            if let Ok(sc) = self.service_channel(layout) {
                self.sc = Some(sc);
            }
        }
        if let Some(sc) = self.sc.as_mut() {
            sc.init(bus);
        }
        self.forget_ring();
        self.state = State::Phase0 { closed: 0 };
    }

    /// Forgets what the master knew of the ring's drives and telegrams (which drives
    /// answered, the service lanes, the cyclic image, the host-run channel, the addressed
    /// drive); a tool's running request goes back to the front of its queue.
    fn forget_ring(&mut self) {
        for d in &mut self.drives {
            d.status.answered = false;
        }
        self.lanes.clear();
        self.requeue_tool();
        self.cyclic = None;
        self.host_sc = None;
        self.addressed = None;
        self.previous = None;
        self.addressed_nsv = None;
    }

    // ----- per cycle ---------------------------------------------------------------------

    fn on_cycle_end<B: SerconBus + ?Sized>(&mut self, bus: &mut B, now: Instant) {
        self.cycles = self.cycles.saturating_add(1);
        // 410B §4.1 4H.1 INT_FIBBR: the receive line lost its edges during this cycle.
        let dark = std::mem::take(&mut self.fibbr_seen);
        if dark {
            self.dark_total = self.dark_total.saturating_add(1);
        }
        match self.state.clone() {
            State::Idle | State::Halted => {}
            State::Phase0 { closed } => self.phase0(bus, closed),
            State::Phase1 { next, checked } => self.phase1(bus, next, checked),
            State::Phase2Read | State::Phase2Config | State::Phase2Held => self.phase2(bus, now),
            State::Phase3 { silent } => self.phase3(bus, now, silent),
            State::Phase4 { silent } => self.phase4(bus, now, silent),
        }
    }

    fn phase0<B: SerconBus + ?Sized>(&mut self, bus: &mut B, closed: u32) {
        // 410B §4.1 2H.13 FIBBR: no edges on the receive line; 11H TCYCDEL: when the MST came
        // back (spec-notes: the ring counts as closed when both say so).
        let fibbr = bus.read_reg::<Ctrl2>().fibbr();
        let delay = bus.read_reg::<Tcycdel>().0;
        // TCYCDEL counts whole µs: a short ring at 16 Mbit/s returns the MST in less than
        // 1 µs and reads 0, so 0 counts as closed when FIBBR says light comes back.
        let closed_now = !fibbr && u32::from(delay) < self.cfg.cycle_us;
        let closed = if closed_now {
            closed.saturating_add(1)
        } else {
            0
        };
        if closed < self.cfg.phase0_cycles.max(1) {
            self.state = State::Phase0 { closed };
            return;
        }
        self.ring_delay_us = delay;
        if let (Some(places), Some(layout)) = (self.places, self.layout.as_ref()) {
            let t1 = layout
                .map
                .blocks
                .first()
                .and_then(|b| b.telegrams.first())
                .map_or(0, |t| u32::from(t.trt));
            set_at_window(bus, self.cfg.variant, places.at_header, t1, delay);
        }
        self.enter_phase(bus, 1);
        self.state = State::Phase1 {
            next: 0,
            checked: 0,
        };
        self.address_next(bus, 0);
    }

    /// Addresses the drive with index `index` in the next cycle's MDT (phases 1-2), with
    /// its service container, and the AT container to the drive addressed this cycle.
    fn address_next<B: SerconBus + ?Sized>(&mut self, bus: &mut B, index: usize) {
        let Some(next) = self.drives.get(index).map(|d| d.status.address) else {
            return;
        };
        self.address(bus, next);
    }

    fn address<B: SerconBus + ?Sized>(&mut self, bus: &mut B, next: DriveAddress) {
        self.previous = self.addressed;
        self.addressed = Some(next);
        let answered_nsv = self.addressed_nsv.take();
        let Some(places) = self.places else {
            return;
        };
        let router = self.sc.as_mut().map(|sc| &*sc.router_mut());
        // Shared containers: the one routed to the drive; a drive without one (phase 1)
        // gets its index's container, which is idle then.
        let next_nsv = router.and_then(|r| r.nsv_of(next)).or_else(|| {
            self.drives
                .iter()
                .find(|x| x.status.address == next)
                .map(|x| x.nsv)
        });
        // Phases 1-2 carry one record each way; the driver points the containers at the
        // service container of the drive concerned (spec-notes "Driver timing and RAM
        // layout": "the driver rebinds NSV with the addressed drive").
        if let Some(nsv) = next_nsv {
            set_nsv(bus, places.mdt_container, nsv);
        }
        self.addressed_nsv = next_nsv;
        // The AT of the next cycle answers this cycle's MDT (410B §4.2.1 EN = 3 on the
        // slave): its service info goes into the container that MDT came from, even if the
        // container has been routed to another drive since (spec-notes "Driver master",
        // parallel phase 2).
        if let Some(nsv) = answered_nsv {
            set_nsv(bus, places.at_container, nsv);
        }
        // 410B §4.2.1 EN = 2: sent every cycle, ADR rewritten per cycle.
        set_mdt(
            bus,
            self.cfg.variant,
            places,
            Some(next),
            TxEnable::Continuous,
        );
    }

    /// The AT of this cycle: the address stored by ACHK = 0, if received without error
    /// (410B §4.2.1 ACHK, RERR).
    fn at_from<B: SerconBus + ?Sized>(&self, bus: &mut B) -> Option<u8> {
        let places = self.places?;
        // ADR, ACHK and RERR are all in word 0; it alone is read.
        let word0 = bus.read_ram(places.at_header);
        match RxHeader::from_words(self.cfg.variant, [word0, 0, 0, 0, 0]) {
            Ok(h) if !h.rerr => Some(h.adr),
            _ => None,
        }
    }

    fn phase1<B: SerconBus + ?Sized>(&mut self, bus: &mut B, next: usize, checked: u32) {
        let n = self.drives.len();
        let answered = self.at_from(bus);
        let mut checked = checked;
        if let Some(expected) = self.previous {
            if answered == Some(expected.get()) {
                if let Some(d) = self
                    .drives
                    .iter_mut()
                    .find(|d| d.status.address == expected)
                {
                    d.status.answered = true;
                }
            }
            checked = checked.saturating_add(1);
        }
        let rounds = checked / n.max(1) as u32;
        if checked > 0 && checked % n.max(1) as u32 == 0 {
            let all = self.drives.iter().all(|d| d.status.answered);
            if all && rounds >= self.cfg.phase1_rounds.max(1) {
                self.enter_phase2(bus);
                return;
            }
            if rounds >= self.cfg.detect_rounds.max(1) {
                let missing = self
                    .drives
                    .iter()
                    .find(|d| !d.status.answered)
                    .map(|d| d.status.address);
                let error = self.error(missing, None, MasterErrorKind::DriveMissing);
                self.halt(error);
                return;
            }
        }
        let index = (next + 1) % n.max(1);
        self.state = State::Phase1 {
            next: index,
            checked,
        };
        self.address_next(bus, index);
    }

    fn enter_phase<B: SerconBus + ?Sized>(&mut self, bus: &mut B, phase: u8) {
        self.phase = phase;
        set_phase(bus, phase);
    }

    fn enter_phase2<B: SerconBus + ?Sized>(&mut self, bus: &mut B) {
        self.enter_phase(bus, 2);
        let mut per_drive = Vec::new();
        for d in &self.drives {
            let mut items = Vec::new();
            let a = d.status.address;
            // The captures' master reads these, in this order, attribute then value.
            for (idn, what) in [
                (3, Some(TimingValue::T1min)),
                (4, Some(TimingValue::TAtmt)),
                (88, Some(TimingValue::TMtsy)),
                (SLAVE_ARRANGEMENT.raw(), None),
                (5, Some(TimingValue::T5)),
                (90, Some(TimingValue::TMtsg)),
            ] {
                let purpose = what.map_or(Purpose::Optional, Purpose::Timing);
                items.push(Item::new(
                    a,
                    Request::read_value(Idn::from_raw(idn)),
                    purpose,
                ));
            }
            for (i, idn) in self.cfg.at_list.iter().enumerate() {
                items.push(Item::attribute(a, *idn, Purpose::AtLength(i)));
            }
            for (i, idn) in self.cfg.mdt_list.iter().enumerate() {
                items.push(Item::attribute(a, *idn, Purpose::MdtLength(i)));
            }
            per_drive.push(items);
        }
        self.lanes = self.phase2_lanes([per_drive]);
        self.turn = 0;
        self.state = State::Phase2Read;
        let first = self.lanes.first().and_then(Lane::drive);
        if let Some(first) = first {
            self.address(bus, first);
        }
    }

    /// Polls the service channel, hands completions to their lanes and starts the lanes'
    /// next requests. Returns `false` when a request failed (the master halted).
    fn run_lanes<B: SerconBus + ?Sized>(&mut self, bus: &mut B, now: Instant) -> bool {
        let Some(done) = self.poll_channel(bus, now) else {
            return false;
        };
        for completion in done {
            self.service_requests = self.service_requests.saturating_add(1);
            if !self.complete(completion) {
                return false;
            }
        }
        let mut starts = Vec::new();
        for (i, lane) in self.lanes.iter_mut().enumerate() {
            if lane.running.is_none() {
                if let Some(item) = lane.items.pop_front() {
                    starts.push((Some(i), item));
                }
            }
        }
        // Tool requests only once the phase-up is through (phase 4, or held in phase 2).
        if matches!(self.state, State::Phase4 { .. } | State::Phase2Held)
            && self.tool.running.is_none()
        {
            if let Some(item) = self.tool.items.pop_front() {
                starts.push((None, item));
            }
        }
        let started = !starts.is_empty();
        for (lane, item) in starts {
            let Some(ticket) = self.submit_to_channel(item.drive, item.request.clone()) else {
                return false;
            };
            let slot = match lane {
                Some(i) => self.lanes.get_mut(i).map(|l| &mut l.running),
                None => Some(&mut self.tool.running),
            };
            if let Some(slot) = slot {
                *slot = Some((ticket, item));
            }
        }
        if started {
            // Schedules the new requests into their containers now, not a cycle later.
            let Some(done) = self.poll_channel(bus, now) else {
                return false;
            };
            for completion in done {
                self.service_requests = self.service_requests.saturating_add(1);
                if !self.complete(completion) {
                    return false;
                }
            }
        }
        true
    }

    /// Polls the service channel in use: the host-run one in phases 3-4 when one MDT
    /// container holds every record, else the chip's containers.
    fn poll_channel<B: SerconBus + ?Sized>(
        &mut self,
        bus: &mut B,
        now: Instant,
    ) -> Option<Vec<Completion>> {
        if let Some(host) = self.host_sc.as_mut() {
            return Some(host.poll(now));
        }
        self.sc.as_mut().map(|sc| sc.poll(bus, now))
    }

    /// Queues `request` for `drive` on the service channel in use.
    fn submit_to_channel(&mut self, drive: DriveAddress, request: Request) -> Option<Ticket> {
        if let Some(host) = self.host_sc.as_mut() {
            if host.serves(drive) {
                return host.submit(drive, request);
            }
        }
        self.sc.as_mut().map(|sc| sc.submit(drive, request))
    }

    /// Takes one completion; `false` if it stops the phase-up.
    fn complete(&mut self, completion: Completion) -> bool {
        if let Some((ticket, item)) = self.tool.running.take() {
            if ticket == completion.ticket {
                // A tool's request: handed back as it is, never an error of the master.
                let own = match item.purpose {
                    Purpose::Tool(own) => own,
                    _ => ticket,
                };
                self.tool_done.push(Completion {
                    ticket: own,
                    ..completion
                });
                return true;
            }
            self.tool.running = Some((ticket, item));
        }
        let Some(lane) = self.lanes.iter_mut().find(|l| {
            l.running
                .as_ref()
                .is_some_and(|(t, _)| *t == completion.ticket)
        }) else {
            return true;
        };
        let Some((_, item)) = lane.running.take() else {
            return true;
        };
        let drive = item.drive;
        let idn = item.request.idn();
        let response = match completion.result {
            Ok(response) => response,
            Err(_) if item.purpose == Purpose::Optional => return true,
            Err(e) => {
                let error = self.error(
                    Some(drive),
                    Some(idn),
                    MasterErrorKind::ServiceChannel(e.kind),
                );
                self.halt(error);
                return false;
            }
        };
        let first = response.words.first().copied();
        match item.purpose {
            Purpose::Timing(which) => {
                let value = first.unwrap_or(0);
                if let Some(d) = self.index.get(drive).and_then(|i| self.drives.get_mut(i)) {
                    let p = &mut d.params;
                    match which {
                        TimingValue::T1min => p.t1min_us = value,
                        TimingValue::TAtmt => p.t_atmt_us = value,
                        TimingValue::T5 => p.t5_us = value,
                        TimingValue::TMtsy => p.t_mtsy_us = value,
                        TimingValue::TMtsg => p.t_mtsg_us = value,
                    }
                }
            }
            Purpose::AtLength(i) | Purpose::MdtLength(i) => {
                let words = response.attribute.and_then(|a| a.fixed_words());
                let Some(words) = words else {
                    let raw = response.attribute.map_or(0, |a| u64::from(a.raw()));
                    let error = self.error(Some(drive), Some(idn), MasterErrorKind::BadValue(raw));
                    self.halt(error);
                    return false;
                };
                if let Some(d) = self.index.get(drive).and_then(|i| self.drives.get_mut(i)) {
                    let list = if matches!(item.purpose, Purpose::AtLength(_)) {
                        &mut d.at_words
                    } else {
                        &mut d.mdt_words
                    };
                    if let Some(slot) = list.get_mut(i) {
                        *slot = Some(words);
                    }
                }
            }
            Purpose::CommandPoll(n) => {
                let status = CommandStatus(first.unwrap_or(0));
                // sercos-facts.md "Procedure commands"; status bits: spec-notes (emulated
                // drive): bit 2 executed, bit 3 error.
                if status.is_error() || (!status.is_executed() && n >= self.cfg.command_polls) {
                    let error = self.error(
                        Some(drive),
                        Some(idn),
                        MasterErrorKind::ProcedureFailed { status: status.0 },
                    );
                    self.halt(error);
                    return false;
                }
                if !status.is_executed() {
                    let again = Item::new(
                        drive,
                        Request::command_status(idn),
                        Purpose::CommandPoll(n + 1),
                    );
                    if let Some(lane) = self.lanes.iter_mut().find(|l| {
                        l.running.is_none() && l.items.front().is_some_and(|i| i.drive == drive)
                    }) {
                        lane.items.push_front(again);
                    }
                }
            }
            Purpose::Optional
            | Purpose::Write
            | Purpose::CommandSet
            | Purpose::CommandCancel
            | Purpose::Tool(_) => {}
        }
        true
    }

    fn phase2<B: SerconBus + ?Sized>(&mut self, bus: &mut B, now: Instant) {
        if !self.run_lanes(bus, now) {
            return;
        }
        let done = self.lanes.iter().all(Lane::is_done);
        if done {
            match self.state {
                State::Phase2Held => {}
                // Asked to stay in phase 2 (MasterConfig::hold_in_phase2): configured and
                // S-0-0127 passed, but no switch to phase 3.
                State::Phase2Config if self.cfg.hold_in_phase2 => {
                    self.state = State::Phase2Held;
                }
                State::Phase2Read => {
                    if let Err(error) = self.configure() {
                        self.halt(error);
                        return;
                    }
                    self.state = State::Phase2Config;
                    // Start the first write now.
                    if !self.run_lanes(bus, now) {
                        return;
                    }
                }
                _ => {
                    if let Err(error) = self.enter_phase3(bus) {
                        self.halt(error);
                    }
                    return;
                }
            }
        }
        let next = self
            .next_phase2_drive()
            .or_else(|| self.tool.drive())
            .or(self.addressed);
        if let Some(next) = next {
            self.address(bus, next);
        }
    }

    /// The phase-2 work as lanes: `stages` are lists of each drive's requests, in the
    /// drives' order, carried out stage after stage.
    ///
    /// Up to eight drives (each with a service container of its own): one lane, all of a
    /// stage's drives one after the other, then the next stage, as the captures' master
    /// does. More drives: one lane per service container (410B §4.2.4 SCPT0-7), drive `i`
    /// in lane `i mod 8`, each lane keeping the stage order for its drives; the lanes run
    /// at once and the MDT of each cycle goes to one of them in turn (spec-notes "Driver
    /// master", parallel phase 2).
    fn phase2_lanes<const N: usize>(&self, stages: [Vec<Vec<Item>>; N]) -> Vec<Lane> {
        let lanes = if self.shared_containers() && self.cfg.parallel_phase2 {
            CONTAINERS
        } else {
            1
        };
        let mut items: Vec<Vec<Item>> = vec![Vec::new(); lanes];
        for stage in stages {
            for (i, drive_items) in stage.into_iter().enumerate() {
                if let Some(lane) = items.get_mut(i % lanes) {
                    lane.extend(drive_items);
                }
            }
        }
        items
            .into_iter()
            .filter(|l| !l.is_empty())
            .map(Lane::new)
            .collect()
    }

    /// The drive the next phase-2 MDT goes to: the one lane's drive, or with parallel
    /// lanes the next lane after the one addressed last that has a request running (one
    /// with requests waiting if none has).
    fn next_phase2_drive(&mut self) -> Option<DriveAddress> {
        let n = self.lanes.len();
        if n <= 1 {
            return self.lanes.first().and_then(Lane::drive);
        }
        let order = (1..=n).map(|k| (self.turn + k) % n);
        let chosen = order
            .clone()
            .find(|&i| self.lanes.get(i).is_some_and(|l| l.running.is_some()))
            .or_else(|| {
                order
                    .clone()
                    .find(|&i| self.lanes.get(i).is_some_and(|l| !l.is_done()))
            })?;
        self.turn = chosen;
        self.lanes.get(chosen).and_then(Lane::drive)
    }

    /// Plans the cycle from what the drives reported and queues the phase-2 writes and
    /// procedure commands, in the captures' master's order.
    fn configure(&mut self) -> Result<(), MasterError> {
        let mut params = Vec::new();
        for d in &mut self.drives {
            let words = |list: &[Option<usize>]| list.iter().map(|w| w.unwrap_or(0)).sum::<usize>();
            d.params.at_data_bytes = u16::try_from(words(&d.at_words) * 2).unwrap_or(u16::MAX);
            d.params.mdt_data_bytes = u16::try_from(words(&d.mdt_words) * 2).unwrap_or(u16::MAX);
            params.push(d.params);
        }
        let (timing, cyclic_layout) = self.plan_and_choose(params)?;
        self.cyclic_layout = cyclic_layout;
        let mut writes = Vec::new();
        let mut reset = Vec::new();
        let mut check = Vec::new();
        for d in &self.drives {
            let a = d.status.address;
            let Some(values) = timing.parameter_writes(a.get()) else {
                continue;
            };
            let mut writes_now = Vec::new();
            for (idn, value) in values {
                writes_now.push(Item::new(
                    a,
                    Request::write_value(idn, vec![value as u16]),
                    Purpose::Write,
                ));
            }
            writes_now.push(Item::new(
                a,
                Request::write_value(Idn::TELEGRAM_TYPE, vec![self.cfg.telegram_type]),
                Purpose::Write,
            ));
            // sercos-facts.md S-0-0015: only type 7 is configured by S-0-0016 and S-0-0024;
            // a standard type brings its own data (spec-notes "Driver master").
            if self.cfg.telegram_type == TELEGRAM_TYPE_CONFIGURED {
                writes_now.extend(self.list_writes(a));
            }
            writes.push(writes_now);
            reset.push(Item::command(a, RESET_CLASS_1).to_vec());
            // As the captures' master: S-0-0127 set, polled and acknowledged (cancelled) in
            // phase 2, before the switch; the drive remembers that it passed (spec-notes
            // "Driver slave and drive node").
            check.push(Item::command(a, Idn::PHASE_3_TRANSITION_CHECK).to_vec());
        }
        self.lanes = self.phase2_lanes([writes, reset, check]);
        self.turn = 0;
        self.timing = Some(timing);
        Ok(())
    }

    /// S-0-0016 and S-0-0024 written with the configured lists (telegram type 7).
    fn list_writes(&self, drive: DriveAddress) -> [Item; 2] {
        let at: Vec<u16> = self.cfg.at_list.iter().map(|i| i.raw()).collect();
        let mdt: Vec<u16> = self.cfg.mdt_list.iter().map(|i| i.raw()).collect();
        [
            Item::new(
                drive,
                Request::write_list(Idn::AT_CONFIGURATION_LIST, &at),
                Purpose::Write,
            ),
            Item::new(
                drive,
                Request::write_list(Idn::MDT_CONFIGURATION_LIST, &mdt),
                Purpose::Write,
            ),
        ]
    }

    /// Writes the phase 3-4 block, switches to it with phase 3 and queues S-0-0128.
    fn enter_phase3<B: SerconBus + ?Sized>(&mut self, bus: &mut B) -> Result<(), MasterError> {
        let timing = self.timing.clone().ok_or(self.error(
            None,
            None,
            MasterErrorKind::Config("no timing"),
        ))?;
        let full = self
            .build_layout(
                &timing,
                [Some(PhaseGroup::NonCyclic), Some(PhaseGroup::Cyclic)],
                self.cyclic_layout,
            )
            .map_err(|k| self.error(None, None, MasterErrorKind::Layout(k)))?;
        let same_block0 = self
            .layout
            .as_ref()
            .is_some_and(|l| l.map.blocks.first() == full.map.blocks.first());
        if !same_block0 {
            return Err(self.error(None, None, MasterErrorKind::Config("phase 0-2 block moved")));
        }
        let block1 = full
            .writes
            .iter()
            .rfind(|w| w.address == COMPT1)
            .map(|w| w.word)
            .filter(|&start| start > COMPT1)
            .ok_or(self.error(None, None, MasterErrorKind::Config("no phase 3-4 block")))?;
        // Everything of block 1 first, COMPT1 last (410B §4.2: COMPT1, start of block 1;
        // the layout zeroes the fixed words first, so its last write of COMPT1 counts).
        for w in full.writes.iter().filter(|w| w.address >= block1) {
            bus.write_ram(w.address, w.word);
        }
        let Some(block) = full
            .map
            .blocks
            .iter()
            .find(|b| b.group == PhaseGroup::Cyclic)
        else {
            return Err(self.error(None, None, MasterErrorKind::Config("no phase 3-4 block")));
        };
        for t in &block.telegrams {
            if t.kind == HeaderKind::Receive {
                set_at_window(
                    bus,
                    self.cfg.variant,
                    t.header,
                    u32::from(t.trt),
                    self.ring_delay_us,
                );
            }
        }
        bus.write_ram(COMPT1, block1);
        self.cyclic = Some(self.cyclic_image(&full)?);
        self.host_sc = None;
        if self.cyclic_layout.mdt == MdtContainers::Single {
            // 410B §4.2.2: one MDT container for every record has no per-drive SVFL/NSV;
            // the host runs every drive's service channel from now on (spec-notes "Master
            // DMA layout"). Its containers live in host memory, with the configured buffer.
            let drives: Vec<DriveAddress> = self.drives.iter().map(|d| d.status.address).collect();
            let host = HostRunChannel::new(
                self.cfg.variant,
                &drives,
                self.cfg.service_buffer_words,
                Some(self.cfg.service_timeout),
            )
            .map_err(|_| {
                self.error(
                    None,
                    None,
                    MasterErrorKind::Config("host-run service containers"),
                )
            })?;
            self.host_sc = Some(host);
            // The host-run channel takes the AT's service info from the record.
            if let Some(image) = self.cyclic.as_mut() {
                image.read_service_info = true;
            }
        } else if self.shared_containers() {
            // 410B §4.2.2: the routes in effect go into the new data containers.
            let places: Vec<_> = self
                .drives
                .iter()
                .filter_map(|d| {
                    let a = d.status.address;
                    let ram = full.map.drive(a.get())?;
                    Some((a, ram.command.control, ram.feedback.control))
                })
                .collect();
            if let Some(sc) = self.sc.as_mut() {
                sc.router_mut().set_cyclic(bus, places);
            }
        }
        // The records go into the buffer VAL turns to; the other one is written in full the
        // first time the chip no longer sends it (410B §4.2.1 transmit VAL).
        if let Some(image) = self.cyclic.as_mut() {
            image.write_commands(bus);
        }
        self.layout = Some(full);
        // 410B §4.1 0CH.2 COMBLK0: block 1 for the phase in PHAS0, from the next cycle on.
        select_block(bus, true);
        self.enter_phase(bus, 3);
        self.lanes = self
            .drives
            .iter()
            // As the captures' master: S-0-0128 set, polled and acknowledged on every drive
            // at once, all in phase 3.
            .map(|d| {
                Lane::new(Item::command(
                    d.status.address,
                    Idn::PHASE_4_TRANSITION_CHECK,
                ))
            })
            .collect();
        self.state = State::Phase3 { silent: 0 };
        Ok(())
    }

    fn cyclic_image(&self, layout: &RamLayout) -> Result<CyclicImage, MasterError> {
        let block = layout
            .map
            .blocks
            .iter()
            .find(|b| b.group == PhaseGroup::Cyclic)
            .ok_or(self.error(None, None, MasterErrorKind::Config("no phase 3-4 block")))?;
        let mdt_header = block
            .telegrams
            .iter()
            .find(|t| t.kind == HeaderKind::Transmit)
            .map(|t| t.header)
            .ok_or(self.error(None, None, MasterErrorKind::Config("no MDT header")))?;
        let mut drives = Vec::new();
        for d in &self.drives {
            let a = d.status.address;
            let ram = layout.map.drive(a.get()).ok_or(self.error(
                Some(a),
                None,
                MasterErrorKind::Config("drive not in layout"),
            ))?;
            let at_header = block
                .telegrams
                .iter()
                .find(|t| t.kind == HeaderKind::Receive && t.adr == a.get())
                .map(|t| t.header)
                .ok_or(self.error(Some(a), None, MasterErrorKind::Config("no AT header")))?;
            let words =
                |list: &[Option<usize>]| list.iter().map(|w| w.unwrap_or(0)).collect::<Vec<_>>();
            drives.push(DriveCyclic {
                address: a,
                command: ram.command,
                feedback: ram.feedback,
                at_header,
                mdt_items: cyclic::items(&self.cfg.mdt_list, &words(&d.mdt_words)),
                at_items: cyclic::items(&self.cfg.at_list, &words(&d.at_words)),
                record: vec![0; usize::from(ram.command.len)],
                received: Vec::new(),
                last_ok: false,
                written: [Vec::new(), Vec::new()],
            });
        }
        Ok(CyclicImage::new(
            self.cfg.variant,
            self.cyclic_layout.buffering,
            mdt_header,
            drives,
        ))
    }

    /// Reads the ATs of this cycle (and hands their service info to the host-run channel);
    /// `None` when the MST is taken as lost (the master went back to phase 0).
    fn exchange<B: SerconBus + ?Sized>(&mut self, bus: &mut B, silent: u32) -> Option<u32> {
        let Some(image) = self.cyclic.as_mut() else {
            return Some(silent);
        };
        let ok = image.read_feedback(bus);
        if let Some(host) = self.host_sc.as_mut() {
            for d in &image.drives {
                // The AT's status word and info word (sercos-telegrams.md "Data Record").
                let record = d.received.get(..cyclic::RECORD_HEADER_WORDS);
                host.receive(d.address, record.filter(|_| d.last_ok));
            }
        }
        for d in &image.drives {
            // One look-up per drive, not a scan (linear per cycle in the ring's size).
            let info = self
                .index
                .get(d.address)
                .and_then(|i| self.drives.get_mut(i));
            if let Some(info) = info {
                if d.last_ok {
                    info.status.ats_received = info.status.ats_received.saturating_add(1);
                } else {
                    info.status.ats_missed = info.status.ats_missed.saturating_add(1);
                }
            }
        }
        let silent = if ok == 0 { silent.saturating_add(1) } else { 0 };
        if silent >= self.cfg.mst_loss_cycles.max(1) {
            // No AT for several cycles: a receive line without edges now (410B §4.1 2H.13
            // FIBBR, read directly) is a broken ring, else the MST does not get round
            // (spec-notes).
            let kind = if bus.read_reg::<Ctrl2>().fibbr() {
                MasterErrorKind::RingBroken
            } else {
                MasterErrorKind::MstLost
            };
            let error = self.error(None, None, kind);
            self.restart(bus, error);
            return None;
        }
        Some(silent)
    }

    /// Writes the commands of the next cycle, the host-run channel's service info first.
    fn send_commands<B: SerconBus + ?Sized>(&mut self, bus: &mut B) {
        let Some(image) = self.cyclic.as_mut() else {
            return;
        };
        if let Some(host) = self.host_sc.as_mut() {
            for d in &mut image.drives {
                let end = cyclic::RECORD_HEADER_WORDS.min(d.record.len());
                if let Some(service) = d.record.get_mut(..end) {
                    host.transmit(d.address, service);
                }
            }
        }
        image.write_commands(bus);
    }

    fn phase3<B: SerconBus + ?Sized>(&mut self, bus: &mut B, now: Instant, silent: u32) {
        let Some(silent) = self.exchange(bus, silent) else {
            return;
        };
        if let State::Phase3 { .. } = self.state {
            self.state = State::Phase3 { silent };
        }
        // The drives take phase 3 from the MST and answer in their phase-3 ATs; S-0-0128
        // ("only in phase 3", sercos-facts.md) is started once every drive's AT has come
        // twice (spec-notes).
        if self.drives.iter().all(|d| d.status.ats_received >= 2)
            && self.run_lanes(bus, now)
            && self.lanes.iter().all(Lane::is_done)
        {
            self.enter_phase(bus, 4);
            self.state = State::Phase4 { silent: 0 };
            self.lanes.clear();
        }
        if matches!(self.state, State::Phase3 { .. } | State::Phase4 { .. }) {
            self.send_commands(bus);
        }
    }

    fn phase4<B: SerconBus + ?Sized>(&mut self, bus: &mut B, now: Instant, silent: u32) {
        let Some(silent) = self.exchange(bus, silent) else {
            return;
        };
        self.run_lanes(bus, now);
        if matches!(self.state, State::Phase4 { .. }) {
            self.state = State::Phase4 { silent };
            self.send_commands(bus);
        }
    }
}

/// Why a cyclic value cannot be set or read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum CyclicError {
    /// The master is not in phase 3 or 4.
    #[error("no cyclic data before phase 3")]
    NotCyclic,
    /// The drive is not configured.
    #[error("drive {0} is not configured")]
    UnknownDrive(DriveAddress),
    /// The IDN is not in the drive's configuration list (S-0-0016 / S-0-0024).
    #[error("{idn} is not in the cyclic data of drive {drive}")]
    NotConfigured {
        /// The drive.
        drive: DriveAddress,
        /// The IDN.
        idn: Idn,
    },
    /// No AT of the drive has been received whole yet.
    #[error("no AT of drive {0} received yet")]
    NoData(DriveAddress),
}

impl Master {
    /// Serves the interrupt flags of 4H until none of the master's is left: a level
    /// interrupt that stays active gives no new edge, so the handler looks again before it
    /// returns (410B §4.1 3H.0 INTFL0 shows the request).
    fn serve_flags<B: SerconBus + ?Sized>(&mut self, bus: &mut B, now: Instant) {
        for _ in 0..4 {
            // 410B §4.1 4H: read the flags, write 1 to clear what was seen (ERRATA).
            let flags = bus.read_reg::<IntFlagsLo>();
            if !flags.is_empty() {
                bus.clear_int_lo(flags);
            }
            if !flags.intersects(chip_init::MASTER_INTERRUPTS) {
                return;
            }
            if flags.contains(IntFlagsLo::INT_FIBBR) {
                self.fibbr_seen = true;
            }
            if flags.contains(IntFlagsLo::INT_COMEND) {
                self.on_cycle_end(bus, now);
            }
        }
    }
}

impl HostProgram for Master {
    fn wake(&mut self, bus: &mut dyn SerconBus, now: Instant, why: Wake) -> Option<Instant> {
        match why {
            // 410B §4.1 6H/3H: INT0 carries only the master's flags, 1-active (ENINT0 with
            // POLINT0 = 0, ERRATA 3H.1/3H.2): INT0 low means none is set, nothing to read.
            Wake::Interrupt { int0: false, .. } => {}
            // serve_flags reads 4H until none of the master's flags is left.
            Wake::Interrupt { .. } => self.serve_flags(bus, now),
            Wake::Deadline => {
                self.serve_flags(bus, now);
                for completion in self.poll_channel(bus, now).unwrap_or_default() {
                    self.service_requests = self.service_requests.saturating_add(1);
                    if !self.complete(completion) {
                        break;
                    }
                }
            }
            _ => {
                // Start (the first call, and again after a power-on): the chip is fresh out of reset, so the ring is brought up from the start.
                if !matches!(self.state, State::Idle) {
                    self.restarts = self.restarts.saturating_add(1);
                }
                self.forget_ring();
                if let Err(error) = self.start(bus) {
                    self.halt(error);
                }
            }
        }
        if !matches!(why, Wake::Interrupt { .. }) {
            // A flag raised while the start or the deadline's work ran gives no new edge on
            // INT0 if INT0 was high already (410B §4.1 3H.0 INTFL0).
            self.serve_flags(bus, now);
        }
        let chip = self
            .sc
            .as_ref()
            .and_then(ServiceChannelMaster::next_deadline);
        let host = self
            .host_sc
            .as_ref()
            .and_then(HostRunChannel::next_deadline);
        chip.into_iter().chain(host).min()
    }
}

/// The service-container buffer for `cfg`'s ring: the configured size if the smallest layout
/// (DMA, one MDT container for every record: no data words, 410B §4.2.1/§4.2.2) holds the
/// ring with it, else the largest that lets it (at least [`MIN_SERVICE_BUFFER_WORDS`]); a
/// ring that fits no layout is refused here, with the words it needs.
fn fitting_service_buffer(cfg: &MasterConfig) -> Result<u16, MasterError> {
    let drives = cfg.drives.len();
    let n = u32::try_from(drives).unwrap_or(u32::MAX);
    // With DMA the containers hold no data: the data lengths do not count.
    let budget = |words: u16| MasterBudget {
        variant: cfg.variant,
        at_data_bytes: 0,
        mdt_data_bytes: 0,
        buffering: Buffering::Dma,
        service_buffer_words: words,
        service_containers: ram_layout::SERVICE_CONTAINERS,
        noncyclic_block: true,
        mdt: MdtContainers::Single,
    };
    if budget(cfg.service_buffer_words).fits(n) {
        return Ok(cfg.service_buffer_words);
    }
    let floor = MIN_SERVICE_BUFFER_WORDS.min(cfg.service_buffer_words);
    if let Some(words) = (floor..cfg.service_buffer_words)
        .rev()
        .find(|&w| budget(w).fits(n))
    {
        return Ok(words);
    }
    Err(MasterError::ring(
        0,
        MasterErrorKind::RingDoesNotFit {
            drives,
            needed: budget(floor).words_needed(n),
            available: u32::from(cfg.variant.ram_words()),
        },
    ))
}

/// Drive parameters before phase 2 has read them: zero times, no cyclic data.
fn default_params(address: u8) -> DriveParameters {
    DriveParameters {
        address,
        t1min_us: 0,
        t_atmt_us: 0,
        t5_us: 0,
        t_mtsy_us: 0,
        t_mtsg_us: 0,
        at_data_bytes: 0,
        mdt_data_bytes: 0,
    }
}

fn noncyclic_places(layout: &RamLayout) -> Option<NonCyclicPlaces> {
    let block = layout
        .map
        .blocks
        .iter()
        .find(|b| b.group == PhaseGroup::NonCyclic)?;
    let at = block
        .telegrams
        .iter()
        .find(|t| t.kind == HeaderKind::Receive)?;
    let mdt = block
        .telegrams
        .iter()
        .find(|t| t.kind == HeaderKind::Transmit)?;
    Some(NonCyclicPlaces {
        at_header: at.header,
        at_container: at.containers.first()?.control,
        mdt_header: mdt.header,
        mdt_container: mdt.containers.first()?.control,
    })
}

/// The receive window either side of an AT's expected start, µs: the planner's gap
/// between telegrams, at least 4 µs (spec-notes).
fn window_us(cfg: &MasterConfig) -> u16 {
    let gap = timing::gap_us(&cfg.timing_rules, cfg.bit_rate);
    u16::try_from(gap.max(4)).unwrap_or(u16::MAX)
}

/// Sets TRT of the receive header at `header` to `t1 + ring delay` and TCHK = 1: the AT
/// leaves the drive t1 after the MST reached it and arrives one ring delay after the
/// master's MST (410B §4.2.1 TRT, TCHK; §4.1 11H TCYCDEL, 18H/19H JTRDEL1/2).
fn set_at_window<B: SerconBus + ?Sized>(
    bus: &mut B,
    variant: sercon_regs::Variant,
    header: u16,
    t1_us: u32,
    delay_us: u16,
) {
    if let Ok(Header::Receive(mut h)) = bus.read_header(variant, header) {
        h.trt = u16::try_from(t1_us.saturating_add(u32::from(delay_us))).unwrap_or(u16::MAX);
        h.tchk = true;
        bus.write_header(variant, header, &Header::Receive(h));
    }
}

/// Sets ADR and EN of the phase 0-2 MDT (410B §4.2.1 transmit header word 0).
fn set_mdt<B: SerconBus + ?Sized>(
    bus: &mut B,
    variant: sercon_regs::Variant,
    places: NonCyclicPlaces,
    drive: Option<DriveAddress>,
    en: TxEnable,
) {
    // ADR and EN are in word 0; it alone is read and written.
    let word0 = bus.read_ram(places.mdt_header);
    if let Ok(mut h) = TxHeader::from_words(variant, [word0, 0, 0, 0]) {
        if let Some(drive) = drive {
            h.adr = drive.get();
        }
        h.en = en;
        let [new0, ..] = h.to_words(variant);
        if new0 != word0 {
            bus.write_ram(places.mdt_header, new0);
        }
    }
}

/// Points the data container at `container` to service container `nsv` (410B §4.2.2 NSV).
fn set_nsv<B: SerconBus + ?Sized>(bus: &mut B, container: u16, nsv: u8) {
    let mut c = ContainerControl::from_word(bus.read_ram(container));
    if c.nsv != nsv {
        c.nsv = nsv;
        bus.write_ram(container, c.to_word());
    }
}
