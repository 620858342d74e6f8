//! The emulated drive: IDN database, cyclic data and axis, driven by the control word.
//!
//! Control word bits 15–13 (sercos-telegrams.md, MDT control word): with 111 the drive
//! follows command values; bit 14 = 0 disables torque at once; bit 15 = 0 removes torque and
//! lets the motor spin down; bit 13 = 0 halts the drive. Status word bits 15–14 (ready to
//! operate), 13 (shutdown error, class 1 diagnostic), 9–8 (actual operation mode) and 5
//! (command change) are made here (sercos-telegrams.md, AT status word).

use sercos_wire::attribute::Value;
use sercos_wire::idn::Idn;
use sercos_wire::telegram::{CommunicationPhase, ControlWord, ReadyToOperate, StatusWord};
use sercos_wire::time::{Duration, Instant};

use crate::command_inputs::CommandInputs;
use crate::database::IdnDatabase;
use crate::motion::{Axis, AxisCommand, ControlMode};
use crate::procedure::{
    CLASS_1_DIAGNOSTIC, CommandStatus, PHASE_3_TRANSITION_CHECK, PHASE_4_TRANSITION_CHECK,
};
use crate::telegram_layout::{self, CyclicLayout, LayoutError};

/// S-0-0011 bit 15, manufacturer-specific error: the simulated fault (docs/spec-notes.md).
pub const CLASS_1_MANUFACTURER_ERROR: u64 = 1 << 15;

const VELOCITY_FEEDBACK: Idn = Idn::from_raw(40);
const POSITION_FEEDBACK: Idn = Idn::from_raw(51);
const MASTER_CONTROL_WORD: Idn = Idn::from_raw(134);
const DRIVE_STATUS_WORD: Idn = Idn::from_raw(135);
const TORQUE_FEEDBACK: Idn = Idn::from_raw(0x8013);

/// Why the drive refused something the master asked.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DriveError {
    /// Phase 3 needs S-0-0127 executed, phase 4 needs S-0-0128 executed, and phases only step
    /// up one at a time (or drop back to 0).
    #[error("phase {to:?} refused from {from:?}: {reason}")]
    PhaseRefused {
        /// The current phase.
        from: CommunicationPhase,
        /// The phase asked for.
        to: CommunicationPhase,
        /// Why.
        reason: &'static str,
    },
    /// The telegram configuration cannot be laid out.
    #[error(transparent)]
    Layout(#[from] LayoutError),
    /// An MDT record is shorter than the configured layout.
    #[error("MDT record of {found} bytes, the layout needs {needed}")]
    RecordTooShort {
        /// Bytes needed.
        needed: usize,
        /// Bytes given.
        found: usize,
    },
}

/// One emulated SERCOS drive.
#[derive(Debug, Clone)]
pub struct EmulatedDrive {
    database: IdnDatabase,
    axis: Axis,
    control: ControlWord,
    layout: CyclicLayout,
    /// The instant of the last [`advance_to`](EmulatedDrive::advance_to) with nothing
    /// changed since (no mutable access to the database, no phase or control word change):
    /// advancing again to the same instant would change nothing, so it is skipped (the
    /// slave driver asks for status word and feedback at the same instant).
    settled_at: Option<Instant>,
    /// The command inputs as the database holds them (`None`: to be read again; dropped on
    /// every mutable access to the database).
    inputs: Option<CommandInputs>,
    /// What the diagnostics (S-0-0135, S-0-0095) were last made from, while nothing else
    /// they depend on can have changed (dropped with `inputs` and on a phase change).
    diagnosed: Option<DiagnosticKey>,
}

/// What the drive status word S-0-0135 and the diagnostic message S-0-0095 are made from
/// besides the database: status word, whether the axis halts, phase.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct DiagnosticKey {
    status: u16,
    halt: bool,
    phase: CommunicationPhase,
}

/// Velocity units per rpm in S-0-0036 / S-0-0040 (4 decimal places, catalogue).
const VELOCITY_SCALE: f64 = 10_000.0;
/// Position units per degree in S-0-0047 / S-0-0051 (4 decimal places, catalogue).
const POSITION_SCALE: f64 = 10_000.0;
/// rpm per percent of torque command in the torque-mode model.
const RPM_PER_TORQUE_PERCENT: f64 = 30.0;

