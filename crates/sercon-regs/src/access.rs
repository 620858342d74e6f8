//! Per register and variant: does it exist, its reset value, and which bits are R/W,
//! read-only status, write actions, write-1-to-clear or unused (410B §4.1, 816 §2.11).
//!
//! The chip model drives its generic register semantics from this table:
//!
//! * a read returns `(stored & rw) | (status from the chip & (read_only | w1c))`, and
//!   0 in every other bit (410B §4.1: "If control registers are read with bits that are
//!   not used, these bits are set to 0"); write-action bits read 0 unless they are also
//!   read-only status bits (28H.0 WDOG_STAT, 28H.2 WDOUT_STAT);
//! * a write stores `written & rw`, clears the status flags `written & w1c`, and triggers
//!   the actions `written & write_action`; other bits are ignored (410B §4.1: "these bits
//!   can be set to 0 or 1; they are not evaluated internally").
//!
//! The reset value of a status bit is the value the chip reports right after reset with
//! its pins inactive; pin levels (SREGEN, SBAUD, TM0-1, CYC_CLK) are not known to this
//! table and are 0 here (`docs/spec-notes.md`, "Registers (sercon-regs)").

use crate::register::{REGISTER_ADDRESS_MASK, Register};
use crate::variant::Variant;

/// Access description of one register on one variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct RegisterSpec {
    /// Whether the register exists on this variant. A register that does not exist
    /// reads 0 and ignores writes (all masks are 0).
    pub exists: bool,
    /// Value read right after a hardware reset (status bits: with pins inactive).
    pub reset: u16,
    /// R/W bits: they read back what was written.
    pub rw: u16,
    /// Read-only bits whose value comes from the chip (status, pin levels); writes to
    /// them are ignored.
    pub read_only: u16,
    /// Write-action bits (SWRST, CYCSTART, RDCNT, WDOG_START, WDOUT_SET, WDOG_TRIG,
    /// TFIFO): writing acts; they read 0, or a status where they are also in
    /// [`read_only`](Self::read_only).
    pub write_action: u16,
    /// Write-1-to-clear bits (4H, 5H, 17H, 28H.1, 28H.6): they read a flag set by the
    /// chip; writing 1 clears it, writing 0 leaves it.
    pub w1c: u16,
}

impl RegisterSpec {
    /// The spec of an address with no register: reads 0, ignores writes.
    pub const ABSENT: RegisterSpec = RegisterSpec {
        exists: false,
        reset: 0,
        rw: 0,
        read_only: 0,
        write_action: 0,
        w1c: 0,
    };

    const fn new(reset: u16, rw: u16, read_only: u16, write_action: u16, w1c: u16) -> Self {
        RegisterSpec {
            exists: true,
            reset,
            rw,
            read_only,
            write_action,
            w1c,
        }
    }

    const fn rw(reset: u16, rw: u16) -> Self {
        Self::new(reset, rw, 0, 0, 0)
    }

    const fn status(read_only: u16) -> Self {
        Self::new(0, 0, read_only, 0, 0)
    }

    /// Bits that are not used: they read 0 and writes to them are ignored.
    pub const fn unused(&self) -> u16 {
        !(self.rw | self.read_only | self.write_action | self.w1c)
    }

    /// Bits whose read value is not 0 by definition (`rw | read_only | w1c`).
    pub const fn readable(&self) -> u16 {
        self.rw | self.read_only | self.w1c
    }

    /// The stored R/W part after a bus write of `written` over `stored`.
    pub const fn stored_after_write(&self, stored: u16, written: u16) -> u16 {
        (stored & !self.rw) | (written & self.rw)
    }

    /// The value a read returns, given the stored R/W bits and the chip's status bits
    /// (status and flags; only its `read_only | w1c` bits are used).
    pub const fn read_value(&self, stored: u16, status: u16) -> u16 {
        (stored & self.rw) | (status & (self.read_only | self.w1c))
    }
}

