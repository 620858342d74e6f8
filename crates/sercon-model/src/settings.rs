//! The register bits that steer the model's behaviour, decoded once per register write.
//!
//! The stored R/W words live in [`crate::register_file::RegisterFile`]; this is the
//! decoded view the event loop reads, so advancing never decodes registers.

use sercon_regs::{Register, Variant};

use crate::register_file::RegisterFile;

/// The bit `n` of `word`.
const fn bit(word: u16, n: u8) -> bool {
    word & (1 << n) != 0
}

/// Decoded behaviour-relevant register contents.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Settings {
    /// 410B §4.1 3H.1 ENINT0 (ERRATA: 1 = enabled), 3H.4 ENINT1.
    pub(crate) enint: [bool; 2],
    /// 410B §4.1 3H.2 POLINT0, 3H.5 POLINT1 (ERRATA: 0 = 1-active).
    pub(crate) polint: [bool; 2],
    /// 410B §4.1 6H/7H (INT0) and 8H/9H (INT1): enables of the flags of 4H and 5H.
    pub(crate) en_lo: [u16; 2],
    /// See [`Settings::en_lo`].
    pub(crate) en_hi: [u16; 2],
    /// The flags of 4H an enabled interrupt output carries (6H with 3H.1 ENINT0, 8H with
    /// 3H.4 ENINT1): only these can be seen at the moment they rise; the telegram
    /// processor's events that raise nothing else (a receive window's opening, a transmit
    /// telegram's end, the end marker) are events of their own only when their flag is
    /// here (spec-notes "Events nobody sees at once").
    pub(crate) int_out_lo: u16,
    /// 816 §2.11.2 28H.3 EN0_INT_WDOG, 28H.4 EN1_INT_WDOG.
    pub(crate) en_wdog: [bool; 2],
    /// 816 §2.11.2 28H.7 EN0_INT_RSCEND, 28H.8 EN1_INT_RSCEND.
    pub(crate) en_rscend: [bool; 2],
    /// 816 §2.11.2 28H.5 WDOG_MSTEN.
    pub(crate) wdog_msten: bool,
    /// 410B §4.1 0CH.0 MSTEN.
    pub(crate) msten: bool,
    /// 410B §4.1 0CH.1 MSTMASTER.
    pub(crate) mstmaster: bool,
    /// 410B §4.1 0CH.2 COMBLK0: the block processed when the phase is PHAS0.
    pub(crate) comblk0: bool,
    /// 410B §4.1 0CH.5 ENCONCLK.
    pub(crate) enconclk: bool,
    /// 410B §4.1 0CH.6 POLCONCLK (1 = 0-active).
    pub(crate) polconclk: bool,
    /// 410B §4.1 0CH.8 ENCYCCLK.
    pub(crate) encycclk: bool,
    /// 410B §4.1 0CH.9 POLCYCCLK (0 = rising edge, 1 = falling edge).
    pub(crate) polcycclk: bool,
    /// 410B §4.1 0CH.12-15 NCYC.
    pub(crate) ncyc: u8,
    /// 410B §4.1 0EH MCLKDIV (4-0; 816 §2.11.1.2: 5-0).
    pub(crate) mclkdiv: u16,
    /// 410B §4.1 0EH MCLKST (12-8; 816 §2.11.1.2: 13-8).
    pub(crate) mclkst: u16,
    /// 410B §4.1 0FH TSCYC0, 10H TSCYC1.
    pub(crate) tscyc: [u16; 2],
    /// 410B §4.1 13H TCNTST.
    pub(crate) tcntst: u16,
    /// 410B §4.1 14H TCYCSTART.
    pub(crate) tcycstart: u16,
    /// 410B §4.1 1AH–1DH TINT0–3.
    pub(crate) tint: [u16; 4],
    /// 410B §4.1 1EH TDIVCLK.
    pub(crate) tdivclk: u16,
    /// 410B §4.1 1FH DTDIVCLK.
    pub(crate) dtdivclk: u16,
    /// 410B §4.1 20H.7-0 NDIVCLK.
    pub(crate) ndivclk: u8,
    /// 410B §4.1 20H.8 POLDIVCLK (1 = 0-active).
    pub(crate) poldivclk: bool,
    /// 816 §2.7 20H.9 DIVCLKMODE.
    pub(crate) divclkmode: bool,
    /// 816 §2.11.2 2AH TWDOG.
    pub(crate) twdog: u16,
    /// Width of MCLKDIV/MCLKST (5 on the 410B, 6 on the 816).
    pub(crate) mclkdiv_bits: u8,
}

impl Settings {
    /// Decodes the stored words of `regs` (R/W bits only; the table of sercon-regs has
    /// already masked bits the variant lacks).
    pub(crate) fn decode(regs: &RegisterFile, variant: Variant) -> Self {
        let r = |reg: Register| regs.stored(reg);
        let c3 = r(Register::Ctrl3);
        let c0c = r(Register::Ctrl0C);
        let wd = r(Register::WdogCtrl);
        let div = r(Register::MclkDiv);
        let nd = r(Register::Ndivclk);
        let bits = variant.mclkdiv_bits();
        let field = (1u16 << bits) - 1;
        Settings {
            enint: [bit(c3, 1), bit(c3, 4)],
            polint: [bit(c3, 2), bit(c3, 5)],
            en_lo: [r(Register::En0IntLo), r(Register::En1IntLo)],
            en_hi: [r(Register::En0IntHi), r(Register::En1IntHi)],
            int_out_lo: (if bit(c3, 1) { r(Register::En0IntLo) } else { 0 })
                | (if bit(c3, 4) { r(Register::En1IntLo) } else { 0 }),
            en_wdog: [bit(wd, 3), bit(wd, 4)],
            en_rscend: [bit(wd, 7), bit(wd, 8)],
            wdog_msten: bit(wd, 5),
            msten: bit(c0c, 0),
            mstmaster: bit(c0c, 1),
            comblk0: bit(c0c, 2),
            enconclk: bit(c0c, 5),
            polconclk: bit(c0c, 6),
            encycclk: bit(c0c, 8),
            polcycclk: bit(c0c, 9),
            ncyc: (c0c >> 12) as u8,
            mclkdiv: div & field,
            mclkst: (div >> 8) & field,
            tscyc: [r(Register::Tscyc0), r(Register::Tscyc1)],
            tcntst: r(Register::Tcntst),
            tcycstart: r(Register::Tcycstart),
            tint: [
                r(Register::Tint0),
                r(Register::Tint1),
                r(Register::Tint2),
                r(Register::Tint3),
            ],
            tdivclk: r(Register::Tdivclk),
            dtdivclk: r(Register::Dtdivclk),
            ndivclk: (nd & 0xFF) as u8,
            poldivclk: bit(nd, 8),
            divclkmode: bit(nd, 9),
            twdog: r(Register::Twdog),
            mclkdiv_bits: bits,
        }
    }

    /// Whether the chip is a SERCOS slave (MSTEN = 1, MSTMASTER = 0): its cycles start
    /// on MST reception, not on CYCSTART or CYC_CLK (410B §4.1 0CH.10 "(master)").
    pub(crate) fn is_sercos_slave(&self) -> bool {
        self.msten && !self.mstmaster
    }

    /// Whether an MST is sent at each cycle start (SERCOS master: MSTEN = MSTMASTER = 1).
    pub(crate) fn sends_mst(&self) -> bool {
        self.msten && self.mstmaster
    }
}
