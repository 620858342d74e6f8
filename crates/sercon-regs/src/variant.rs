//! The two controllers this crate describes and the differences between them, as data.

/// Which controller a register map or RAM layout belongs to.
///
/// The SERCON816 is a down-compatible successor of the SERCON410B (816 §1.1); every
/// difference that affects the register map or the RAM layout is a method here.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Variant {
    /// The SERCON410B (datasheet 1994).
    #[doc(alias = "SERCON410B")]
    Sercon410b,
    /// The SERCON816 (delta specification v1.3, 1999).
    #[doc(alias = "SERCON816")]
    Sercon816,
}

impl Variant {
    /// Both variants, oldest first.
    pub const ALL: [Variant; 2] = [Variant::Sercon410b, Variant::Sercon816];

    /// The circuit code read from register VERSION (00H).
    // 816 §2.11.1.1: SERCON410B 0002H, SERCON816 0010H (ERRATA "0H VERSION").
    pub const fn version(self) -> u16 {
        match self {
            Variant::Sercon410b => 0x0002,
            Variant::Sercon816 => 0x0010,
        }
    }

    /// The variant whose VERSION register reads `version`, if any.
    pub const fn from_version(version: u16) -> Option<Variant> {
        match version {
            0x0002 => Some(Variant::Sercon410b),
            0x0010 => Some(Variant::Sercon816),
            _ => None,
        }
    }

    /// Size of the dual-port RAM in 16-bit words.
    // 410B §1: "Dual port RAM with 1024 words * 16-bit"; 816 §2.5: extended to 2048 words.
    pub const fn ram_words(self) -> u16 {
        match self {
            Variant::Sercon410b => 1024,
            Variant::Sercon816 => 2048,
        }
    }

    /// Mask of the RAM word-address bits the chip decodes (A10-1 on the 410B, A11-1 on
    /// the 816): a word address is reduced to the RAM with `address & ram_address_mask()`.
    // 410B §2 (A15-0): "A10-1 selects the words of the internal RAM"; 816 §2.5: A11-A1.
    pub const fn ram_address_mask(self) -> u16 {
        self.ram_words() - 1
    }

    /// Width in bits of a RAM pointer field (PT, THTPT, THWPT): 10 on the 410B, 11 on
    /// the 816.
    // ERRATA "word addresses": the 816 widens the pointer fields by one bit.
    pub const fn pointer_bits(self) -> u8 {
        match self {
            Variant::Sercon410b => 10,
            Variant::Sercon816 => 11,
        }
    }

    /// Mask of a RAM pointer field at bit 0 (`0x03FF` or `0x07FF`).
    pub const fn pointer_mask(self) -> u16 {
        (1u16 << self.pointer_bits()) - 1
    }

    /// Width in bits of MCLKDIV (0EH.4-0 / 0EH.5-0) and of MCLKST (0EH.12-8 / 0EH.13-8).
    // 816 §2.11.1.2: the divider and its start value are extended by one bit.
    pub const fn mclkdiv_bits(self) -> u8 {
        match self {
            Variant::Sercon410b => 5,
            Variant::Sercon816 => 6,
        }
    }

    /// Whether control bit SWBAUD16 (1H.15) exists.
    // 816 §2.3.1 table; ERRATA "410B 1H.15": reads 0 in 410B mode.
    pub const fn has_swbaud16(self) -> bool {
        matches!(self, Variant::Sercon816)
    }

    /// Whether control bit DIVCLKMODE (20H.9) exists.
    // 816 §2.7 and §2.11.1.3.
    pub const fn has_divclkmode(self) -> bool {
        matches!(self, Variant::Sercon816)
    }

    /// Whether the watchdog registers 28H–2AH exist.
    // 816 §2.11.2: new control registers 28H, 29H, 2AH.
    pub const fn has_watchdog(self) -> bool {
        matches!(self, Variant::Sercon816)
    }

    /// Word address of the last control register of this variant (27H or 2AH).
    pub const fn last_register_address(self) -> u8 {
        match self {
            Variant::Sercon410b => 0x27,
            Variant::Sercon816 => 0x2A,
        }
    }

    /// Value of REPON (1H.3) after reset given the levels of pins TM0 and TM1.
    // 410B §4.1 1H: REPON resets to 1. 816 §2.3.3: TM0 = TM1 = 0 gives 0 (repeater off),
    // every other combination 1.
    pub const fn repon_after_reset(self, tm0: bool, tm1: bool) -> bool {
        match self {
            Variant::Sercon410b => true,
            Variant::Sercon816 => tm0 || tm1,
        }
    }
}
