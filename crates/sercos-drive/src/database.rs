//! The drive's IDN database, served to the service channel.
//!
//! Reads and writes follow sercos-facts.md, "IDNs" (elements 1–7), "Attribute" (length,
//! procedure command, write protection in phases 2–4) and "Service channel errors" (the codes
//! returned). Procedure commands (sercos-facts.md, "Procedure commands": 3 = set and enable,
//! 0 = cancel) run at once when written; see [`crate::procedure`].

use std::collections::{BTreeMap, BTreeSet};

use sercdrv::idn_store::IdnStore;
use sercos_wire::attribute::{AttributeError, DataLength, Value};
use sercos_wire::idn::{Element, Idn};
use sercos_wire::idn_catalog::CATALOG;
use sercos_wire::service_error::{DescriptiveElement, ElementFault, ServiceError};
use sercos_wire::telegram::CommunicationPhase;

use crate::parameter::{Parameter, text_words};
use crate::procedure::{self, CommandStatus};

/// S-0-0017, IDN list of all operation data.
const ALL_OPERATION_DATA: Idn = Idn::from_raw(17);
/// S-0-0095, diagnostic message.
pub(crate) const DIAGNOSTIC_MESSAGE: Idn = Idn::from_raw(95);

/// The IDN database of one emulated drive.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct IdnDatabase {
    parameters: BTreeMap<Idn, Parameter>,
    commands: BTreeMap<Idn, CommandStatus>,
    /// Transition checks (S-0-0127, S-0-0128) that passed and still hold: a cancel
    /// (acknowledgement) keeps them, a write of a parameter they read or a drop of the
    /// phase forgets them.
    passed_checks: BTreeSet<Idn>,
    phase: CommunicationPhase,
}

impl IdnDatabase {
    /// An empty database (no IDNs), in phase 0.
    pub fn empty() -> IdnDatabase {
        IdnDatabase::default()
    }

    /// Every IDN of the catalogue (`sercos_wire::idn_catalog`) with its default value.
    pub fn standard() -> IdnDatabase {
        let mut database = IdnDatabase::empty();
        for info in CATALOG {
            // The catalogue's own test proves its defaults fit; skip one that does not.
            if let Ok(parameter) = Parameter::from_catalog(info) {
                database.insert(parameter);
            }
        }
        database
    }

    /// Adds or replaces a parameter (and refreshes S-0-0017).
    pub fn insert(&mut self, parameter: Parameter) {
        self.parameters.insert(parameter.idn, parameter);
        self.refresh_idn_list();
    }

    /// The parameter of `idn`.
    pub fn get(&self, idn: Idn) -> Option<&Parameter> {
        self.parameters.get(&idn)
    }

    /// All parameters, by IDN.
    pub fn parameters(&self) -> impl Iterator<Item = &Parameter> {
        self.parameters.values()
    }

    /// Number of IDNs.
    pub fn len(&self) -> usize {
        self.parameters.len()
    }

    /// `true` when there are no IDNs.
    pub fn is_empty(&self) -> bool {
        self.parameters.is_empty()
    }

    /// Element 7 of `idn` as a number, when present and a single integer.
    pub fn number(&self, idn: Idn) -> Option<i128> {
        self.get(idn).and_then(Parameter::number)
    }

    /// The current communication phase (for write protection).
    pub fn phase(&self) -> CommunicationPhase {
        self.phase
    }

    /// The status of procedure command `idn` ([`CommandStatus::NotSet`] if never set).
    pub fn command_status(&self, idn: Idn) -> CommandStatus {
        self.commands
            .get(&idn)
            .copied()
            .unwrap_or(CommandStatus::NotSet)
    }

    /// Whether transition check `check` (S-0-0127, S-0-0128) has been executed without
    /// error and still holds: the master may already have acknowledged (cancelled) it, as
    /// the captures' master does before it switches the phase (docs/spec-notes.md, "Driver
    /// slave and drive node"). Forgotten when a parameter the check read is written or the
    /// phase drops.
    pub fn transition_check_passed(&self, check: Idn) -> bool {
        self.passed_checks.contains(&check)
    }

