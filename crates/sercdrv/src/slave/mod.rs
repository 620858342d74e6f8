//! SERCDRV's slave: a SERCON at a drive address, driven through [`SerconBus`] only and
//! woken by the chip's interrupts ([`HostProgram`]).
//!
//! * **Initialisation** ([`SlaveDriver::start`]): predivider (0EH), bit rate and repeater
//!   (1H), normal transmit mode (2H), the phase 0–2 RAM (block 0: its AT with EN = 3, the
//!   unicast MDT to its address; 410B §4.2), the service container, TSCYC0/1, PHAS12, MST
//!   receive (0CH MSTEN = 1, MSTMASTER = 0), PHAS0/PHAS1 (0AH), interrupts INT_PHAS0,
//!   INT_PHASERR, INT_COMEND and INT_SC_0 on INT0 (4H–7H, 3H).
//! * **Phases.** PHAS0 holds the current phase, PHAS1 the next one the slave accepts, so
//!   the chip follows an accepted step at once (410B §4.1 0AH, 0CH COMBLK0/1): 0 → 1 → 2
//!   always, 2 → 3 only when S-0-0127 has passed and the phase 3–4 RAM (block 1,
//!   from S-0-0002/6/9/10/89 and the device's cyclic lengths) is laid out, 3 → 4 only when
//!   S-0-0128 has passed. A check that passed stays passed when the master acknowledges
//!   (cancels) it, until a parameter it read is written or the phase drops. Any other phase is INT_PHASERR: no block is processed and
//!   the refusal is reported. INT_PHAS0 takes the slave back to phase 0.
//! * **Service channel**: the drvsc server ([`ServiceChannelSlave`]) on INT_SC_0, from the
//!   device's [`IdnStore`](crate::idn_store::IdnStore).
//! * **Cyclic data** at the end of every block (INT_COMEND): the MDT record to the device
//!   (phases 3–4), the device's status word and feedback into the AT (double buffer: VAL),
//!   CMD_AT from status-word bit 5.
//!
//! Readings chosen where the documents are silent: `docs/spec-notes.md`, "Driver slave and
//! drive node".

mod config;
mod cyclic;
mod device;
mod error;
mod events;
mod parameters;
#[cfg(test)]
mod wake_tests;

pub use config::{DEFAULT_NONCYCLIC_CYCLE_US, DEFAULT_SCLK_HZ, SlaveConfig};
use cyclic::AtWritten;
pub use cyclic::RecordPlaces;
pub use device::{CyclicLengths, DeviceRefusal, SlaveDevice};
pub use error::SlaveError;
pub use events::{PhaseRefusal, SlaveDriverEvent};
pub use parameters::{
    AT_START, CYCLE_TIME, MDT_LENGTH, MDT_POSITION, MDT_START, PHASE_3_CHECK, PHASE_3_CHECKED,
    PHASE_4_CHECK, PHASE_4_CHECKED, checked_by, command_executed, command_status, cyclic_timing,
    noncyclic_plan, noncyclic_timing, read_number,
};

use sercon_regs::host::{HostProgram, Wake};
use sercon_regs::ram::COMPT1;
use sercon_regs::value::control::TestMode;
use sercon_regs::{
    Ctrl0C, Ctrl1, Ctrl2, Ctrl3, IntFlagsHi, IntFlagsLo, Phas, PhasRec, Register, SerconBus,
    SerconBusExt, Thrpt,
};
use sercos_wire::telegram::{CommunicationPhase, StatusWord};
use sercos_wire::time::Instant;

use crate::ram_layout::{self, PhaseGroup, RamLayout, RamLayoutRequest, RegionKind, Role};
use crate::service_channel::{ContainerSlot, ServiceChannelSlave, SlaveEvent};
use sercos_wire::idn::{Element, Idn};

/// Interrupts of 4H the slave serves (410B §4.1 4H.4, 4H.5, 4H.6, 4H.9).
const SERVED_LO: IntFlagsLo = IntFlagsLo::INT_COMEND
    .union(IntFlagsLo::INT_PHAS0)
    .union(IntFlagsLo::INT_PHASERR)
    .union(IntFlagsLo::INT_MSTMIS);

