use thiserror::Error;

/// Why a report descriptor could not be located into a pen layout, or a report not decoded.
/// Descriptor errors carry the byte offset of the offending item; report errors the report ID
/// and the byte that was missing or wrong.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum HidError {
    /// The descriptor has no bytes.
    #[error("the report descriptor is empty")]
    EmptyDescriptor,
    /// The descriptor is longer than any real device's.
    #[error("the report descriptor has {len} bytes, more than the {max} a HID device may declare")]
    DescriptorTooLong {
        /// Bytes given.
        len: usize,
        /// The limit.
        max: usize,
    },
    /// An item announces more data bytes than the descriptor has left.
    #[error(
        "report descriptor truncated: the item at byte {offset} needs {needed} data byte(s), \
         only {available} remain"
    )]
    DescriptorTruncated {
        /// Byte offset of the item's prefix.
        offset: usize,
        /// Data bytes the item announces.
        needed: usize,
        /// Data bytes left in the descriptor.
        available: usize,
    },
    /// An item is structurally valid but its value is refused (too large, out of order, ...).
    #[error("report descriptor, item at byte {offset}: {message}")]
    DescriptorInvalid {
        /// Byte offset of the item (0 when the parser could not tell).
        offset: usize,
        /// What is wrong.
        message: String,
    },
    /// No input report has absolute X and Y together with a pen usage (Tip Switch, In Range or
    /// Tip Pressure) outside a touch contact.
    #[error("the report descriptor declares no pen input report (absolute X, Y and a pen usage)")]
    NoPenReport,
    /// A pen field cannot be converted to physical units.
    #[error("report {report_id:#04x}, field {field}: {message}")]
    BadField {
        /// Report ID (0 when the device uses no report IDs).
        report_id: u8,
        /// Field name (`X`, `Tip Pressure`, ...).
        field: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A report with no bytes.
    #[error("empty report")]
    EmptyReport,
    /// The report's first byte names a report ID the descriptor does not declare for input.
    #[error("byte 0: report ID {report_id:#04x} is not an input report of this descriptor")]
    UnknownReportId {
        /// The ID found.
        report_id: u8,
    },
    /// The report is shorter than its layout: a field would read past the end.
    #[error(
        "report {report_id:#04x} truncated: field {field} needs byte {needed_byte}, \
         the report has {len} byte(s)"
    )]
    ReportTruncated {
        /// Report ID (0 when the device uses no report IDs).
        report_id: u8,
        /// The field that did not fit.
        field: &'static str,
        /// 0-based index of the first missing byte.
        needed_byte: usize,
        /// Bytes in the report.
        len: usize,
    },
    /// A decoded value converts to a number that is not finite.
    #[error("report {report_id:#04x}, field {field} at byte {byte}: {message}")]
    BadValue {
        /// Report ID (0 when the device uses no report IDs).
        report_id: u8,
        /// Field name.
        field: &'static str,
        /// Byte offset of the field's first bit.
        byte: usize,
        /// What is wrong.
        message: String,
    },
    /// A field's logical value lies outside the Logical Minimum..=Maximum its descriptor
    /// declares (a corrupted report, or a device that does not keep its word): the report is
    /// refused rather than scaled into a position off the tablet.
    #[error(
        "report {report_id:#04x}, field {field} at byte {byte}: value {value} is outside \
         the logical range {min}..={max}"
    )]
    OutOfRange {
        /// Report ID (0 when the device uses no report IDs).
        report_id: u8,
        /// Field name.
        field: &'static str,
        /// Byte offset of the field's first bit.
        byte: usize,
        /// The logical value read.
        value: i64,
        /// Logical Minimum.
        min: i64,
        /// Logical Maximum.
        max: i64,
    },
}