    /// `true` while a procedure command has finished (executed or failed) and the master has
    /// not yet cancelled it: the drive shows this in status-word bit 5 (sercos-facts.md,
    /// "the drive signals a change of command status with status-word bit 5").
    pub fn command_change(&self) -> bool {
        self.commands
            .values()
            .any(|status| matches!(status, CommandStatus::Executed | CommandStatus::Error))
    }

    /// Sets element 7 from inside the drive (feedback values, diagnostics): checked against
    /// the attribute, not against limits or write protection.
    pub fn set_internal(&mut self, idn: Idn, value: &Value) -> Result<(), AttributeError> {
        match self.parameters.get_mut(&idn) {
            Some(parameter) => parameter.set_value(value),
            None => Err(AttributeError::WrongType),
        }
    }

    /// Sets the diagnostic message S-0-0095 (cut to its maximum length).
    pub fn set_diagnostic_message(&mut self, text: &str) {
        if let Some(parameter) = self.parameters.get_mut(&DIAGNOSTIC_MESSAGE) {
            let mut end = text.len().min(usize::from(parameter.max_len));
            while !text.is_char_boundary(end) {
                end = end.saturating_sub(1);
            }
            let bytes = text.get(..end).unwrap_or("").as_bytes();
            // Written every cycle by the drive but changed rarely: words that already hold
            // exactly the encoding of `bytes` are left alone (same result, no encoding).
            if parameter.holds_text(bytes) {
                return;
            }
            let _ = parameter.set_value(&Value::Text(bytes.to_vec()));
        }
    }

    /// Reads element `element` of `idn` as service-channel words.
    pub fn read(&self, idn: Idn, element: Element) -> Result<Vec<u16>, ServiceError> {
        let parameter = self.get(idn).ok_or(ServiceError::IdnNotPresent)?;
        let attribute = parameter.attribute;
        match element {
            Element::ServiceChannelClosed => Err(ServiceError::ServiceChannelNotOpen),
            Element::Idn => Ok(vec![idn.raw()]),
            Element::Name => Ok(text_words(&parameter.name)),
            Element::Attribute => Ok(attribute.to_words().to_vec()),
            Element::Unit => Ok(text_words(&parameter.unit)),
            Element::Minimum => limit_words(
                parameter,
                parameter.min.as_ref(),
                DescriptiveElement::Minimum,
            ),
            Element::Maximum => limit_words(
                parameter,
                parameter.max.as_ref(),
                DescriptiveElement::Maximum,
            ),
            Element::OperationData if attribute.is_procedure_command() => {
                // docs/spec-notes.md, "Emulated drive": reading a procedure command's
                // operation data returns its status (set, enabled, executed, error).
                Ok(vec![self.command_status(idn).bits()])
            }
            Element::OperationData => Ok(parameter.words().to_vec()),
        }
    }

    /// Writes element `element` of `idn` from service-channel words, with every check
    /// sercos-facts.md lists; a failed write leaves the database unchanged.
    pub fn write(&mut self, idn: Idn, element: Element, words: &[u16]) -> Result<(), ServiceError> {
        let parameter = self.get(idn).ok_or(ServiceError::IdnNotPresent)?;
        let element = match element {
            Element::ServiceChannelClosed => return Err(ServiceError::InvalidAccessToClosing),
            Element::Idn => return Err(ServiceError::InvalidAccessToElement1),
            Element::OperationData => element,
            other => {
                // Elements 2–6 are fixed in the emulated drive: x004H "cannot be changed".
                let described = DescriptiveElement::from_number(other.bits())
                    .ok_or(ServiceError::InvalidAccessToElement1)?;
                return Err(ServiceError::Element(
                    described,
                    ElementFault::CannotBeChanged,
                ));
            }
        };
        debug_assert_eq!(element, Element::OperationData);
        let attribute = parameter.attribute;
        // sercos-facts.md, attribute bits 30–28: write protection in phase 2, 3, 4.
        // Protected in all three: read only (7004H); in this phase only: 7005H.
        let everywhere = [
            CommunicationPhase::Phase2,
            CommunicationPhase::Phase3,
            CommunicationPhase::Phase4,
        ]
        .iter()
        .all(|&phase| attribute.write_protected_in(phase));
        if everywhere {
            return Err(ServiceError::OperationDataReadOnly);
        }
        if attribute.write_protected_in(self.phase) {
            return Err(ServiceError::OperationDataWriteProtectedNow);
        }
        let value = attribute.decode(words).map_err(|error| match error {
            AttributeError::TooShort { .. } => ServiceError::OperationDataTooShort,
            AttributeError::TooLong { .. } => ServiceError::OperationDataTooLong,
            _ => ServiceError::OperationDataInvalid,
        })?;
        if attribute.data_length().is_variable()
            && words.first().copied().unwrap_or(0) > parameter.max_len
        {
            return Err(ServiceError::OperationDataTooLong);
        }
        check_limits(parameter, &value)?;
        if attribute.is_procedure_command() {
            // sercos-facts.md, procedure commands: 3 = set and enable, 0 = cancel.
            return match value.as_i128() {
                Some(3) => {
                    self.start_command(idn);
                    Ok(())
                }
                Some(0) => {
                    self.commands.remove(&idn);
                    Ok(())
                }
                _ => Err(ServiceError::OperationDataInvalid),
            };
        }
        if attribute.data_length() == DataLength::Reserved {
            return Err(ServiceError::OperationDataInvalid);
        }
        if let Some(parameter) = self.parameters.get_mut(&idn) {
            parameter
                .set_words(words)
                .map_err(|_| ServiceError::OperationDataInvalid)?;
        }
        // docs/spec-notes.md "Driver slave and drive node": a check no longer holds once a
        // parameter it read has changed.
        self.passed_checks
            .retain(|&check| !procedure::checked_by(check).contains(&idn));
        Ok(())
    }