impl EmulatedDrive {
    /// A drive with `database`, at rest, at time `now`.
    pub fn new(database: IdnDatabase, now: Instant) -> EmulatedDrive {
        let mut drive = EmulatedDrive {
            axis: Axis::new(now, Duration::from_millis(5)),
            database,
            control: ControlWord::new(),
            layout: CyclicLayout::default(),
            settled_at: None,
            inputs: None,
            diagnosed: None,
        };
        drive.apply_time_constant();
        drive.update_diagnostics();
        drive
    }

    /// The IDN database (serve the service channel from it).
    pub fn database(&self) -> &IdnDatabase {
        &self.database
    }

    /// The IDN database, mutable.
    pub fn database_mut(&mut self) -> &mut IdnDatabase {
        self.settled_at = None;
        self.inputs = None;
        self.diagnosed = None;
        &mut self.database
    }

    /// The axis.
    pub fn axis(&self) -> &Axis {
        &self.axis
    }

    /// The communication phase.
    pub fn phase(&self) -> CommunicationPhase {
        self.database.phase()
    }

    /// The cyclic layout fixed at the step to phase 3.
    pub fn layout(&self) -> &CyclicLayout {
        &self.layout
    }

    /// Follows the MST's phase. Phase 0 is always allowed; otherwise phases step up by one,
    /// phase 3 only after S-0-0127 passed and phase 4 only after S-0-0128 passed
    /// (sercos-facts.md, S-0-0127, S-0-0128), whether or not the master has cancelled
    /// (acknowledged) the command since ([`IdnDatabase::transition_check_passed`]).
    pub fn set_phase(&mut self, phase: CommunicationPhase) -> Result<(), DriveError> {
        self.settled_at = None;
        self.diagnosed = None;
        let from = self.phase();
        let refuse = |reason| {
            Err(DriveError::PhaseRefused {
                from,
                to: phase,
                reason,
            })
        };
        if phase != CommunicationPhase::Phase0 && phase != from {
            if phase.number() != from.number() + 1 {
                return refuse("phases step up one at a time");
            }
            let check = match phase {
                CommunicationPhase::Phase3 => Some(PHASE_3_TRANSITION_CHECK),
                CommunicationPhase::Phase4 => Some(PHASE_4_TRANSITION_CHECK),
                _ => None,
            };
            if let Some(check) = check {
                // sercos-facts.md S-0-0127/S-0-0128; docs/spec-notes.md "Driver slave and
                // drive node": the check passed and still holds, acknowledged or not (the
                // captures' master cancels it before it switches the phase).
                if !self.database.transition_check_passed(check) {
                    return refuse("transition check not executed");
                }
            }
            if phase == CommunicationPhase::Phase3 {
                self.layout = telegram_layout::layout(&self.database)?;
            }
        }
        self.database.set_phase(phase);
        self.update_diagnostics();
        Ok(())
    }

    /// Takes one MDT record (control word, service info, cyclic data in layout order) at
    /// time `now`. The service info is the slave driver's business and is ignored here.
    pub fn receive_mdt_record(&mut self, now: Instant, record: &[u8]) -> Result<(), DriveError> {
        let needed = self.layout.mdt_record_len();
        if record.len() < needed {
            return Err(DriveError::RecordTooShort {
                needed,
                found: record.len(),
            });
        }
        // The axis moves up to `now` under the command it had; feedback and diagnostics are
        // made once, below, after the record is taken.
        if self.settled_at != Some(now) {
            self.update_command();
            self.axis.advance_to(now);
        }
        self.settled_at = None;
        if let [low, high, ..] = record {
            self.control = ControlWord::from_raw(u16::from_le_bytes([*low, *high]));
        }
        let _ = self.database.set_internal(
            MASTER_CONTROL_WORD,
            &Value::Unsigned(u64::from(self.control.raw())),
        );
        if self.phase() == CommunicationPhase::Phase3 || self.phase() == CommunicationPhase::Phase4
        {
            for field in &self.layout.mdt {
                let Some(bytes) = record.get(field.offset..field.offset + field.len) else {
                    continue;
                };
                // Cyclic fields are fixed length, 1, 2 or 4 words (telegram_layout).
                let mut words = [0u16; 4];
                let count = bytes.len() / 2;
                for (word, pair) in words.iter_mut().zip(bytes.chunks_exact(2)) {
                    *word = u16::from_le_bytes([
                        pair.first().copied().unwrap_or(0),
                        pair.get(1).copied().unwrap_or(0),
                    ]);
                }
                let Some(words) = words.get(..count) else {
                    continue;
                };
                if let Some(parameter) = self.database.get(field.idn) {
                    if let Ok(value) = parameter.attribute.decode(words) {
                        let _ = self.database.set_internal(field.idn, &value);
                        // A command value of the record: the kept inputs take it.
                        if CommandInputs::covers(field.idn) {
                            if let Some(inputs) = &mut self.inputs {
                                inputs.note(field.idn, self.database.number(field.idn));
                            }
                        }
                    }
                }
            }
        }
        // Command, feedback and diagnostics at `now` with the record taken (what the
        // status word and AT data of this cycle are made from).
        self.advance_to(now);
        Ok(())
    }

