//! Shared formatting of control and status words: the raw value, then the names of what is set.

use core::fmt;

/// Writes `XXXXH (name, name, ...)`, or `XXXXH (none)` when nothing is named.
pub(crate) struct NameList<'f, 'b> {
    f: &'f mut fmt::Formatter<'b>,
    first: bool,
}

impl<'f, 'b> NameList<'f, 'b> {
    /// Writes the raw word and opens the list.
    pub(crate) fn start(f: &'f mut fmt::Formatter<'b>, raw: u16) -> Result<Self, fmt::Error> {
        write!(f, "{raw:04X}H (")?;
        Ok(NameList { f, first: true })
    }

    fn separator(&mut self) -> fmt::Result {
        if !self.first {
            self.f.write_str(", ")?;
        }
        self.first = false;
        Ok(())
    }

    /// Names a one-bit flag if it is set.
    pub(crate) fn flag(&mut self, set: bool, name: &str) -> fmt::Result {
        if set {
            self.separator()?;
            self.f.write_str(name)?;
        }
        Ok(())
    }

    /// Names a multi-bit field with its value, if `shown` (the value alone if `name` is empty).
    pub(crate) fn field(
        &mut self,
        shown: bool,
        name: &str,
        value: &dyn fmt::Display,
    ) -> fmt::Result {
        if shown {
            self.separator()?;
            if name.is_empty() {
                write!(self.f, "{value}")?;
            } else {
                write!(self.f, "{name} {value}")?;
            }
        }
        Ok(())
    }

    /// Closes the list.
    pub(crate) fn finish(mut self) -> fmt::Result {
        if self.first {
            self.f.write_str("none")?;
        }
        self.first = false;
        self.f.write_str(")")
    }
}
