//! Line bit buffers: bits packed most significant bit first, with an explicit length.

/// A read-only view of line bits: bit `i` is bit `7 - (start + i) % 8` of byte
/// `(start + i) / 8`, i.e. packed most significant bit first as in the capture files.
/// Two views are equal when they hold the same bits.
#[derive(Debug, Clone, Copy)]
pub struct Bits<'a> {
    bytes: &'a [u8],
    start: usize,
    len: usize,
}

impl<'a> Bits<'a> {
    /// Every bit of `bytes`.
    pub fn from_bytes(bytes: &'a [u8]) -> Self {
        Bits {
            bytes,
            start: 0,
            len: bytes.len().saturating_mul(8),
        }
    }

    /// The first `bit_len` bits of `bytes`, or `None` when `bytes` holds fewer bits.
    pub fn new(bytes: &'a [u8], bit_len: usize) -> Option<Self> {
        (bit_len <= bytes.len().saturating_mul(8)).then_some(Bits {
            bytes,
            start: 0,
            len: bit_len,
        })
    }

    /// Number of bits in the view.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the view holds no bit.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Bit `i`, or `None` past the end.
    pub fn get(&self, i: usize) -> Option<bool> {
        if i >= self.len {
            return None;
        }
        let at = self.start + i;
        self.bytes.get(at / 8).map(|b| (b >> (7 - at % 8)) & 1 == 1)
    }

    /// The bits `from..to` of this view, or `None` when the range is out of bounds or reversed.
    pub fn slice(&self, from: usize, to: usize) -> Option<Bits<'a>> {
        (from <= to && to <= self.len).then_some(Bits {
            bytes: self.bytes,
            start: self.start + from,
            len: to - from,
        })
    }

    /// The underlying bytes, the offset of bit 0 in them, and the length.
    pub(crate) fn raw(&self) -> (&'a [u8], usize, usize) {
        (self.bytes, self.start, self.len)
    }

    /// Iterator over the bits, first bit first.
    pub fn iter(&self) -> impl Iterator<Item = bool> + '_ {
        (0..self.len).map(|i| self.get(i).unwrap_or(false))
    }
}

impl PartialEq for Bits<'_> {
    fn eq(&self, other: &Self) -> bool {
        self.len == other.len && self.iter().eq(other.iter())
    }
}

impl Eq for Bits<'_> {}

/// The sink was full: the bits did not fit into the caller's buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[error("line bit buffer full: {capacity} bits")]
pub struct SinkFull {
    /// Capacity of the sink in bits.
    pub capacity: u64,
}

/// Where an encoder writes line bits.
pub trait BitSink {
    /// Bits written so far.
    fn bit_len(&self) -> u64;

    /// Appends the low `n` bits of `bits` (`n` ≤ 32), the most significant of them first.
    /// On error nothing is appended.
    fn put(&mut self, bits: u32, n: u32) -> Result<(), SinkFull>;

    /// Drops every bit from `len` on (used to undo a telegram that did not fit).
    fn truncate(&mut self, len: u64);
}

/// Writes line bits into a caller's byte buffer, most significant bit first.
#[derive(Debug)]
pub struct BitWriter<'a> {
    buf: &'a mut [u8],
    len: u64,
}

impl<'a> BitWriter<'a> {
    /// A writer that starts at bit 0 of `buf`.
    pub fn new(buf: &'a mut [u8]) -> Self {
        BitWriter { buf, len: 0 }
    }

    /// The bits written so far.
    pub fn bits(&self) -> Bits<'_> {
        Bits {
            bytes: self.buf,
            start: 0,
            len: usize::try_from(self.len).unwrap_or(usize::MAX),
        }
    }

    /// Capacity in bits.
    pub fn capacity(&self) -> u64 {
        (self.buf.len() as u64).saturating_mul(8)
    }
}

/// Writes `n` bits (MSB first of the low `n` of `bits`) at bit `at` of `buf`; the caller has
/// checked that they fit.
fn write_bits(buf: &mut [u8], at: u64, bits: u32, n: u32) {
    if n == 0 {
        return;
    }
    // Left-align the n bits in a u64 starting at bit offset at % 8.
    let off = (at % 8) as u32;
    let v = (u64::from(bits) << (64 - n)) >> off;
    let first = (at / 8) as usize;
    let nbytes = (off + n).div_ceil(8) as usize;
    for (k, byte) in buf.iter_mut().skip(first).take(nbytes).enumerate() {
        let part = (v >> (56 - 8 * k)) as u8;
        if k == 0 {
            let keep = !(0xFFu8 >> off);
            *byte = (*byte & keep) | part;
        } else {
            *byte = part;
        }
    }
}

