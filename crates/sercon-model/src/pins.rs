//! The controller's output pins as a timed stream of level changes.
//!
//! Every output pin of the chip (410B datasheet §2, Table 1; 816 §2.2) can be traced as a
//! sequence of [`PinEvent`]s. Only traced pins cost anything: a pin nobody traces is not
//! scheduled at all (its level is still computed on demand where the registers show it).

use core::fmt;
use sercos_wire::time::Instant;

/// An output pin of the SERCON410B / SERCON816.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Pin {
    /// INT0 (pin 44): interrupt output 0, polarity by POLINT0 (3H.2).
    Int0,
    /// INT1 (pin 43): interrupt output 1, polarity by POLINT1 (3H.5).
    Int1,
    /// CON_CLK (pin 35): control clock, active from TINT0 to TINT1 (0CH.5, 0CH.6).
    ConClk,
    /// DIV_CLK (pin 36): divided control clock, 1 µs pulses (1EH, 1FH, 20H).
    DivClk,
    /// WDOGN (pin 24 on the SERCON816): watchdog output, active low (816 §2.6.1).
    Wdogn,
    /// IDLE (pin 25): transmitter active, active low while the node sends its own data.
    Idle,
    /// REACTN (pin 26): receive active, active low while a telegram is being received.
    Reactn,
    /// L_ERRN (pin 32): line error, active low (LMODE, 2H.14–15).
    LErrn,
    /// DMAREQR (pin 38): DMA request receive, active high.
    DmaReqR,
    /// DMAREQT (pin 39): DMA request transmit, active high.
    DmaReqT,
    /// TxD1 (pin 16): the transmitted line signal.
    TxD,
}

impl Pin {
    /// Every pin, in a fixed order (used for trace headers).
    pub const ALL: [Pin; 11] = [
        Pin::Int0,
        Pin::Int1,
        Pin::ConClk,
        Pin::DivClk,
        Pin::Wdogn,
        Pin::Idle,
        Pin::Reactn,
        Pin::LErrn,
        Pin::DmaReqR,
        Pin::DmaReqT,
        Pin::TxD,
    ];

    /// The datasheet's name of the pin.
    pub const fn name(self) -> &'static str {
        match self {
            Pin::Int0 => "INT0",
            Pin::Int1 => "INT1",
            Pin::ConClk => "CON_CLK",
            Pin::DivClk => "DIV_CLK",
            Pin::Wdogn => "WDOGN",
            Pin::Idle => "IDLE",
            Pin::Reactn => "REACTN",
            Pin::LErrn => "L_ERRN",
            Pin::DmaReqR => "DMAREQR",
            Pin::DmaReqT => "DMAREQT",
            Pin::TxD => "TxD",
        }
    }

    /// Looks a pin up by its datasheet name (case-insensitive, `_` optional).
    pub fn from_name(name: &str) -> Option<Pin> {
        let norm = |s: &str| -> bool {
            let a = s
                .bytes()
                .filter(|b| *b != b'_')
                .map(|b| b.to_ascii_uppercase());
            let b = name
                .bytes()
                .filter(|b| *b != b'_')
                .map(|b| b.to_ascii_uppercase());
            a.eq(b)
        };
        Pin::ALL.into_iter().find(|p| norm(p.name()))
    }

    const fn bit(self) -> u16 {
        1 << (self as u16)
    }
}

impl fmt::Display for Pin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A set of pins (for choosing which pins are traced).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub struct PinSet(u16);

impl PinSet {
    /// No pin.
    pub const EMPTY: PinSet = PinSet(0);
    /// Every pin.
    pub const ALL: PinSet = PinSet((1 << Pin::ALL.len()) - 1);

    /// A set of the given pins.
    pub fn of(pins: &[Pin]) -> PinSet {
        pins.iter().fold(PinSet::EMPTY, |s, p| s.with(*p))
    }
    /// This set plus `pin`.
    pub const fn with(self, pin: Pin) -> PinSet {
        PinSet(self.0 | pin.bit())
    }
    /// Whether `pin` is in the set.
    pub const fn contains(self, pin: Pin) -> bool {
        self.0 & pin.bit() != 0
    }
    /// Whether the set is empty.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }
    /// The pins of the set in [`Pin::ALL`] order.
    pub fn iter(self) -> impl Iterator<Item = Pin> {
        Pin::ALL.into_iter().filter(move |p| self.contains(*p))
    }
}

/// A change of level on an output pin at a point in simulated time. `level` is the electrical
/// level (true = high), after polarity bits are applied.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PinEvent {
    /// When the level changed.
    pub at: Instant,
    /// Which pin.
    pub pin: Pin,
    /// The new electrical level (true = high).
    pub level: bool,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for p in Pin::ALL {
            assert_eq!(Pin::from_name(p.name()), Some(p));
        }
        assert_eq!(Pin::from_name("conclk"), Some(Pin::ConClk));
        assert_eq!(Pin::from_name("nope"), None);
    }

    #[test]
    fn sets() {
        let s = PinSet::of(&[Pin::ConClk, Pin::DivClk]);
        assert!(s.contains(Pin::ConClk) && s.contains(Pin::DivClk) && !s.contains(Pin::Int0));
        assert_eq!(s.iter().count(), 2);
        assert_eq!(PinSet::ALL.iter().count(), Pin::ALL.len());
    }
}