    /// Sets the phase; write protection follows it. A drop of the phase forgets the
    /// transition checks that passed (the phase-up starts again).
    pub fn set_phase(&mut self, phase: CommunicationPhase) {
        if phase.number() < self.phase.number() {
            self.passed_checks.clear();
        }
        self.phase = phase;
    }

    fn start_command(&mut self, idn: Idn) {
        let outcome = procedure::execute(self, idn);
        let status = match outcome {
            Ok(()) => {
                self.passed_checks.insert(idn);
                CommandStatus::Executed
            }
            Err(message) => {
                self.passed_checks.remove(&idn);
                self.set_diagnostic_message(&message);
                CommandStatus::Error
            }
        };
        self.commands.insert(idn, status);
    }

    fn refresh_idn_list(&mut self) {
        let idns: Vec<Idn> = self.parameters.keys().copied().collect();
        if let Some(list) = self.parameters.get_mut(&ALL_OPERATION_DATA) {
            // docs/spec-notes.md: S-0-0017 grows with the database.
            list.max_len = u16::try_from(idns.len() * 2)
                .unwrap_or(0xFFFE)
                .max(list.max_len);
            let _ = list.set_value(&Value::IdnList(idns));
        }
    }
}

fn limit_words(
    parameter: &Parameter,
    limit: Option<&Value>,
    element: DescriptiveElement,
) -> Result<Vec<u16>, ServiceError> {
    let not_present = ServiceError::Element(element, ElementFault::NotPresent);
    let value = limit.ok_or(not_present)?;
    parameter
        .attribute
        .encode(value, 0)
        .map_err(|_| not_present)
}

/// sercos-facts.md: 7006H below minimum, 7007H above maximum.
fn check_limits(parameter: &Parameter, value: &Value) -> Result<(), ServiceError> {
    let Some(number) = value.as_f64() else {
        return Ok(());
    };
    if let Some(min) = parameter.min.as_ref().and_then(Value::as_f64) {
        if number < min {
            return Err(ServiceError::OperationDataBelowMinimum);
        }
    }
    if let Some(max) = parameter.max.as_ref().and_then(Value::as_f64) {
        if number > max {
            return Err(ServiceError::OperationDataAboveMaximum);
        }
    }
    Ok(())
}

impl IdnStore for IdnDatabase {
    fn read_element(&self, idn: Idn, element: Element) -> Result<Vec<u16>, ServiceError> {
        self.read(idn, element)
    }

    fn write_element(
        &mut self,
        idn: Idn,
        element: Element,
        words: &[u16],
    ) -> Result<(), ServiceError> {
        self.write(idn, element, words)
    }

    fn set_phase(&mut self, phase: CommunicationPhase) {
        IdnDatabase::set_phase(self, phase);
    }
}