/// Most events kept for [`SlaveDriver::take_events`]; older ones are dropped.
const MAX_EVENTS: usize = 4096;

/// Most rounds of reading 4H/5H in one wake (flags raised while serving are served too).
const MAX_ROUNDS: usize = 8;

/// Where the driver is.
#[derive(Debug, Clone, PartialEq, Eq)]
enum State {
    /// Not yet initialised.
    Idle,
    /// Running.
    Running,
    /// Stopped for good by an error it cannot get around.
    Failed(SlaveError),
}

/// What PHAS0/PHAS1, 0CH and PHAS12 were last programmed to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Programmed {
    phas: Phas,
    ctrl0c: Ctrl0C,
    phas12: bool,
}

/// The SERCDRV slave over one chip, serving `device`.
#[derive(Debug)]
pub struct SlaveDriver<D> {
    config: SlaveConfig,
    device: D,
    noncyclic: RamLayout,
    noncyclic_records: Option<RecordPlaces>,
    cyclic: Option<(RamLayout, RecordPlaces)>,
    service: ServiceChannelSlave,
    phase: CommunicationPhase,
    programmed: Option<Programmed>,
    last_refused: Option<u8>,
    /// Transition checks that passed and still hold (acknowledged or not): forgotten when a
    /// parameter they read is written or the phase drops (spec-notes "Driver slave and
    /// drive node").
    passed_checks: Vec<Idn>,
    state: State,
    events: Vec<SlaveDriverEvent>,
    /// The MDT record of the cycle, reused every cycle (no allocation per cycle).
    command: Vec<u8>,
    /// The feedback data of the cycle, reused every cycle.
    feedback: Vec<u8>,
    /// CMD_AT as last written into the service container (`None`: not known, read it):
    /// only the driver writes it (spec-notes "Service containers": the chip never does in
    /// slave mode) and the service server keeps it when it stores word 0, so it is written
    /// only when the status word's bit 5 changes, not read back every cycle.
    cmd_at: Option<bool>,
    /// What was last written into the AT container of block 0 (phases 0-2).
    noncyclic_at: AtWritten,
    /// What was last written into the AT container of block 1 (phases 3-4), while laid out.
    cyclic_at: AtWritten,
}

