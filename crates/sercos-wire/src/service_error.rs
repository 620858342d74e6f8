//! The standard service-channel error codes a drive returns in place of data.
//!
//! sercos-facts.md, "Service channel errors" (Bosch Rexroth IndraDrive manual; Rockwell):
//! 0001H service channel not open, 0009H invalid access to closing the service channel,
//! 1001H IDN not present, 1009H invalid access to element 1, x001H–x005H for elements 2–6
//! (not present, too short, too long, cannot be changed, write-protected now), and
//! 7002H–7009H for the operation data. Codes the table does not list are kept as
//! [`ServiceError::Unknown`].

use core::fmt;

/// Data block elements 2–6, whose errors follow the pattern x001H–x005H.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(u8)]
pub enum DescriptiveElement {
    /// Element 2, the name.
    Name = 2,
    /// Element 3, the attribute.
    Attribute = 3,
    /// Element 4, the unit.
    Unit = 4,
    /// Element 5, the minimum input value.
    Minimum = 5,
    /// Element 6, the maximum input value.
    Maximum = 6,
}

impl DescriptiveElement {
    /// The element number, 2–6.
    pub const fn number(self) -> u8 {
        self as u8
    }

    /// The element from its number; `None` outside 2–6.
    pub const fn from_number(number: u8) -> Option<DescriptiveElement> {
        match number {
            2 => Some(DescriptiveElement::Name),
            3 => Some(DescriptiveElement::Attribute),
            4 => Some(DescriptiveElement::Unit),
            5 => Some(DescriptiveElement::Minimum),
            6 => Some(DescriptiveElement::Maximum),
            _ => None,
        }
    }

    /// A short lower-case name.
    pub const fn name(self) -> &'static str {
        match self {
            DescriptiveElement::Name => "name",
            DescriptiveElement::Attribute => "attribute",
            DescriptiveElement::Unit => "unit",
            DescriptiveElement::Minimum => "minimum",
            DescriptiveElement::Maximum => "maximum",
        }
    }
}

/// What went wrong with element 2–6: the low nibble of the code x001H–x005H.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum ElementFault {
    /// x001H: the element is not present.
    NotPresent = 1,
    /// x002H: the element is too short.
    TooShort = 2,
    /// x003H: the element is too long.
    TooLong = 3,
    /// x004H: the element cannot be changed (read only).
    CannotBeChanged = 4,
    /// x005H: the element is write-protected at this time.
    WriteProtectedNow = 5,
}

impl ElementFault {
    const fn from_nibble(nibble: u16) -> Option<ElementFault> {
        match nibble {
            1 => Some(ElementFault::NotPresent),
            2 => Some(ElementFault::TooShort),
            3 => Some(ElementFault::TooLong),
            4 => Some(ElementFault::CannotBeChanged),
            5 => Some(ElementFault::WriteProtectedNow),
            _ => None,
        }
    }

    const fn meaning(self) -> &'static str {
        match self {
            ElementFault::NotPresent => "not present",
            ElementFault::TooShort => "too short",
            ElementFault::TooLong => "too long",
            ElementFault::CannotBeChanged => "cannot be changed",
            ElementFault::WriteProtectedNow => "write-protected at this time",
        }
    }
}

/// A service-channel error code (sercos-facts.md, "Service channel errors").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ServiceError {
    /// 0001H: service channel not open.
    ServiceChannelNotOpen,
    /// 0009H: invalid access to closing the service channel.
    InvalidAccessToClosing,
    /// 1001H: IDN not present.
    IdnNotPresent,
    /// 1009H: invalid access to element 1.
    InvalidAccessToElement1,
    /// x001H–x005H: a fault of element x = 2–6.
    Element(DescriptiveElement, ElementFault),
    /// 7002H: operation data too short.
    OperationDataTooShort,
    /// 7003H: operation data too long.
    OperationDataTooLong,
    /// 7004H: operation data cannot be changed (read only).
    OperationDataReadOnly,
    /// 7005H: operation data write-protected at this time (e.g. in this phase).
    OperationDataWriteProtectedNow,
    /// 7006H: operation data below the minimum.
    OperationDataBelowMinimum,
    /// 7007H: operation data above the maximum.
    OperationDataAboveMaximum,
    /// 7008H: operation data invalid.
    OperationDataInvalid,
    /// 7009H: operation data write-protected by password.
    OperationDataPasswordProtected,
    /// A code the table does not list, kept as it was received.
    Unknown(u16),
}

impl ServiceError {
    /// The error for a 16-bit code; codes the table does not list become
    /// [`ServiceError::Unknown`], so `from_code(c).code() == c` for every `c`.
    pub const fn from_code(code: u16) -> ServiceError {
        match code {
            0x0001 => ServiceError::ServiceChannelNotOpen,
            0x0009 => ServiceError::InvalidAccessToClosing,
            0x1001 => ServiceError::IdnNotPresent,
            0x1009 => ServiceError::InvalidAccessToElement1,
            0x7002 => ServiceError::OperationDataTooShort,
            0x7003 => ServiceError::OperationDataTooLong,
            0x7004 => ServiceError::OperationDataReadOnly,
            0x7005 => ServiceError::OperationDataWriteProtectedNow,
            0x7006 => ServiceError::OperationDataBelowMinimum,
            0x7007 => ServiceError::OperationDataAboveMaximum,
            0x7008 => ServiceError::OperationDataInvalid,
            0x7009 => ServiceError::OperationDataPasswordProtected,
            _ => {
                // sercos-facts.md: x001H–x005H for x = 2 (name) … 6 (maximum).
                if code & 0x0FF0 == 0 {
                    if let (Some(element), Some(fault)) = (
                        DescriptiveElement::from_number((code >> 12) as u8),
                        ElementFault::from_nibble(code & 0xF),
                    ) {
                        return ServiceError::Element(element, fault);
                    }
                }
                ServiceError::Unknown(code)
            }
        }
    }

