//! Why a cycle cannot be planned.

/// The timing planner refuses the configuration; every variant names the drive (where one is
/// to blame), the quantity and the numbers, in microseconds or bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum TimingError {
    /// No drive to plan for.
    #[error("no drives: phases 3-4 need at least one drive")]
    NoDrives,
    /// More drives than addresses 1-254.
    #[error("{count} drives: at most 254 fit the addresses 1-254")]
    TooManyDrives {
        /// Drives given.
        count: usize,
    },
    /// A drive address outside 1-254.
    #[error("drive address {address} is not 1-254")]
    InvalidAddress {
        /// The address given.
        address: u8,
    },
    /// Two drives with the same address.
    #[error("drive address {address} appears twice")]
    DuplicateAddress {
        /// The repeated address.
        address: u8,
    },
    /// tScyc outside what the controller can time.
    #[error("cycle time S-0-0002 = {cycle_us} µs is outside {min_us}-{max_us} µs")]
    CycleTimeOutOfRange {
        /// tScyc given.
        cycle_us: u32,
        /// Shortest cycle.
        min_us: u32,
        /// Longest cycle.
        max_us: u32,
    },
    /// The NC cycle time is not a whole multiple of tScyc.
    #[error("NC cycle time S-0-0001 = {nc_cycle_us} µs is not a multiple of tScyc = {cycle_us} µs")]
    NcCycleNotMultiple {
        /// S-0-0001 given.
        nc_cycle_us: u32,
        /// tScyc given.
        cycle_us: u32,
    },
    /// A cyclic data length that is not a whole number of 16-bit words.
    #[error(
        "drive {address}: {telegram} cyclic data of {bytes} bytes is not a whole number of words"
    )]
    OddDataLength {
        /// The drive.
        address: u8,
        /// "AT" or "MDT".
        telegram: &'static str,
        /// Bytes given.
        bytes: u32,
    },
    /// A record or telegram longer than a data container (LEN, 10 bits) or a telegram length
    /// field can describe.
    #[error("drive {address}: {telegram} needs {words} data words, at most {max_words} fit")]
    TelegramTooLong {
        /// The drive (0 for the broadcast MDT as a whole).
        address: u8,
        /// "AT record", "MDT record" or "MDT".
        telegram: &'static str,
        /// Data words needed.
        words: u32,
        /// Most data words allowed.
        max_words: u32,
    },
    /// A drive's AT cannot start at its t1min and still end before the MDT window and the end
    /// of the cycle.
    #[error(
        "drive {address}: AT at t1 = {t1_us} µs (t1min S-0-0003 = {t1min_us} µs) plus tATMT \
         S-0-0004 ends at {needed_us} µs, but the latest allowed is {latest_us} µs"
    )]
    AtTooLate {
        /// The drive.
        address: u8,
        /// The drive's t1min.
        t1min_us: u32,
        /// The t1 it would get.
        t1_us: u32,
        /// t1 + AT duration + tATMT.
        needed_us: u32,
        /// The latest t2 the cycle allows.
        latest_us: u32,
    },
    /// The telegrams, gaps and recovery times need more than one cycle.
    #[error(
        "cycle too short: {what} needs {needed_us} µs after the end of MST, the cycle leaves \
         {available_us} µs (tScyc {cycle_us} µs minus the MST)"
    )]
    CycleTooShort {
        /// What did not fit.
        what: &'static str,
        /// Time needed after the end of the MST.
        needed_us: u32,
        /// Time available after the end of the MST.
        available_us: u32,
        /// tScyc.
        cycle_us: u32,
    },
    /// No t3 satisfies t2 + MDT duration + S-0-0090 < t3 ≤ tScyc.
    #[error(
        "drive {address}: t3 must exceed t2 {t2_us} + MDT {mdt_us} + tMTSG S-0-0090 {t_mtsg_us} \
         µs but may not exceed tScyc {cycle_us} µs"
    )]
    T3Impossible {
        /// The drive with the largest S-0-0090.
        address: u8,
        /// t2.
        t2_us: u32,
        /// Worst-case MDT duration.
        mdt_us: u32,
        /// The drive's S-0-0090.
        t_mtsg_us: u32,
        /// tScyc.
        cycle_us: u32,
    },
    /// No t4 satisfies t4 ≤ tScyc − t5.
    #[error("drive {address}: t5 S-0-0005 = {t5_us} µs leaves no t4 ≤ tScyc {cycle_us} µs - t5")]
    T4Impossible {
        /// The drive with the largest t5.
        address: u8,
        /// Its t5.
        t5_us: u32,
        /// tScyc.
        cycle_us: u32,
    },
}