impl BitSink for BitWriter<'_> {
    fn bit_len(&self) -> u64 {
        self.len
    }

    fn put(&mut self, bits: u32, n: u32) -> Result<(), SinkFull> {
        let n = n.min(32);
        let end = self.len + u64::from(n);
        if end > self.capacity() {
            return Err(SinkFull {
                capacity: self.capacity(),
            });
        }
        write_bits(self.buf, self.len, bits, n);
        self.len = end;
        Ok(())
    }

    fn truncate(&mut self, len: u64) {
        self.len = self.len.min(len);
    }
}

/// A growable buffer of line bits (with the `alloc` feature).
#[cfg(feature = "alloc")]
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct BitVec {
    bytes: alloc::vec::Vec<u8>,
    len: u64,
}

#[cfg(feature = "alloc")]
impl BitVec {
    /// An empty buffer.
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty buffer with room for `bits` bits.
    pub fn with_capacity(bits: usize) -> Self {
        BitVec {
            bytes: alloc::vec::Vec::with_capacity(bits.div_ceil(8)),
            len: 0,
        }
    }

    /// A view of the bits.
    pub fn bits(&self) -> Bits<'_> {
        Bits {
            bytes: &self.bytes,
            start: 0,
            len: usize::try_from(self.len).unwrap_or(usize::MAX),
        }
    }

    /// The packed bytes (the last one padded with 0s).
    pub fn as_bytes(&self) -> &[u8] {
        &self.bytes
    }

    /// Number of bits.
    pub fn len(&self) -> u64 {
        self.len
    }

    /// Whether the buffer holds no bit.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Removes every bit.
    pub fn clear(&mut self) {
        self.bytes.clear();
        self.len = 0;
    }

    /// Appends one bit.
    pub fn push(&mut self, bit: bool) {
        let _ = self.put(u32::from(bit), 1);
    }

    /// A copy of the bits of `bits` (a byte at a time, whatever their offset; the padding
    /// is 0).
    pub fn from_bits(bits: Bits<'_>) -> BitVec {
        let (src, start, len) = bits.raw();
        let first = start / 8;
        let shift = (start % 8) as u32;
        let n = len.div_ceil(8);
        let byte = |i: usize| src.get(i).copied().unwrap_or(0);
        let mut bytes: alloc::vec::Vec<u8> = (first..first + n)
            .map(|i| {
                if shift == 0 {
                    byte(i)
                } else {
                    (byte(i) << shift) | (byte(i + 1) >> (8 - shift))
                }
            })
            .collect();
        let rem = (len % 8) as u32;
        if rem != 0
            && let Some(last) = bytes.last_mut()
        {
            *last &= !(0xFFu8 >> rem);
        }
        BitVec {
            bytes,
            len: len as u64,
        }
    }

    /// The same bits, each inverted (a byte at a time; the padding stays 0).
    pub fn inverted(&self) -> BitVec {
        let mut bytes: alloc::vec::Vec<u8> = self.bytes.iter().map(|b| !b).collect();
        let rem = (self.len % 8) as u32;
        if rem != 0
            && let Some(last) = bytes.last_mut()
        {
            *last &= !(0xFFu8 >> rem);
        }
        BitVec {
            bytes,
            len: self.len,
        }
    }
}

#[cfg(feature = "alloc")]
impl BitSink for BitVec {
    fn bit_len(&self) -> u64 {
        self.len
    }

    fn put(&mut self, bits: u32, n: u32) -> Result<(), SinkFull> {
        let n = n.min(32);
        let end = self.len + u64::from(n);
        let need = usize::try_from(end.div_ceil(8)).map_err(|_| SinkFull { capacity: self.len })?;
        if need > self.bytes.len() {
            self.bytes.resize(need, 0);
        }
        write_bits(&mut self.bytes, self.len, bits, n);
        self.len = end;
        Ok(())
    }

    fn truncate(&mut self, len: u64) {
        if len < self.len {
            self.len = len;
            let keep = usize::try_from(len.div_ceil(8)).unwrap_or(usize::MAX);
            self.bytes.truncate(keep);
            let rem = (len % 8) as u32;
            if rem != 0
                && let Some(last) = self.bytes.last_mut()
            {
                *last &= !(0xFFu8 >> rem);
            }
        }
    }
}
