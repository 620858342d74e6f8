//! The status word of a procedure command, as read from its operation data.
//!
//! sercos-facts.md, "Procedure commands": the master writes 3 (set and enable) to element 7
//! to start one, polls it, and writes 0 to cancel or acknowledge it; the drive signals a
//! change of command status with AT status-word bit 5. The bits of the status word are the
//! reading of docs/spec-notes.md, "IDN attributes, IDN catalog and the emulated drive":
//! bit 0 set, bit 1 enabled, bit 2 executed, bit 3 error.

/// A procedure command's status word.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct CommandStatus(pub u16);

impl CommandStatus {
    /// Bit 0: the command is set.
    pub const SET: u16 = 1 << 0;
    /// Bit 1: the command is enabled.
    pub const ENABLED: u16 = 1 << 1;
    /// Bit 2: the command was executed correctly.
    pub const EXECUTED: u16 = 1 << 2;
    /// Bit 3: the command failed.
    pub const ERROR: u16 = 1 << 3;

    /// Whether the command is set.
    pub fn is_set(self) -> bool {
        self.0 & Self::SET != 0
    }

    /// Whether it is set and enabled but neither executed nor failed yet.
    pub fn in_progress(self) -> bool {
        self.is_set() && self.0 & Self::ENABLED != 0 && !self.is_finished()
    }

    /// Whether it ended (executed or failed).
    pub fn is_finished(self) -> bool {
        self.0 & (Self::EXECUTED | Self::ERROR) != 0
    }

    /// Whether it was executed correctly.
    pub fn is_executed(self) -> bool {
        self.0 & Self::EXECUTED != 0 && self.0 & Self::ERROR == 0
    }

    /// Whether it failed.
    pub fn is_error(self) -> bool {
        self.0 & Self::ERROR != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // spec-notes "emulated drive": 0000H not set, 0003H in progress, 0007H executed,
    // 000BH error.
    #[test]
    fn status_words() {
        assert!(!CommandStatus(0).is_set());
        assert!(CommandStatus(3).in_progress());
        assert!(CommandStatus(7).is_executed() && !CommandStatus(7).in_progress());
        assert!(CommandStatus(0x0B).is_error() && CommandStatus(0x0B).is_finished());
        assert!(!CommandStatus(0x0B).is_executed());
    }
}
