//! The events of one communication cycle, as offsets in µs from its start.
//!
//! Every timing register is compared with the time counter TCNT (410B §4.1 1AH–20H:
//! "Time at which ..."); TCNT is loaded with TCNTST at the start of a cycle and counts
//! the predivider's µs (spec-notes "TCNT"), so a register value `v` matches at the
//! offset `e` with `(TCNTST + e) mod 2¹⁶ = v`. The plan lists those offsets once per
//! configuration so that advancing costs the events, not the microseconds.

use crate::settings::Settings;

/// TCNT is a 16-bit counter (410B §4.1 12H/13H: 0-15).
const TCNT_MODULUS: u64 = 1 << 16;

/// What happens at one offset of the cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct PlanEntry {
    /// Offset from the cycle start in µs ticks.
    pub(crate) e: u64,
    /// Flags of 5H set at this offset (INT_TIME0-3).
    pub(crate) set_hi: u16,
    /// CON_CLK flip-flop: `Some(true)` at TINT0, `Some(false)` at TINT1.
    pub(crate) conclk: Option<bool>,
    /// A DIV_CLK pulse starts here (and INT_DIVCLK is set).
    pub(crate) divclk_pulse: bool,
}

/// What the entries at offset 0 (the cycle start) do together, in their order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct StartEntries {
    /// How many entries lie at offset 0 (the first of the others follows them).
    pub(crate) count: usize,
    /// The flags of 5H they set.
    pub(crate) set_hi: u16,
    /// The CON_CLK flip-flop as the last of them leaves it (TINT1 after TINT0 wins).
    pub(crate) conclk: Option<bool>,
    /// One of them starts a DIV_CLK pulse.
    pub(crate) divclk_pulse: bool,
}

/// The events of a cycle with a given configuration, sorted by offset.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub(crate) struct CyclePlan {
    /// Entries sorted by `e`; at equal `e`, TINT0 before TINT1 (so TINT1 wins).
    pub(crate) entries: Vec<PlanEntry>,
    /// The entries at offset 0 taken together: a cycle start applies them in one go.
    pub(crate) start: StartEntries,
}

/// The first offset after `after` at which TCNT, started at `tcntst`, equals `value`.
pub(crate) fn next_match(value: u16, tcntst: u16, after: u64) -> u64 {
    let from = after + 1;
    let want = u64::from(value.wrapping_sub(tcntst));
    let at_from = from % TCNT_MODULUS;
    from + (want + TCNT_MODULUS - at_from) % TCNT_MODULUS
}

/// Every offset in `[0, len)` at which TCNT (started at `tcntst`) equals `value`.
fn matches(value: u16, tcntst: u16, len: u64) -> impl Iterator<Item = u64> {
    let first = u64::from(value.wrapping_sub(tcntst));
    (0..)
        .map(move |k| first + k * TCNT_MODULUS)
        .take_while(move |e| *e < len)
}

impl CyclePlan {
    /// The plan of a cycle of `len` µs whose TCNT starts at `tcntst`.
    pub(crate) fn build(s: &Settings, tcntst: u16, len: u64) -> Self {
        let mut entries = Vec::new();
        let blank = PlanEntry {
            e: 0,
            set_hi: 0,
            conclk: None,
            divclk_pulse: false,
        };
        for (n, &tint) in s.tint.iter().enumerate() {
            // 410B §4.1 1AH–1DH / 5H.9-12: INT_TIMEn when TCNT reaches TINTn; TINT0 and
            // TINT1 also give the first and second edge of CON_CLK (0CH.5).
            let conclk = match n {
                0 => Some(true),
                1 => Some(false),
                _ => None,
            };
            for e in matches(tint, tcntst, len) {
                entries.push(PlanEntry {
                    e,
                    set_hi: 1 << (9 + n),
                    conclk,
                    ..blank
                });
            }
        }
        if s.ndivclk != 0 {
            // 410B §4.1 1EH/1FH/20H: NDIVCLK pulses, the first at TDIVCLK, then every
            // DTDIVCLK; 816 §2.7 DIVCLKMODE = 1: one pulse at TDIVCLK in chosen cycles.
            let pulses = if s.divclkmode {
                1
            } else {
                u16::from(s.ndivclk)
            };
            let mut seen = Vec::with_capacity(usize::from(pulses));
            for k in 0..pulses {
                let at = s.tdivclk.wrapping_add(k.wrapping_mul(s.dtdivclk));
                if seen.contains(&at) {
                    continue; // DTDIVCLK = 0 (or a wrap): pulses coincide.
                }
                seen.push(at);
                for e in matches(at, tcntst, len) {
                    entries.push(PlanEntry {
                        e,
                        divclk_pulse: true,
                        ..blank
                    });
                }
            }
        }
        // Stable sort keeps TINT0 before TINT1 at equal offsets.
        entries.sort_by_key(|en| en.e);
        let mut start = StartEntries::default();
        for entry in entries.iter().take_while(|en| en.e == 0) {
            start.count += 1;
            start.set_hi |= entry.set_hi;
            start.conclk = entry.conclk.or(start.conclk);
            start.divclk_pulse |= entry.divclk_pulse;
        }
        CyclePlan { entries, start }
    }

    /// Index of the first entry after offset `e`.
    pub(crate) fn first_after(&self, e: u64) -> usize {
        self.entries.partition_point(|en| en.e <= e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn next_match_wraps_the_counter() {
        assert_eq!(next_match(100, 0, 0), 100);
        assert_eq!(next_match(0, 0, 0), 65_536);
        assert_eq!(next_match(10, 20, 0), 65_526);
        assert_eq!(next_match(100, 0, 150), 65_636);
    }

    #[test]
    fn plan_lists_pulses_and_time_interrupts_in_order() {
        let s = Settings {
            tint: [5, 3, 70, 9],
            tdivclk: 2,
            dtdivclk: 10,
            ndivclk: 4,
            ..Settings::default()
        };
        let p = CyclePlan::build(&s, 0, 40);
        let es: Vec<u64> = p.entries.iter().map(|e| e.e).collect();
        assert_eq!(es, vec![2, 3, 5, 9, 12, 22, 32]);
    }
}
