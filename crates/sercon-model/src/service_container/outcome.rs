//! What one step of a service container reports back to the telegram processor.

use core::ops::{BitOr, BitOrAssign};

/// The interrupt bits of a service container's control words that a step raised
/// (410B §4.2.4, both tables). Each set bit was written 1 into the container by this step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ScInterrupts(u16);

impl ScInterrupts {
    /// No interrupt bit.
    pub const NONE: ScInterrupts = ScInterrupts(0);
    /// INT_ERR (master word 0.12): the slave reports an error.
    pub const INT_ERR: ScInterrupts = ScInterrupts(1 << 0);
    /// INT_END_WRBUF (word 0.13, both modes): end of the write buffer is reached.
    pub const INT_END_WRBUF: ScInterrupts = ScInterrupts(1 << 1);
    /// INT_END_RDBUF (word 0.14, both modes): end of the read buffer is reached.
    pub const INT_END_RDBUF: ScInterrupts = ScInterrupts(1 << 2);
    /// INT_SC_ERR (word 4.9, both modes): protocol error.
    pub const INT_SC_ERR: ScInterrupts = ScInterrupts(1 << 3);
    /// INT_HS_TIMEOUT (master word 4.10): handshake timeout.
    pub const INT_HS_TIMEOUT: ScInterrupts = ScInterrupts(1 << 4);
    /// INT_BUSY_TIMEOUT (master word 4.11): BUSY timeout.
    pub const INT_BUSY_TIMEOUT: ScInterrupts = ScInterrupts(1 << 5);
    /// INT_CMD (master word 4.12): the slave has set the command modification bit.
    pub const INT_CMD: ScInterrupts = ScInterrupts(1 << 6);
    /// INT_ELEM_CHANGE (slave word 0.12): the master has modified data element or
    /// read/write.
    pub const INT_ELEM_CHANGE: ScInterrupts = ScInterrupts(1 << 7);
    /// INT_END_MDT (slave word 0.15): the master reports the end via END_MDT.
    pub const INT_END_MDT: ScInterrupts = ScInterrupts(1 << 8);

    /// The raw bits (this type's own numbering, not the RAM's).
    pub const fn bits(self) -> u16 {
        self.0
    }

    /// Whether no bit is set.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// Whether every bit of `other` is set in `self`.
    pub const fn contains(self, other: ScInterrupts) -> bool {
        self.0 & other.0 == other.0
    }

    /// The bits of both.
    pub const fn union(self, other: ScInterrupts) -> ScInterrupts {
        ScInterrupts(self.0 | other.0)
    }
}

impl BitOr for ScInterrupts {
    type Output = ScInterrupts;

    fn bitor(self, rhs: ScInterrupts) -> ScInterrupts {
        self.union(rhs)
    }
}

impl BitOrAssign for ScInterrupts {
    fn bitor_assign(&mut self, rhs: ScInterrupts) {
        *self = self.union(rhs);
    }
}

/// What a call into the service container did, for the chip around it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ScOutcome {
    /// The container raised at least one of its interrupt bits: the chip sets INT_SC_n
    /// (5H.n, 410B §4.1) for container `n`.
    pub int_sc: bool,
    /// Which interrupt bits of the container were raised (written 1) by this call.
    pub raised: ScInterrupts,
    /// A handshake step completed in this call: master mode, the slave acknowledged the
    /// step (AHS = MHS, BUSY = 0, `on_receive`) or a new step was started with MHS toggled
    /// (`on_transmit`); slave mode, the container answered the master's step with AHS = MHS
    /// (`on_receive`).
    pub handshake: bool,
    /// Info words this call moved between the record and the container's buffers (filled
    /// into the record on transmit, taken into the read buffer on receive).
    pub info_words: u8,
    /// RAM words read or written (SCPTn, control words, buffer words); the telegram
    /// processor may use it for the RAM access time.
    pub ram_accesses: u16,
    /// SERCON816 only, on receive: the service-container work for this record is complete,
    /// so the chip may raise INT_RSCEND (28H.6) at the end of the receive telegram
    /// (816 §2.10.2.2). Always `false` on the SERCON410B and outside `on_receive`.
    pub rscend: bool,
}

impl ScOutcome {
    /// Records that the container raised `bits`.
    pub(super) fn raise(&mut self, bits: ScInterrupts) {
        self.raised |= bits;
        // 410B §4.1 5H: INT_SC_n, "Interrupt service container".
        self.int_sc = true;
    }
}
