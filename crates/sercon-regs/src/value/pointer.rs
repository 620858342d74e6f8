//! Telegram-processor status: header pointers and header words 21H–26H (410B §4.1).

use crate::bitfield::{bool_bits, field};
use crate::error::RamError;
use crate::ram::header::HeaderKind;
use crate::value::word_register;

word_register!(
    /// 21H THTPT (R): RAM address of the header of the transmitted telegram; bits 9-0 on
    /// the 410B, 10-0 on the 816 (ERRATA "word addresses").
    #[doc(alias = "THTPT")]
    Thtpt,
    Thtpt
);
word_register!(
    /// 23H THWPT (R): RAM address of the header of the telegram expected; bits 9-0 on
    /// the 410B, 10-0 on the 816 (ERRATA "word addresses").
    #[doc(alias = "THWPT")]
    Thwpt,
    Thwpt
);

impl Thtpt {
    /// THTPT: bits 10-0 (bit 10 reads 0 on the 410B, 410B §4.1 "(Not used)").
    pub const fn thtpt(self) -> u16 {
        field(self.0, 0, 11)
    }
}

impl Thwpt {
    /// THWPT: bits 10-0 (bit 10 reads 0 on the 410B, 410B §4.1 "(Not used)").
    pub const fn thwpt(self) -> u16 {
        field(self.0, 0, 11)
    }
}

word_register!(
    /// 25H: THRPT (9-0, R), MSTTCHK (10), PHAS12 (11), FLMDTADR (12) (410B §4.1;
    /// 816 §2.9.2). THRPT keeps 10 bits on the 816 because bit 10 is MSTTCHK
    /// (`docs/spec-notes.md`).
    #[doc(alias("THRPT", "MSTTCHK", "PHAS12", "FLMDTADR"))]
    Thrpt,
    Thrpt
);

impl Thrpt {
    /// THRPT: low 10 bits of the RAM address of the header of the received telegram.
    pub const fn thrpt(self) -> u16 {
        field(self.0, 0, 10)
    }

    bool_bits! {
        /// MSTTCHK (25H.10): MST receive time is checked.
        msttchk, with_msttchk, 10;
        /// PHAS12 (25H.11): operating mode for SERCOS interface phases 1 and 2.
        phas12, with_phas12, 11;
        /// FLMDTADR (25H.12): address of the receive telegram equal to the expected value.
        flmdtadr, with_flmdtadr, 12;
    }
}

word_register!(
    /// 22H THT (R): word 0 of the header of the transmitted telegram.
    #[doc(alias = "THT")]
    Tht,
    Tht
);
word_register!(
    /// 24H THW (R): word 0 of the header of the telegram expected.
    #[doc(alias = "THW")]
    Thw,
    Thw
);
word_register!(
    /// 26H THR (R): word 0 of the header of the received telegram.
    #[doc(alias = "THR")]
    Thr,
    Thr
);

macro_rules! header_word0 {
    ($($ty:ident),*) => {$(
        impl $ty {
            /// The kind of structure this header word 0 marks (410B §4.2.1, ERRATA).
            pub const fn kind(self) -> Result<HeaderKind, RamError> {
                HeaderKind::classify(self.0)
            }

            /// ADR (bits 7-0): the telegram address.
            pub const fn adr(self) -> u8 {
                self.0 as u8
            }
        }
    )*};
}
header_word0!(Tht, Thw, Thr);