impl<D: SlaveDevice> SlaveDriver<D> {
    /// A driver for `config` serving `device`; checks the configuration and lays out the
    /// phase 0–2 RAM (nothing is written before [`start`](Self::start)).
    pub fn new(config: SlaveConfig, device: D) -> Result<SlaveDriver<D>, SlaveError> {
        config.validate()?;
        let timing = parameters::noncyclic_timing(&config)?;
        let noncyclic = ram_layout::build(&RamLayoutRequest {
            blocks: [Some(PhaseGroup::NonCyclic), None],
            service_buffer_words: config.service_buffer_words,
            ..RamLayoutRequest::new(
                config.variant,
                Role::Slave {
                    address: config.address,
                },
                &timing,
            )
        })?;
        let service = noncyclic
            .map
            .service_containers
            .first()
            .map(|s| ContainerSlot::new(config.variant, s.nsv, s.address, s.buffer_words))
            .transpose()
            .map_err(|e| SlaveError::Device(e.to_string()))?
            .ok_or(SlaveError::Device("no service container".into()))?;
        let noncyclic_records = RecordPlaces::find(&noncyclic, PhaseGroup::NonCyclic);
        Ok(SlaveDriver {
            config,
            device,
            noncyclic,
            noncyclic_records,
            cyclic: None,
            service: ServiceChannelSlave::new(service),
            phase: CommunicationPhase::Phase0,
            programmed: None,
            last_refused: None,
            passed_checks: Vec::new(),
            state: State::Idle,
            events: Vec::new(),
            command: Vec::new(),
            feedback: Vec::new(),
            cmd_at: None,
            noncyclic_at: AtWritten::default(),
            cyclic_at: AtWritten::default(),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &SlaveConfig {
        &self.config
    }

    /// The device.
    pub fn device(&self) -> &D {
        &self.device
    }

    /// The device, mutable.
    pub fn device_mut(&mut self) -> &mut D {
        &mut self.device
    }

    /// The phase the slave follows.
    pub fn phase(&self) -> CommunicationPhase {
        self.phase
    }

    /// The phase 0–2 RAM layout.
    pub fn noncyclic_layout(&self) -> &RamLayout {
        &self.noncyclic
    }

    /// The phase 3–4 RAM layout, once laid out.
    pub fn cyclic_layout(&self) -> Option<&RamLayout> {
        self.cyclic.as_ref().map(|(layout, _)| layout)
    }

    /// The service-channel server.
    pub fn service_channel(&self) -> &ServiceChannelSlave {
        &self.service
    }

    /// The error that stopped the driver, if any.
    pub fn failure(&self) -> Option<&SlaveError> {
        match &self.state {
            State::Failed(e) => Some(e),
            _ => None,
        }
    }

    /// Takes the events since the last call.
    pub fn take_events(&mut self) -> Vec<SlaveDriverEvent> {
        std::mem::take(&mut self.events)
    }

    fn push(&mut self, event: SlaveDriverEvent) {
        if self.events.len() >= MAX_EVENTS {
            self.events.drain(..MAX_EVENTS / 2);
        }
        self.events.push(event);
    }

    /// Initialises the chip for the slave's address (see the module documentation); on an
    /// error the driver stops and reports it.
    pub fn start<B: SerconBus + ?Sized>(&mut self, bus: &mut B, now: Instant) {
        match self.try_start(bus, now) {
            Ok(()) => {
                self.state = State::Running;
                self.push(SlaveDriverEvent::Started);
            }
            Err(error) => self.fail(error),
        }
    }

    fn fail(&mut self, error: SlaveError) {
        self.state = State::Failed(error.clone());
        self.push(SlaveDriverEvent::Failed(error));
    }

    fn try_start<B: SerconBus + ?Sized>(
        &mut self,
        bus: &mut B,
        now: Instant,
    ) -> Result<(), SlaveError> {
        let c = self.config;
        // 410B §4.1 0H VERSION (ERRATA "0H VERSION": 0002H 410B, 0010H 816).
        let found = bus.detect_variant();
        if found != Some(c.variant) {
            return Err(SlaveError::WrongVariant {
                expected: c.variant,
                found,
            });
        }
        // 410B §4.1 3H: no interrupts and no telegrams while the RAM is written.
        bus.write_reg(Ctrl3::empty());
        bus.write_reg(Ctrl0C(0));
        // 410B §4.1 0EH: MCLKDIV = fMCLK / 1 MHz - 1, the µs time base of TRT and TSCYC.
        bus.write_reg(c.mclkdiv()?);
        // 410B §4.1 1H.3 REPON: a slave repeats the ring; 1H.6/10/15: the bit rate.
        let ctrl1: Ctrl1 = bus.read_reg();
        let rate = c.bit_rate_bits(ctrl1.contains(Ctrl1::SREGEN))?;
        let mut ctrl1 = ctrl1
            .difference(Ctrl1::ENTSBAUD | Ctrl1::SWBAUD | Ctrl1::SWBAUD16 | Ctrl1::SWRST)
            .union(Ctrl1::REPON);
        if let Some(bits) = rate {
            ctrl1 |= bits;
        }
        bus.write_reg(ctrl1);
        // 410B §4.1 2H.7-9 TMODE = 7: normal operation whatever the test pins say.
        let ctrl2: Ctrl2 = bus.read_reg();
        bus.write_reg(ctrl2.with_tmode(TestMode::Normal));
        // 410B §4.2: the phase 0-2 structures, then the service container's control words.
        for w in &self.noncyclic.writes {
            bus.write_ram(w.address, w.word);
        }
        self.service.init(bus);
        // 410B §4.2.4 slave table: the container starts with CMD_AT = 0 (init above).
        self.cmd_at = Some(false);
        // The RAM was written anew: nothing of the AT containers is known.
        self.noncyclic_at.forget();
        self.cyclic_at.forget();
        // 410B §4.1 0FH/10H TSCYC0/1, µs; the phase 3-4 value follows S-0-0002.
        let cycle = u16::try_from(c.noncyclic_cycle_us).unwrap_or(u16::MAX);
        bus.write(Register::Tscyc0, cycle);
        bus.write(Register::Tscyc1, cycle);
        self.phase = CommunicationPhase::Phase0;
        self.cyclic = None;
        self.programmed = None;
        self.last_refused = None;
        if let Err(refusal) = self.device.enter_phase(now, self.phase) {
            self.push(SlaveDriverEvent::DeviceRefused(refusal));
        }
        self.write_feedback(bus, now);
        self.program_phases(bus);
        // 410B §4.1 4H/5H: clear stale flags (write 1 clears, ERRATA "410B 4H/5H"), then
        // enable ours onto INT0 (6H, 7H) and INT0 itself (3H.1, ERRATA "410B 3H.1").
        bus.clear_int_lo(IntFlagsLo::all());
        bus.clear_int_hi(IntFlagsHi::all());
        bus.write(Register::En0IntLo, SERVED_LO.bits());
        bus.write(Register::En0IntHi, self.sc_flag().bits());
        bus.write(Register::En1IntLo, 0);
        bus.write(Register::En1IntHi, 0);
        // 410B §4.1 3H.8 ENTMT: send data telegrams.
        bus.write_reg(Ctrl3::ENINT0 | Ctrl3::ENTMT);
        Ok(())
    }

    fn sc_flag(&self) -> IntFlagsHi {
        IntFlagsHi::int_sc(self.service.slot().nsv()).unwrap_or(IntFlagsHi::empty())
    }

    /// Serves the chip's interrupts: phase 0, phase errors, the service container and the
    /// end of the transmission block.
    pub fn on_interrupt<B: SerconBus + ?Sized>(&mut self, bus: &mut B, now: Instant) {
        if self.state != State::Running {
            return;
        }
        for round in 0..MAX_ROUNDS {
            // 410B §4.1 3H.0 INTFL0: after a round, one read says whether an enabled flag
            // (all the driver's are on INT0) was raised while serving; only then are 4H/5H
            // read again.
            if round > 0 && !bus.read_reg::<Ctrl3>().contains(Ctrl3::INTFL0) {
                break;
            }
            let lo = bus.read_reg::<IntFlagsLo>() & SERVED_LO;
            let hi = bus.read_reg::<IntFlagsHi>() & self.sc_flag();
            if lo.is_empty() && hi.is_empty() {
                break;
            }
            // 410B §4.1 4H: write 1 clears the flags being served.
            bus.clear_int_lo(lo);
            if lo.contains(IntFlagsLo::INT_PHAS0) {
                self.back_to_phase_0(bus, now);
            }
            if lo.contains(IntFlagsLo::INT_PHASERR) {
                self.phase_error(bus);
            }
            if lo.contains(IntFlagsLo::INT_MSTMIS) {
                self.mst_lost(bus, now);
            }
            if !hi.is_empty() {
                let events = self.service.on_interrupt(bus, self.device.idn_store(), hi);
                for e in events {
                    if let SlaveEvent::Written {
                        idn,
                        element: Element::OperationData,
                    } = e
                    {
                        self.note_written(idn);
                    }
                    self.push(SlaveDriverEvent::Service(e));
                }
                self.update_arming(bus);
            }
            if lo.contains(IntFlagsLo::INT_COMEND) {
                self.end_of_block(bus, now);
            }
        }
    }

    /// 410B §4.1 4H.5 INT_PHAS0: the master is in phase 0 (again).
    fn back_to_phase_0<B: SerconBus + ?Sized>(&mut self, bus: &mut B, now: Instant) {
        self.last_refused = None;
        if self.phase != CommunicationPhase::Phase0 {
            self.enter(now, CommunicationPhase::Phase0);
        }
        self.program_phases(bus);
    }

    /// 410B §4.1 4H.9 INT_MSTMIS: the MST was missing twice in a row. The slave has lost the
    /// master's cycle: it shuts down (the drive leaves the phase, its axis stops) and waits
    /// for the master's phase-0 MSTs to start again (spec-notes "Driver slave and drive node").
    fn mst_lost<B: SerconBus + ?Sized>(&mut self, bus: &mut B, now: Instant) {
        if self.phase == CommunicationPhase::Phase0 {
            return;
        }
        self.push(SlaveDriverEvent::MstLost { phase: self.phase });
        self.last_refused = None;
        self.enter(now, CommunicationPhase::Phase0);
        self.program_phases(bus);
    }

    /// 410B §4.1 4H.6 INT_PHASERR: the MST carried a phase that is neither PHAS0 nor
    /// PHAS1; the chip processed no block.
    fn phase_error<B: SerconBus + ?Sized>(&mut self, bus: &mut B) {
        // 410B §4.1 0BH PHASREC: phase of the received MST.
        let requested = bus.read_reg::<PhasRec>().phasrec();
        if requested & 7 == 0 || self.last_refused == Some(requested) {
            return;
        }
        self.last_refused = Some(requested);
        let reason = match (self.phase.number(), requested) {
            (2, 3) if self.cyclic.is_none() && !self.check_passed(PHASE_3_CHECK) => {
                PhaseRefusal::TransitionCheckNotExecuted(PHASE_3_CHECK)
            }
            (2, 3) => PhaseRefusal::CyclicSetUpFailed,
            (3, 4) => PhaseRefusal::TransitionCheckNotExecuted(PHASE_4_CHECK),
            (_, r) if r > 4 => PhaseRefusal::NoSuchPhase,
            _ => PhaseRefusal::NotTheNextPhase,
        };
        self.push(SlaveDriverEvent::PhaseRefused {
            from: self.phase,
            requested,
            reason,
        });
    }

    /// Whether transition check `check` passed and still holds. The command's status is
    /// read first: 0007H (executed) records the pass, an error or a new run (bit 3, or
    /// set without executed) forgets it, 0 (cancelled: the master's acknowledgement, which
    /// the captures' master sends before it switches the phase) keeps it (sercos-facts.md
    /// "Procedure commands"; spec-notes "Driver slave and drive node").
    fn check_passed(&mut self, check: Idn) -> bool {
        match parameters::command_status(self.device.idn_store(), check) {
            Some(0x0007) => {
                if !self.passed_checks.contains(&check) {
                    self.passed_checks.push(check);
                }
            }
            Some(0) | None => {}
            Some(_) => self.passed_checks.retain(|&c| c != check),
        }
        self.passed_checks.contains(&check)
    }

    /// The master wrote the operation data of `idn`: a check that read it no longer holds,
    /// and an armed step to phase 3 is dropped with S-0-0127 (its layout came from them).
    fn note_written(&mut self, idn: Idn) {
        self.passed_checks
            .retain(|&check| !parameters::checked_by(check).contains(&idn));
        if self.phase == CommunicationPhase::Phase2 && !self.passed_checks.contains(&PHASE_3_CHECK)
        {
            self.cyclic = None;
        }
    }

    /// 410B §4.1 4H.4 INT_COMEND: the block ended; the MDT of this cycle is in.
    fn end_of_block<B: SerconBus + ?Sized>(&mut self, bus: &mut B, now: Instant) {
        if let Some(p) = self.programmed {
            // 410B §4.1 0AH/0CH: the chip followed PHAS1 (the step the slave had accepted).
            // PHASREC (0BH) is read only when PHAS1 is a step up: PHAS1 = 0 (nothing armed)
            // is followed by an MST of phase 0, which raised INT_PHAS0 (4H.5) at its
            // reception, served before this block's end (back_to_phase_0).
            let phas1 = p.phas.phas1();
            if phas1 != 0 && phas1 != self.phase.number() {
                let received = bus.read_reg::<PhasRec>().phasrec();
                if received == phas1 {
                    if let Ok(next) = CommunicationPhase::try_from(received) {
                        self.enter(now, next);
                    }
                }
            }
        }
        if self.phase.is_cyclic() {
            if let Some((_, places)) = &self.cyclic {
                if places.read_command_into(bus, &mut self.command) {
                    if let Err(refusal) = self.device.command_record(now, &self.command) {
                        self.push(SlaveDriverEvent::DeviceRefused(refusal));
                    }
                } else {
                    self.push(SlaveDriverEvent::CommandMissing);
                }
            }
        }
        self.update_arming(bus);
        self.write_feedback(bus, now);
    }

    fn enter(&mut self, now: Instant, phase: CommunicationPhase) {
        if phase.number() < self.phase.number() {
            // A drop of the phase: the phase-up starts again, its checks with it.
            self.passed_checks.clear();
        }
        self.phase = phase;
        self.last_refused = None;
        if let Err(refusal) = self.device.enter_phase(now, phase) {
            self.push(SlaveDriverEvent::DeviceRefused(refusal));
        }
        self.push(SlaveDriverEvent::PhaseChanged(phase));
    }

    /// The phase the slave accepts next, laying out the phase 3-4 RAM when phase 3 becomes
    /// acceptable; then programs PHAS0/PHAS1.
    fn update_arming<B: SerconBus + ?Sized>(&mut self, bus: &mut B) {
        if self.phase == CommunicationPhase::Phase2 {
            // sercos-facts.md S-0-0127: phase 3 only after the transition check (passed,
            // acknowledged or not).
            let done = self.check_passed(PHASE_3_CHECK);
            if done && self.cyclic.is_none() {
                match self.lay_out_cyclic(bus) {
                    Ok(()) => self.push(SlaveDriverEvent::CyclicSetUp),
                    Err(error) => {
                        if self.last_refused != Some(0xFE) {
                            self.last_refused = Some(0xFE);
                            self.push(SlaveDriverEvent::CyclicSetUpFailed(error));
                        }
                    }
                }
            } else if !done {
                self.cyclic = None;
            }
        }
        self.program_phases(bus);
    }

    /// Lays out block 1 (phases 3-4) from the IDN store and writes it, leaving block 0 and
    /// the service container as they are.
    fn lay_out_cyclic<B: SerconBus + ?Sized>(&mut self, bus: &mut B) -> Result<(), SlaveError> {
        let lengths = self
            .device
            .cyclic_lengths()
            .map_err(|r| SlaveError::Device(r.0))?;
        let timing = parameters::cyclic_timing(&self.config, self.device.idn_store(), lengths)?;
        let layout = ram_layout::build(&RamLayoutRequest {
            blocks: [Some(PhaseGroup::NonCyclic), Some(PhaseGroup::Cyclic)],
            buffering: self.config.buffering,
            service_buffer_words: self.config.service_buffer_words,
            ..RamLayoutRequest::new(
                self.config.variant,
                Role::Slave {
                    address: self.config.address,
                },
                &timing,
            )
        })?;
        let places = RecordPlaces::find(&layout, PhaseGroup::Cyclic)
            .ok_or(SlaveError::Device("no phase 3-4 records laid out".into()))?;
        // Block 0 lays out the same (same phase 0-2 slots): only the structures after it
        // and COMPT1 are written (410B §4.2 COMPT1: start of transmission block 1).
        let first = layout
            .map
            .blocks
            .iter()
            .find(|b| b.group == PhaseGroup::Cyclic)
            .and_then(|b| b.telegrams.first())
            .map_or(u16::MAX, |t| t.header);
        let service: Vec<(u32, u32)> = layout
            .regions
            .iter()
            .filter(|r| r.kind == RegionKind::ServiceContainer)
            .map(|r| (r.start, r.start + r.words))
            .collect();
        for w in &layout.writes {
            let in_service = service
                .iter()
                .any(|&(a, b)| (a..b).contains(&u32::from(w.address)));
            if (w.address >= first || w.address == COMPT1) && !in_service {
                bus.write_ram(w.address, w.word);
            }
        }
        // 410B §4.1 10H TSCYC1: the cycle time of block 1 (S-0-0002).
        bus.write(
            Register::Tscyc1,
            u16::try_from(timing.cycle_time_us).unwrap_or(u16::MAX),
        );
        self.cyclic = Some((layout, places));
        self.cyclic_at.forget();
        Ok(())
    }

    /// The phase after the current one that the slave accepts now, if any.
    fn acceptable_next(&mut self) -> Option<CommunicationPhase> {
        match self.phase {
            CommunicationPhase::Phase0 => Some(CommunicationPhase::Phase1),
            CommunicationPhase::Phase1 => Some(CommunicationPhase::Phase2),
            CommunicationPhase::Phase2 => {
                self.cyclic.is_some().then_some(CommunicationPhase::Phase3)
            }
            // sercos-facts.md S-0-0128: phase 4 only after the transition check.
            CommunicationPhase::Phase3 => self
                .check_passed(PHASE_4_CHECK)
                .then_some(CommunicationPhase::Phase4),
            CommunicationPhase::Phase4 => None,
        }
    }

    /// PHAS0 = current phase, PHAS1 = the acceptable next phase (else 0: a drop to phase 0
    /// runs block 0 at once), COMBLK0/1 = the block of each, PHAS12 in phases 0-2
    /// (410B §4.1 0AH, 0CH.2-3, 25H.11).
    fn program_phases<B: SerconBus + ?Sized>(&mut self, bus: &mut B) {
        let next = self.acceptable_next().unwrap_or(CommunicationPhase::Phase0);
        let wanted = Programmed {
            phas: Phas::new(self.phase.number(), next.number()),
            ctrl0c: Ctrl0C(0)
                .with_msten(true)
                .with_mstmaster(false)
                .with_comblk0(self.phase.is_cyclic())
                .with_comblk1(next.is_cyclic()),
            phas12: !self.phase.is_cyclic(),
        };
        if self.programmed == Some(wanted) {
            return;
        }
        bus.write_reg(wanted.phas);
        bus.write_reg(wanted.ctrl0c);
        // 25H.11 PHAS12: "Operating mode for SERCOS interface phase 1 and 2".
        let thrpt: Thrpt = bus.read_reg();
        bus.write_reg(thrpt.with_phas12(wanted.phas12).with_msttchk(false));
        self.programmed = Some(wanted);
    }

    /// Status word and feedback into the AT of the current block (and of block 1 while the
    /// step to phase 3 is armed, so its first AT is right); CMD_AT from status bit 5.
    fn write_feedback<B: SerconBus + ?Sized>(&mut self, bus: &mut B, now: Instant) {
        let status = self.device.status_word(now);
        self.device.feedback_data(now, &mut self.feedback);
        if let Some(places) = &self.noncyclic_records {
            if !self.phase.is_cyclic() {
                places.write_feedback_changed(bus, status, &[], &mut self.noncyclic_at);
            }
        }
        if let Some((_, places)) = &self.cyclic {
            places.write_feedback_changed(bus, status, &self.feedback, &mut self.cyclic_at);
        }
        // ERRATA "service info in a container": status bit 5 is CMD_AT of the container.
        let cmd_at = status & StatusWord::COMMAND_CHANGE != 0;
        if self.cmd_at != Some(cmd_at) {
            self.service.set_command_change(bus, cmd_at);
            self.cmd_at = Some(cmd_at);
        }
    }
}

impl<D: SlaveDevice> HostProgram for SlaveDriver<D> {
    fn wake(&mut self, bus: &mut dyn SerconBus, now: Instant, why: Wake) -> Option<Instant> {
        // A power-on restarts the host processor with a chip fresh out of reset: start over.
        if matches!(why, Wake::Start | Wake::PowerOn) || self.state == State::Idle {
            self.start(bus, now);
        } else if let Wake::Interrupt { int0: false, .. } = why {
            // 410B §4.1 3H.0-2, 6H/7H: every flag the driver serves is enabled on INT0 and
            // nothing else is, 1-active (POLINT0 = 0): INT0 low (its flags were just
            // cleared) means there is nothing to serve, so 4H/5H are not read.
            return None;
        }
        self.on_interrupt(bus, now);
        None
    }
}
