//! Telegram lengths on the line with the worst-case stuffing margin.
//!
//! A telegram on the line is flag, ADR, data, FCS (2 bytes), flag (sercos-telegrams.md, field
//! tables; ERRATA "Telegrams", frame). Between the flags a 0 is inserted after every five
//! consecutive 1s (ERRATA "Telegrams", frame), so `n` bits between the flags can grow by at
//! most `⌊n / 5⌋` inserted 0s (all ones). The exact count for given bytes is
//! [`sercos_wire::line::frame_bit_len`]; the planner cannot know the data, so it reserves the
//! worst case.

use sercos_wire::line::{FCS_LEN, FLAG_BITS};
use sercos_wire::time::{BitRate, Duration};

/// Line bits of a telegram of `telegram_bytes` bytes (ADR and data, without FCS and flags)
/// when every bit between the flags is a 1: flags, bytes, FCS and one inserted 0 per five 1s.
// ERRATA "Telegrams": a 0 is stuffed after five consecutive 1s between the flags.
pub const fn worst_case_line_bits(telegram_bytes: u64) -> u64 {
    let between_flags = (telegram_bytes + FCS_LEN as u64) * 8;
    2 * FLAG_BITS + between_flags + between_flags / 5
}

/// Line bits of the same telegram without any inserted 0 (the best case).
pub const fn unstuffed_line_bits(telegram_bytes: u64) -> u64 {
    2 * FLAG_BITS + (telegram_bytes + FCS_LEN as u64) * 8
}

/// Worst-case time a telegram of `telegram_bytes` bytes occupies the line at `rate`, rounded
/// up to whole microseconds (the unit of every SERCOS time parameter and of TRT).
pub const fn worst_case_micros(telegram_bytes: u64, rate: BitRate) -> u64 {
    ceil_micros(rate.duration_of_bits(worst_case_line_bits(telegram_bytes)))
}

/// `d` in whole microseconds, rounded up.
pub const fn ceil_micros(d: Duration) -> u64 {
    d.as_picos().div_ceil(1_000_000)
}