    /// The cyclic data of the AT record (after status word and service info), in layout
    /// order, little endian.
    pub fn at_cyclic_data(&self) -> Vec<u8> {
        let mut bytes = Vec::new();
        self.write_at_cyclic_data(&mut bytes);
        bytes
    }

    /// [`at_cyclic_data`](Self::at_cyclic_data) into `bytes` (cleared first), reusing its
    /// allocation.
    pub fn write_at_cyclic_data(&self, bytes: &mut Vec<u8>) {
        bytes.clear();
        for field in &self.layout.at {
            let start = bytes.len();
            if let Some(parameter) = self.database.get(field.idn) {
                bytes.extend(parameter.words().iter().flat_map(|w| w.to_le_bytes()));
            }
            bytes.resize(start + field.len, 0);
        }
    }

    /// Advances the axis to `now` and updates feedback values and diagnostics.
    pub fn advance_to(&mut self, now: Instant) {
        if self.settled_at == Some(now) {
            return;
        }
        self.update_command();
        self.axis.advance_to(now);
        let velocity = (self.axis.velocity_rpm() * VELOCITY_SCALE).round();
        let position = (self.axis.position_deg() * POSITION_SCALE).round();
        let velocity = velocity.clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i64;
        // Position feedback wraps like a 32-bit encoder counter.
        let position = (position.rem_euclid(4_294_967_296.0) as i64 as u32) as i32;
        let _ = self
            .database
            .set_internal(VELOCITY_FEEDBACK, &Value::Signed(velocity));
        let _ = self
            .database
            .set_internal(POSITION_FEEDBACK, &Value::Signed(i64::from(position)));
        let torque = self.inputs().torque.unwrap_or(0);
        let torque = if matches!(self.axis.command(), AxisCommand::Coast) {
            0
        } else {
            torque
        };
        let _ = self.database.set_internal(
            TORQUE_FEEDBACK,
            &Value::Signed(torque.clamp(-5000, 5000) as i64),
        );
        self.update_diagnostics();
        self.settled_at = Some(now);
    }

    /// The status word without the service-channel bits (the slave driver adds AHS, busy and
    /// error).
    pub fn status_word(&self) -> StatusWord {
        let class_1 = self.class_1_error();
        // docs/spec-notes.md, "Emulated drive": 00 on a class 1 error, 01 below phase 4,
        // 10 in phase 4 without drive on + enable, 11 when following.
        let ready = if class_1 {
            ReadyToOperate::NotReadyForPowerUp
        } else if self.phase() != CommunicationPhase::Phase4 {
            ReadyToOperate::ReadyForPowerUp
        } else if self.control.drive_on() && self.control.drive_enable() {
            ReadyToOperate::ReadyToOperate
        } else {
            ReadyToOperate::PowerReady
        };
        let mut raw = u16::from(ready.bits()) << 14;
        if class_1 {
            raw |= StatusWord::SHUTDOWN_ERROR;
        }
        raw |= self.control.raw() & StatusWord::ACTUAL_OPERATION_MODE;
        if self.database.command_change() {
            raw |= StatusWord::COMMAND_CHANGE;
        }
        StatusWord::from_raw(raw)
    }

    fn class_1_error(&self) -> bool {
        let class_1 = match &self.inputs {
            Some(inputs) => inputs.class_1,
            None => self.database.number(CLASS_1_DIAGNOSTIC),
        };
        class_1.unwrap_or(0) != 0
    }

    /// The command inputs, read from the database if they were dropped.
    fn inputs(&mut self) -> CommandInputs {
        match self.inputs {
            Some(inputs) => inputs,
            None => {
                let inputs = CommandInputs::read(&self.database);
                self.inputs = Some(inputs);
                inputs
            }
        }
    }

    /// The drive wrote element 7 of `idn` itself: a command input it is takes the new value.
    fn note_written(&mut self, idn: Idn) {
        if CommandInputs::covers(idn) {
            if let Some(inputs) = &mut self.inputs {
                inputs.note(idn, self.database.number(idn));
            }
        }
    }