    /// The 16-bit code.
    pub const fn code(self) -> u16 {
        match self {
            ServiceError::ServiceChannelNotOpen => 0x0001,
            ServiceError::InvalidAccessToClosing => 0x0009,
            ServiceError::IdnNotPresent => 0x1001,
            ServiceError::InvalidAccessToElement1 => 0x1009,
            ServiceError::Element(element, fault) => ((element as u16) << 12) | fault as u16,
            ServiceError::OperationDataTooShort => 0x7002,
            ServiceError::OperationDataTooLong => 0x7003,
            ServiceError::OperationDataReadOnly => 0x7004,
            ServiceError::OperationDataWriteProtectedNow => 0x7005,
            ServiceError::OperationDataBelowMinimum => 0x7006,
            ServiceError::OperationDataAboveMaximum => 0x7007,
            ServiceError::OperationDataInvalid => 0x7008,
            ServiceError::OperationDataPasswordProtected => 0x7009,
            ServiceError::Unknown(code) => code,
        }
    }

    /// What the code means, in words (without the element for element faults; [`Display`]
    /// adds it).
    ///
    /// [`Display`]: fmt::Display
    pub const fn meaning(self) -> &'static str {
        match self {
            ServiceError::ServiceChannelNotOpen => "service channel not open",
            ServiceError::InvalidAccessToClosing => "invalid access to closing the service channel",
            ServiceError::IdnNotPresent => "IDN not present",
            ServiceError::InvalidAccessToElement1 => "invalid access to element 1",
            ServiceError::Element(_, fault) => fault.meaning(),
            ServiceError::OperationDataTooShort => "operation data too short",
            ServiceError::OperationDataTooLong => "operation data too long",
            ServiceError::OperationDataReadOnly => "operation data cannot be changed (read only)",
            ServiceError::OperationDataWriteProtectedNow => {
                "operation data write-protected at this time"
            }
            ServiceError::OperationDataBelowMinimum => "operation data below minimum",
            ServiceError::OperationDataAboveMaximum => "operation data above maximum",
            ServiceError::OperationDataInvalid => "operation data invalid",
            ServiceError::OperationDataPasswordProtected => {
                "operation data write-protected by password"
            }
            ServiceError::Unknown(_) => "unknown service channel error",
        }
    }
}

impl From<u16> for ServiceError {
    fn from(code: u16) -> ServiceError {
        ServiceError::from_code(code)
    }
}

impl From<ServiceError> for u16 {
    fn from(error: ServiceError) -> u16 {
        error.code()
    }
}

/// `1001H IDN not present`, `3004H attribute cannot be changed`.
impl fmt::Display for ServiceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ServiceError::Element(element, fault) => write!(
                f,
                "{:04X}H {} {}",
                self.code(),
                element.name(),
                fault.meaning()
            ),
            _ => write!(f, "{:04X}H {}", self.code(), self.meaning()),
        }
    }
}

impl core::error::Error for ServiceError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_codes() {
        // sercos-facts.md, service channel errors table.
        assert_eq!(
            ServiceError::from_code(0x0001),
            ServiceError::ServiceChannelNotOpen
        );
        assert_eq!(ServiceError::from_code(0x1001), ServiceError::IdnNotPresent);
        assert_eq!(
            ServiceError::from_code(0x3004),
            ServiceError::Element(DescriptiveElement::Attribute, ElementFault::CannotBeChanged)
        );
        assert_eq!(
            ServiceError::from_code(0x6005),
            ServiceError::Element(DescriptiveElement::Maximum, ElementFault::WriteProtectedNow)
        );
        assert_eq!(
            ServiceError::from_code(0x7007),
            ServiceError::OperationDataAboveMaximum
        );
        // 7001H and 2006H are not in the table.
        assert_eq!(
            ServiceError::from_code(0x7001),
            ServiceError::Unknown(0x7001)
        );
        assert_eq!(
            ServiceError::from_code(0x2006),
            ServiceError::Unknown(0x2006)
        );
        assert_eq!(
            ServiceError::from_code(0x2101),
            ServiceError::Unknown(0x2101)
        );
    }

    #[test]
    fn every_code_round_trips() {
        for code in 0..=u16::MAX {
            assert_eq!(ServiceError::from_code(code).code(), code);
        }
    }

    #[cfg(feature = "alloc")]
    #[test]
    fn human_text() {
        use alloc::string::ToString;
        assert_eq!(
            ServiceError::IdnNotPresent.to_string(),
            "1001H IDN not present"
        );
        assert_eq!(
            ServiceError::from_code(0x4003).to_string(),
            "4003H unit too long"
        );
    }
}
