//! Status the telegram processor shows in the control registers (410B §4.1 3H, 0BH,
//! 11H, 17H, 21H–26H) and the flag bits it raises in 4H/5H.

/// 410B §4.1 4H.5 INT_PHAS0.
pub(crate) const INT_PHAS0: u16 = 1 << 5;
/// 410B §4.1 4H.6 INT_PHASERR.
pub(crate) const INT_PHASERR: u16 = 1 << 6;
/// 410B §4.1 4H.7 INT_MSTEARLY.
pub(crate) const INT_MSTEARLY: u16 = 1 << 7;
/// 410B §4.1 4H.8 INT_MSTLATE.
pub(crate) const INT_MSTLATE: u16 = 1 << 8;
/// 410B §4.1 4H.9 INT_MSTMIS.
pub(crate) const INT_MSTMIS: u16 = 1 << 9;
/// 410B §4.1 4H.10 INT_TSTART.
pub(crate) const INT_TSTART: u16 = 1 << 10;
/// 410B §4.1 4H.11 INT_TEND.
pub(crate) const INT_TEND: u16 = 1 << 11;
/// 410B §4.1 4H.12 INT_RWAIT.
pub(crate) const INT_RWAIT: u16 = 1 << 12;
/// 410B §4.1 4H.13 INT_RSTART.
pub(crate) const INT_RSTART: u16 = 1 << 13;
/// 410B §4.1 4H.14 INT_REND.
pub(crate) const INT_REND: u16 = 1 << 14;
/// 410B §4.1 4H.15 INT_RERR.
pub(crate) const INT_RERR: u16 = 1 << 15;
/// 410B §4.1 5H.8 INT_RMISS.
pub(crate) const INT_RMISS: u16 = 1 << 8;
/// 410B §4.1 5H.14 INT_PROGERR.
pub(crate) const INT_PROGERR: u16 = 1 << 14;
/// 410B §4.1 5H.15 INT_NEWADR.
pub(crate) const INT_NEWADR: u16 = 1 << 15;

/// The flags of PROGERR_FL (410B §4.1 17H). The datasheet gives no bit assignment; this
/// model's (spec-notes "Telegram processor and MST", "PROGERR_FL bits"):
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ProgErr {
    /// Bit 0: a header or container lies (partly) outside the RAM.
    OutsideRam = 0,
    /// Bit 1: a header list without end marker (invalid marker bits 10) or with a loop.
    NoEndMarker = 1,
    /// Bit 2: data containers overrun their telegram (POS + LEN > TLEN, Σ LEN > TLEN, or
    /// no container with LASTDC within bounds).
    ContainerOverrun = 2,
    /// Bit 3: telegrams overlap in time (a transmit telegram due before the previous one
    /// ended or before its header was reached; a block still running at the next cycle; an
    /// MST due while the transmitter still sends).
    Overlap = 3,
    /// Bit 4: a DMA FIFO under- or overrun (TFIFO short of words at the start of a
    /// telegram, RFIFO still holding words when new data arrives).
    DmaFifo = 4,
}

impl ProgErr {
    /// The bit of PROGERR_FL.
    pub(crate) const fn bit(self) -> u16 {
        1 << self as u16
    }
}
