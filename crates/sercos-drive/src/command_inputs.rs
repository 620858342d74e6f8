//! The database values the drive chooses its axis command from, read once and kept while
//! they cannot have changed, so that a cycle does not look each of them up in the IDN
//! database (twice) again.
//!
//! The drive ([`crate::drive::EmulatedDrive`]) drops them on every mutable access to its
//! database (the service channel's writes, procedure commands) and notes the IDNs it writes
//! itself (the MDT record's command values, the simulated fault's class 1 diagnostic).

use sercos_wire::idn::Idn;

use crate::database::IdnDatabase;
use crate::procedure::{CLASS_1_DIAGNOSTIC, SIMULATED_FAULT};

/// P-0-0001, the velocity loop's time constant in 0.1 ms.
pub(crate) const TIME_CONSTANT: Idn = Idn::from_raw(0x8001);
/// S-0-0032 … S-0-0035, primary and secondary operation modes (control word bits 9–8
/// choose one, sercos-telegrams.md MDT control word).
const FIRST_OPERATION_MODE: u16 = 32;
/// S-0-0036, velocity command.
pub(crate) const VELOCITY_COMMAND: Idn = Idn::from_raw(36);
/// S-0-0047, position command.
pub(crate) const POSITION_COMMAND: Idn = Idn::from_raw(47);
/// S-0-0080, torque command.
pub(crate) const TORQUE_COMMAND: Idn = Idn::from_raw(80);

/// Element 7 of each input as [`IdnDatabase::number`] gives it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct CommandInputs {
    /// P-0-0001.
    pub(crate) time_constant: Option<i128>,
    /// P-0-0003, the simulated fault.
    pub(crate) simulated_fault: Option<i128>,
    /// S-0-0011, class 1 diagnostic.
    pub(crate) class_1: Option<i128>,
    /// S-0-0032 … S-0-0035.
    pub(crate) operation_modes: [Option<i128>; 4],
    /// S-0-0036.
    pub(crate) velocity: Option<i128>,
    /// S-0-0047.
    pub(crate) position: Option<i128>,
    /// S-0-0080.
    pub(crate) torque: Option<i128>,
}

impl CommandInputs {
    /// All inputs as `database` holds them now.
    pub(crate) fn read(database: &IdnDatabase) -> CommandInputs {
        let mode = |i: u16| database.number(Idn::from_raw(FIRST_OPERATION_MODE + i));
        CommandInputs {
            time_constant: database.number(TIME_CONSTANT),
            simulated_fault: database.number(SIMULATED_FAULT),
            class_1: database.number(CLASS_1_DIAGNOSTIC),
            operation_modes: [mode(0), mode(1), mode(2), mode(3)],
            velocity: database.number(VELOCITY_COMMAND),
            position: database.number(POSITION_COMMAND),
            torque: database.number(TORQUE_COMMAND),
        }
    }

    /// The operation mode IDN `idn` is S-0-0032 + the returned index, if it is one.
    fn mode_index(idn: Idn) -> Option<usize> {
        let i = idn.raw().checked_sub(FIRST_OPERATION_MODE)?;
        (i < 4).then_some(usize::from(i))
    }

    /// Whether `idn` is one of the inputs.
    pub(crate) fn covers(idn: Idn) -> bool {
        [
            TIME_CONSTANT,
            SIMULATED_FAULT,
            CLASS_1_DIAGNOSTIC,
            VELOCITY_COMMAND,
            POSITION_COMMAND,
            TORQUE_COMMAND,
        ]
        .contains(&idn)
            || CommandInputs::mode_index(idn).is_some()
    }

    /// Takes `number`, element 7 of `idn` just written, if `idn` is one of the inputs.
    pub(crate) fn note(&mut self, idn: Idn, number: Option<i128>) {
        let slot = match idn {
            TIME_CONSTANT => &mut self.time_constant,
            SIMULATED_FAULT => &mut self.simulated_fault,
            CLASS_1_DIAGNOSTIC => &mut self.class_1,
            VELOCITY_COMMAND => &mut self.velocity,
            POSITION_COMMAND => &mut self.position,
            TORQUE_COMMAND => &mut self.torque,
            _ => match CommandInputs::mode_index(idn).and_then(|i| self.operation_modes.get_mut(i))
            {
                Some(slot) => slot,
                None => return,
            },
        };
        *slot = number;
    }

    /// S-0-0032 + `index` (0–3).
    pub(crate) fn operation_mode(&self, index: u8) -> Option<i128> {
        self.operation_modes
            .get(usize::from(index))
            .copied()
            .flatten()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sercos_wire::attribute::Value;

    // sercos-facts.md "IDNs": each input is element 7 of its IDN; a noted write gives what a
    // fresh read gives.
    #[test]
    fn noted_writes_match_a_fresh_read() {
        let mut database = IdnDatabase::standard();
        let mut inputs = CommandInputs::read(&database);
        assert_eq!(inputs, CommandInputs::read(&database));
        for (idn, value) in [
            (VELOCITY_COMMAND, Value::Signed(-123_456)),
            (POSITION_COMMAND, Value::Signed(77)),
            (TORQUE_COMMAND, Value::Signed(-5)),
            (Idn::from_raw(33), Value::Unsigned(11)),
            (CLASS_1_DIAGNOSTIC, Value::Unsigned(1 << 15)),
        ] {
            assert!(CommandInputs::covers(idn));
            assert!(database.set_internal(idn, &value).is_ok(), "{idn:?}");
            assert_ne!(
                inputs,
                CommandInputs::read(&database),
                "{idn:?} changed nothing"
            );
            inputs.note(idn, database.number(idn));
            assert_eq!(inputs, CommandInputs::read(&database), "{idn:?}");
        }
        assert!(!CommandInputs::covers(Idn::from_raw(40)));
        assert!(!CommandInputs::covers(Idn::from_raw(36 + 0x8000)));
    }
}