    fn apply_time_constant(&mut self) {
        // P-0-0001 in 0.1 ms (one decimal place, catalogue).
        let tenths = self.inputs().time_constant.unwrap_or(50).clamp(1, 100_000);
        self.axis
            .set_time_constant(Duration::from_micros(tenths as u64 * 100));
    }

    /// Chooses the axis command from the control word, phase, diagnostics and mode.
    fn update_command(&mut self) {
        self.apply_time_constant();
        let inputs = self.inputs();
        if inputs.simulated_fault.unwrap_or(0) != 0 {
            let diagnostic = inputs.class_1.unwrap_or(0) as u64;
            let _ = self.database.set_internal(
                CLASS_1_DIAGNOSTIC,
                &Value::Unsigned(diagnostic | CLASS_1_MANUFACTURER_ERROR),
            );
            self.note_written(CLASS_1_DIAGNOSTIC);
        }
        let inputs = self.inputs();
        let control = self.control;
        let following = self.phase() == CommunicationPhase::Phase4
            && !self.class_1_error()
            && control.drive_on()
            && control.drive_enable();
        let command = if !following {
            AxisCommand::Coast
        } else if !control.drive_restart() {
            AxisCommand::Halt
        } else {
            // Control word bits 9–8 choose S-0-0032…S-0-0035.
            let mode = inputs
                .operation_mode(control.operation_mode().bits())
                .unwrap_or(0);
            match ControlMode::from_operation_mode(mode) {
                Some(ControlMode::Velocity) => {
                    AxisCommand::Velocity(inputs.velocity.unwrap_or(0) as f64 / VELOCITY_SCALE)
                }
                Some(ControlMode::Position) => {
                    AxisCommand::Position(inputs.position.unwrap_or(0) as f64 / POSITION_SCALE)
                }
                Some(ControlMode::Torque) => AxisCommand::Velocity(
                    inputs.torque.unwrap_or(0) as f64 / 10.0 * RPM_PER_TORQUE_PERCENT,
                ),
                None => AxisCommand::Halt,
            }
        };
        self.axis.set_command(command);
    }

    fn update_diagnostics(&mut self) {
        let status = self.status_word();
        // Diagnostics only on change: the same status word, axis command kind and phase,
        // with the database untouched since (no service-channel write, no procedure
        // command), give the same S-0-0135 and S-0-0095.
        let key = DiagnosticKey {
            status: status.raw(),
            halt: matches!(self.axis.command(), AxisCommand::Halt),
            phase: self.phase(),
        };
        if self.diagnosed == Some(key) {
            return;
        }
        self.diagnosed = Some(key);
        let _ = self
            .database
            .set_internal(DRIVE_STATUS_WORD, &Value::Unsigned(u64::from(status.raw())));
        if self.class_1_error() {
            self.database.set_diagnostic_message(
                "F1500 class 1 error: manufacturer-specific error (P-0-0003)",
            );
        } else if let Some(text) = self.pending_command_error() {
            self.database.set_diagnostic_message(&text);
        } else {
            let message = match (status.ready_to_operate(), self.axis.command()) {
                (ReadyToOperate::ReadyToOperate, AxisCommand::Halt) => "A0010 drive halt",
                (ReadyToOperate::ReadyToOperate, _) => "A0100 drive ready to operate",
                (ReadyToOperate::PowerReady, _) => "A0013 ready for power on",
                _ => match self.phase() {
                    CommunicationPhase::Phase0 => "A0000 communication phase 0",
                    CommunicationPhase::Phase1 => "A0001 communication phase 1",
                    CommunicationPhase::Phase2 => "A0002 communication phase 2",
                    CommunicationPhase::Phase3 => "A0003 communication phase 3",
                    CommunicationPhase::Phase4 => "A0004 communication phase 4",
                },
            };
            self.database.set_diagnostic_message(message);
        }
    }

    /// The diagnostic message a failed procedure command left, while it is not cancelled.
    fn pending_command_error(&self) -> Option<String> {
        let failed = [
            PHASE_3_TRANSITION_CHECK,
            PHASE_4_TRANSITION_CHECK,
            crate::procedure::RESET_CLASS_1_DIAGNOSTIC,
        ]
        .iter()
        .any(|&idn| self.database.command_status(idn) == CommandStatus::Error);
        if !failed {
            return None;
        }
        match self
            .database
            .get(crate::database::DIAGNOSTIC_MESSAGE)
            .and_then(|p| p.value().ok())
        {
            Some(Value::Text(bytes)) => Some(String::from_utf8_lossy(&bytes).into_owned()),
            _ => None,
        }
    }
}
