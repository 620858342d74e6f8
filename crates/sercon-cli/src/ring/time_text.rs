//! Durations as the user writes them: `2s`, `1.5s`, `250ms`, `100us`, exact to the
//! picosecond (no floating point on the way).

use sercos_wire::time::Duration;

/// Picoseconds per unit, longest suffix first so `ms` is not read as `s`.
const UNITS: [(&str, u64); 6] = [
    ("ms", 1_000_000_000),
    ("us", 1_000_000),
    ("µs", 1_000_000),
    ("ns", 1_000),
    ("ps", 1),
    ("s", 1_000_000_000_000),
];

/// Parses `<decimal><unit>` with unit `s`, `ms`, `us` (or `µs`), `ns` or `ps`; `None` when
/// the text is not such a duration, has more decimals than picoseconds hold, or overflows.
pub fn parse_duration(text: &str) -> Option<Duration> {
    let text = text.trim();
    let (number, scale) = UNITS
        .iter()
        .find_map(|(unit, scale)| text.strip_suffix(unit).map(|n| (n, *scale)))?;
    let (whole, fraction) = match number.split_once('.') {
        Some((w, f)) => (w, f),
        None => (number, ""),
    };
    if whole.is_empty() && fraction.is_empty() {
        return None;
    }
    let digits = |s: &str| s.bytes().all(|b| b.is_ascii_digit());
    if !digits(whole) || !digits(fraction) {
        return None;
    }
    let whole: u64 = if whole.is_empty() {
        0
    } else {
        whole.parse().ok()?
    };
    let mut picos = whole.checked_mul(scale)?;
    // Each decimal digit is worth a tenth of the one before; digits finer than 1 ps are
    // refused rather than rounded.
    let mut place = scale;
    for b in fraction.bytes() {
        if place % 10 != 0 {
            return None;
        }
        place /= 10;
        picos = picos.checked_add(u64::from(b - b'0').checked_mul(place)?)?;
    }
    Some(Duration::from_picos(picos))
}

/// A duration in seconds with as many decimals as it needs (at most 12), e.g. `1.5s`.
pub fn format_duration(d: Duration) -> String {
    let ps = d.as_picos();
    let whole = ps / 1_000_000_000_000;
    let frac = ps % 1_000_000_000_000;
    if frac == 0 {
        return format!("{whole}s");
    }
    let digits = format!("{frac:012}");
    format!("{whole}.{}s", digits.trim_end_matches('0'))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_and_decimals() {
        assert_eq!(parse_duration("2s"), Some(Duration::from_secs(2)));
        assert_eq!(parse_duration("1.5s"), Some(Duration::from_millis(1500)));
        assert_eq!(parse_duration("250ms"), Some(Duration::from_millis(250)));
        assert_eq!(parse_duration("100us"), Some(Duration::from_micros(100)));
        assert_eq!(parse_duration("62.5ns"), Some(Duration::from_picos(62_500)));
        assert_eq!(parse_duration(".5s"), Some(Duration::from_millis(500)));
    }

    #[test]
    fn refusals() {
        for bad in [
            "",
            "s",
            "2",
            "2x",
            "-1s",
            "1.2.3s",
            "1e3s",
            "0.0000000000001s",
            "99999999999999999999s",
        ] {
            assert_eq!(parse_duration(bad), None, "{bad}");
        }
    }

    #[test]
    fn format_round_trips() {
        for d in [
            Duration::from_secs(3),
            Duration::from_millis(1500),
            Duration::from_picos(62_500),
        ] {
            assert_eq!(parse_duration(&format_duration(d)), Some(d));
        }
    }
}