impl Register {
    /// Access and reset description of this register on `variant`.
    pub const fn spec(self, variant: Variant) -> RegisterSpec {
        if !self.exists_on(variant) {
            // 816 §2.11.2: 28H–2AH are new; on the 410B they read 0 (task reading).
            return RegisterSpec::ABSENT;
        }
        let is816 = matches!(variant, Variant::Sercon816);
        match self {
            // 410B §4.1 0H: VERSION R, 0002H; 816 §2.11.1.1: 0010H.
            Register::Version => RegisterSpec::new(variant.version(), 0, 0xFFFF, 0, 0),
            // 410B §4.1 1H: RSTFL(0) R/W reset 1, SWRST(1) W, bit 2 unused, REPON(3) R/W
            // reset 1, SREGEN(4) R pin, REGMODE(5) R/W reset 1, SWBAUD(6) R/W 0,
            // POLRXD(7) … DMAMODE(14) R/W 0, SBAUD(11) R pin; 1H.15 SWBAUD16 on the 816
            // only (816 §2.3.1, ERRATA "410B 1H.15").
            Register::Ctrl1 => RegisterSpec::new(
                0x0029,
                if is816 { 0xF7E9 } else { 0x77E9 },
                0x0810,
                0x0002,
                0,
            ),
            // 410B §4.1 2H: ENTXD1-6 R/W reset 1, TXDMODE R/W, TMODE0-2 R/W reset 0,
            // TM0-1 R, RDIST R, FIBBR R, LMODE0-1 R/W reset 0.
            Register::Ctrl2 => RegisterSpec::new(0x003F, 0xC3FF, 0x3C00, 0, 0),
            // 410B §4.1 3H: ENINT0/POLINT0/ENINT1/POLINT1/ENTMT R/W reset 0; the rest R.
            // IDLE(14) and REACTN(15) are active-low pin levels, inactive = 1 at reset.
            Register::Ctrl3 => RegisterSpec::new(0xC000, 0x0136, 0xFEC9, 0, 0),
            // 410B §4.1 4H/5H, ERRATA "410B 4H/5H": read flags, write 1 clears.
            Register::IntFlagsLo | Register::IntFlagsHi => RegisterSpec::new(0, 0, 0, 0, 0xFFFF),
            // 410B §4.1 6H–9H: EN0_INT_n / EN1_INT_n R/W; reset 0 (no interrupt enabled).
            Register::En0IntLo | Register::En0IntHi | Register::En1IntLo | Register::En1IntHi => {
                RegisterSpec::rw(0, 0xFFFF)
            }
            // 410B §4.1 0AH: PHAS0, PHAS1 R/W, reset 0FFH each (ERRATA "410B 0AH").
            Register::Phas => RegisterSpec::rw(0xFFFF, 0xFFFF),
            // 410B §4.1 0BH: PHASREC, RECADR R.
            Register::PhasRec => RegisterSpec::status(0xFFFF),
            // 410B §4.1 0CH: MSTEN, MSTMASTER, COMBLK0/1, ENCONCLK, POLCONCLK, ENCYCCLK,
            // POLCYCCLK, NCYC R/W; CON_CLK(4), CYC_CLK(7) R levels; CYCSTART(10), RDCNT(11) W.
            Register::Ctrl0C => RegisterSpec::new(0, 0xF36F, 0x0090, 0x0C00, 0),
            // 410B §4.1 0DH: HS_TIMEOUT, BUSY_TIMEOUT R/W.
            Register::ScTimeout => RegisterSpec::rw(0, 0xFFFF),
            // 410B §4.1 0EH: MCLKDIV 4-0 reset 19, MCLKST 12-8; 816 §2.11.1.2: 5-0, 13-8.
            Register::MclkDiv => RegisterSpec::rw(19, if is816 { 0x3F3F } else { 0x1F1F }),
            // 410B §4.1 0FH–10H, 13H–16H, 18H–1FH: 16-bit R/W times.
            Register::Tscyc0
            | Register::Tscyc1
            | Register::Tcntst
            | Register::Tcycstart
            | Register::Jtscyc1
            | Register::Jtscyc2
            | Register::Jtrdel1
            | Register::Jtrdel2
            | Register::Tint0
            | Register::Tint1
            | Register::Tint2
            | Register::Tint3
            | Register::Tdivclk
            | Register::Dtdivclk => RegisterSpec::rw(0, 0xFFFF),
            // 410B §4.1 11H TCYCDEL, 12H TCNTLT, 22H THT, 24H THW, 26H THR: R.
            Register::Tcycdel
            | Register::Tcntlt
            | Register::Tht
            | Register::Thw
            | Register::Thr => RegisterSpec::status(0xFFFF),
            // 410B §4.1 17H: PROGERR_FL R / CLR_PROGERR_FL W (write 1 clears).
            Register::ProgerrFl => RegisterSpec::new(0, 0, 0, 0, 0xFFFF),
            // 410B §4.1 20H: NDIVCLK 7-0, POLDIVCLK 8 R/W reset 0; 816 §2.7: DIVCLKMODE 9.
            Register::Ndivclk => RegisterSpec::rw(0, if is816 { 0x03FF } else { 0x01FF }),
            // 410B §4.1 21H/23H: THTPT/THWPT 9-0 R; ERRATA: 11 bits on the 816.
            Register::Thtpt | Register::Thwpt => RegisterSpec::status(variant.pointer_mask()),
            // 410B §4.1 25H: THRPT 9-0 R (10 bits on both: bit 10 is MSTTCHK, see
            // spec-notes), MSTTCHK(10), PHAS12(11), FLMDTADR(12) R/W reset 0.
            Register::Thrpt => RegisterSpec::new(0, 0x1C00, 0x03FF, 0, 0),
            // 410B §4.1 27H: RFIFO R (a read pops) / TFIFO W (a write pushes).
            Register::Fifo => RegisterSpec::new(0, 0, 0xFFFF, 0xFFFF, 0),
            // 816 §2.11.2 28H: 0 WDOG_START W / WDOG_STAT R, 1 INT_WDOG R / CLR_INT_WDOG W,
            // 2 WDOUT_SET W / WDOUT_STAT R (ERRATA "816 28H.2"), 3-5 R/W, 6 INT_RSCEND R /
            // CLR_RSCEND W (ERRATA "816 28H.6"), 7-8 R/W; all reset 0.
            Register::WdogCtrl => RegisterSpec::new(0, 0x01B8, 0x0005, 0x0005, 0x0042),
            // 816 §2.11.2 29H: WDOG_TRIG 7-0 W.
            Register::WdogTrig => RegisterSpec::new(0, 0, 0, 0x00FF, 0),
            // 816 §2.11.2 2AH: TWDOG 15-0 R/W.
            Register::Twdog => RegisterSpec::rw(0, 0xFFFF),
        }
    }
}

/// Access description of any word address 00H–3FH on `variant` (higher address bits
/// are masked off as the chip decodes only A6-1); addresses without a register give
/// [`RegisterSpec::ABSENT`].
pub const fn register_spec(variant: Variant, address: u8) -> RegisterSpec {
    match Register::from_address(address & REGISTER_ADDRESS_MASK) {
        Some(register) => register.spec(variant),
        None => RegisterSpec::ABSENT,
    }
}

/// Reset values of the whole register space 00H–3FH of `variant`, indexed by word
/// address (0 where no register exists).
pub const fn reset_values(variant: Variant) -> [u16; crate::register::REGISTER_SPACE_WORDS] {
    let mut values = [0u16; crate::register::REGISTER_SPACE_WORDS];
    let mut address = 0;
    while address < values.len() {
        values[address] = register_spec(variant, address as u8).reset;
        address += 1;
    }
    values
}
