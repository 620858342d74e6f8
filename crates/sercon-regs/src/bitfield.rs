//! Bit and field helpers shared by the register values and the RAM structures.

/// Bit `bit` of `word`.
pub(crate) const fn bit(word: u16, bit: u8) -> bool {
    (word >> bit) & 1 != 0
}

/// `word` with bit `bit` set to `value`.
pub(crate) const fn with_bit(word: u16, bit: u8, value: bool) -> u16 {
    if value {
        word | (1 << bit)
    } else {
        word & !(1 << bit)
    }
}

/// Mask of `width` bits at bit 0 (`width` ≤ 16).
pub(crate) const fn mask(width: u8) -> u16 {
    if width >= 16 {
        0xFFFF
    } else {
        (1u16 << width) - 1
    }
}

/// The `width`-bit field at `shift` of `word`.
pub(crate) const fn field(word: u16, shift: u8, width: u8) -> u16 {
    (word >> shift) & mask(width)
}

/// `word` with the `width`-bit field at `shift` replaced by `value` (extra bits of
/// `value` are dropped; callers check the range first).
pub(crate) const fn with_field(word: u16, shift: u8, width: u8, value: u16) -> u16 {
    let m = mask(width) << shift;
    (word & !m) | ((value << shift) & m)
}

/// Declares `pub const fn $get(self) -> bool` and `pub const fn $set(self, bool) -> Self`
/// for bit `$bit` of a `struct(u16)`.
macro_rules! bool_bits {
    ($( $(#[$meta:meta])* $get:ident, $set:ident, $bit:literal; )*) => {
        $(
            $(#[$meta])*
            pub const fn $get(self) -> bool {
                $crate::bitfield::bit(self.0, $bit)
            }
            #[doc = concat!("This value with `", stringify!($get), "` (bit ", stringify!($bit), ") set to `value`.")]
            #[must_use]
            pub const fn $set(self, value: bool) -> Self {
                Self($crate::bitfield::with_bit(self.0, $bit, value))
            }
        )*
    };
}
pub(crate) use bool_bits;
