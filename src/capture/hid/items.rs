//! A structural check of a report descriptor, item by item, before the `hidreport` parser sees
//! it. It rejects, with the item's byte offset, what would make a parser panic or allocate without
//! bound: items cut short, long items, Usages without a Usage Page, Pop without Push, and counts
//! beyond the limits the Linux HID core enforces on real devices.
//!
//! It also normalises one thing: like the Linux HID core (`hid_parser_global`), a Logical or
//! Physical Maximum is read unsigned when its Minimum is not negative, so `0x25, 0xff` is 255.
//! `hidreport` reads it signed (-1); the check rewrites such an item one size wider with a zero
//! high byte, and keeps the map back to the original byte offsets.

use super::error::HidError;

/// Longest descriptor accepted: Linux's `HID_MAX_DESCRIPTOR_SIZE`, the largest a device may
/// hand the kernel.
pub const MAX_DESCRIPTOR_BYTES: usize = 4096;
/// Largest Report Size in bits: the Linux HID core refuses anything wider (`hid_add_field`).
const MAX_REPORT_SIZE_BITS: u32 = 256;
/// Largest Report Count, and largest Usage Minimum..Maximum span: Linux's `HID_MAX_USAGES`.
const MAX_USAGES: u32 = 12288;
/// Upper bound on the data fields of all main items together: several times any real device,
/// small enough that the parser's per-field allocations stay in megabytes.
const MAX_TOTAL_FIELDS: u64 = 65536;
/// Push nesting bound (Linux: `HID_GLOBAL_STACK_SIZE` is 4; four times that is generous).
const MAX_PUSH_DEPTH: usize = 16;
/// Collection nesting bound: real descriptors nest 2 to 4 deep.
const MAX_COLLECTION_DEPTH: usize = 32;

/// Prefix byte of a long item (HID 1.11, 6.2.2.3); its data size is in the next byte.
const LONG_ITEM_PREFIX: u8 = 0xFE;

const TYPE_MAIN: u8 = 0;
const TYPE_GLOBAL: u8 = 1;
const TYPE_LOCAL: u8 = 2;

const MAIN_INPUT: u8 = 0x8;
const MAIN_OUTPUT: u8 = 0x9;
const MAIN_COLLECTION: u8 = 0xA;
const MAIN_FEATURE: u8 = 0xB;
const MAIN_END_COLLECTION: u8 = 0xC;

const GLOBAL_USAGE_PAGE: u8 = 0x0;
const GLOBAL_LOGICAL_MINIMUM: u8 = 0x1;
const GLOBAL_LOGICAL_MAXIMUM: u8 = 0x2;
const GLOBAL_PHYSICAL_MINIMUM: u8 = 0x3;
const GLOBAL_PHYSICAL_MAXIMUM: u8 = 0x4;
const GLOBAL_REPORT_SIZE: u8 = 0x7;
const GLOBAL_REPORT_ID: u8 = 0x8;
const GLOBAL_REPORT_COUNT: u8 = 0x9;
const GLOBAL_PUSH: u8 = 0xA;
const GLOBAL_POP: u8 = 0xB;

const LOCAL_USAGE: u8 = 0x0;
const LOCAL_USAGE_MINIMUM: u8 = 0x1;
const LOCAL_USAGE_MAXIMUM: u8 = 0x2;

/// The global state the check needs, saved by Push and restored by Pop.
#[derive(Clone, Copy, Default)]
struct Globals {
    usage_page: bool,
    report_count: u32,
    logical_min_negative: bool,
    physical_min_negative: bool,
}

/// A checked descriptor, with unsigned maxima made explicit (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct CheckedDescriptor {
    /// The bytes to hand the parser.
    pub bytes: Vec<u8>,
    /// For every item: (offset in `bytes`, offset in the original), ascending.
    offsets: Vec<(usize, usize)>,
}

impl CheckedDescriptor {
    /// The original byte offset of the item at `offset` in [`CheckedDescriptor::bytes`].
    pub fn original_offset(&self, offset: usize) -> usize {
        let i = self.offsets.partition_point(|&(new, _)| new <= offset);
        match i.checked_sub(1).and_then(|i| self.offsets.get(i)) {
            Some(&(new, old)) => old + (offset - new),
            None => offset,
        }
    }
}

/// Whether the item data, read as the signed value HID defines, is negative.
fn high_bit_set(data: &[u8]) -> bool {
    data.last().is_some_and(|b| b & 0x80 != 0)
}

/// The local state, reset by every main item.
#[derive(Default)]
struct Locals {
    short_usage: bool,
    usage_minimum: Option<u32>,
    usage_maximum: Option<u32>,
}

/// Checks the descriptor's item structure; `Ok` holds the bytes the `hidreport` parser can be
/// run on.
pub fn check_items(bytes: &[u8]) -> Result<CheckedDescriptor, HidError> {
    if bytes.is_empty() {
        return Err(HidError::EmptyDescriptor);
    }
    if bytes.len() > MAX_DESCRIPTOR_BYTES {
        return Err(HidError::DescriptorTooLong {
            len: bytes.len(),
            max: MAX_DESCRIPTOR_BYTES,
        });
    }
    let invalid = |offset: usize, message: String| HidError::DescriptorInvalid { offset, message };
    let mut globals = Globals::default();
    let mut stack: Vec<Globals> = Vec::new();
    let mut locals = Locals::default();
    let mut depth = 0usize;
    let mut total_fields = 0u64;
    let mut offset = 0usize;
    let mut out = CheckedDescriptor {
        bytes: Vec::with_capacity(bytes.len()),
        offsets: Vec::new(),
    };
    while offset < bytes.len() {
        let prefix = bytes[offset];
        let remaining = bytes.len() - offset - 1;
        if prefix == LONG_ITEM_PREFIX {
            let Some(&size) = bytes.get(offset + 1) else {
                return Err(HidError::DescriptorTruncated {
                    offset,
                    needed: 2,
                    available: remaining,
                });
            };
            let needed = 2 + usize::from(size);
            if needed > remaining {
                return Err(HidError::DescriptorTruncated {
                    offset,
                    needed,
                    available: remaining,
                });
            }
            // HID 1.11 defines no long item tags, and `hidreport` reads 0xFE as a short item
            // (2 data bytes), so the long item's payload would reach it as items this check
            // never saw (a Usage without a Usage Page: a panic). Linux rejects long items too.
            return Err(invalid(
                offset,
                format!("long item ({size} data bytes): no long items are defined"),
            ));
        }
        let size = match prefix & 0b11 {
            3 => 4,
            n => usize::from(n),
        };
        if size > remaining {
            return Err(HidError::DescriptorTruncated {
                offset,
                needed: size,
                available: remaining,
            });
        }
        let data = &bytes[offset + 1..offset + 1 + size];
        let value = data
            .iter()
            .rev()
            .fold(0u32, |acc, &b| (acc << 8) | u32::from(b));
        let kind = (prefix >> 2) & 0b11;
        let tag = prefix >> 4;
        out.offsets.push((out.bytes.len(), offset));
        let unsigned_max = match (kind, tag) {
            (TYPE_GLOBAL, GLOBAL_LOGICAL_MAXIMUM) => !globals.logical_min_negative,
            (TYPE_GLOBAL, GLOBAL_PHYSICAL_MAXIMUM) => !globals.physical_min_negative,
            _ => false,
        };
        if unsigned_max && (size == 1 || size == 2) && high_bit_set(data) {
            // One size wider (1 -> 2 bytes, 2 -> 4: size codes 2 and 3), zero-extended.
            out.bytes
                .push((prefix & !0b11) | (if size == 1 { 2 } else { 3 }));
            out.bytes.extend_from_slice(data);
            out.bytes.extend(std::iter::repeat_n(0u8, size));
        } else {
            out.bytes
                .extend_from_slice(&bytes[offset..offset + 1 + size]);
        }
        match (kind, tag) {
            (TYPE_MAIN, MAIN_INPUT | MAIN_OUTPUT | MAIN_FEATURE | MAIN_COLLECTION) => {
                if locals.short_usage && !globals.usage_page {
                    return Err(invalid(offset, "a Usage without a Usage Page".into()));
                }
                if let (Some(min), Some(max)) = (locals.usage_minimum, locals.usage_maximum)
                    && max.saturating_sub(min) >= MAX_USAGES
                {
                    return Err(invalid(
                        offset,
                        format!("Usage Minimum..Maximum spans more than {MAX_USAGES} usages"),
                    ));
                }
                if tag == MAIN_COLLECTION {
                    depth += 1;
                    if depth > MAX_COLLECTION_DEPTH {
                        return Err(invalid(
                            offset,
                            format!("collections nested deeper than {MAX_COLLECTION_DEPTH}"),
                        ));
                    }
                } else {
                    total_fields += u64::from(globals.report_count);
                    if total_fields > MAX_TOTAL_FIELDS {
                        return Err(invalid(
                            offset,
                            format!("more than {MAX_TOTAL_FIELDS} fields in all reports"),
                        ));
                    }
                }
                locals = Locals::default();
            }
            (TYPE_MAIN, MAIN_END_COLLECTION) => {
                depth = depth
                    .checked_sub(1)
                    .ok_or_else(|| invalid(offset, "End Collection without Collection".into()))?;
                locals = Locals::default();
            }
            (TYPE_GLOBAL, GLOBAL_USAGE_PAGE) => globals.usage_page = true,
            (TYPE_GLOBAL, GLOBAL_LOGICAL_MINIMUM) => {
                globals.logical_min_negative = high_bit_set(data)
            }
            (TYPE_GLOBAL, GLOBAL_PHYSICAL_MINIMUM) => {
                globals.physical_min_negative = high_bit_set(data);
            }
            (TYPE_GLOBAL, GLOBAL_REPORT_SIZE) if value > MAX_REPORT_SIZE_BITS => {
                return Err(invalid(
                    offset,
                    format!("Report Size {value} exceeds {MAX_REPORT_SIZE_BITS} bits"),
                ));
            }
            (TYPE_GLOBAL, GLOBAL_REPORT_COUNT) => {
                if value > MAX_USAGES {
                    return Err(invalid(
                        offset,
                        format!("Report Count {value} exceeds {MAX_USAGES}"),
                    ));
                }
                globals.report_count = value;
            }
            (TYPE_GLOBAL, GLOBAL_REPORT_ID) if value == 0 || value > u32::from(u8::MAX) => {
                return Err(invalid(
                    offset,
                    format!("Report ID {value} is outside 1..=255"),
                ));
            }
            (TYPE_GLOBAL, GLOBAL_PUSH) => {
                if stack.len() >= MAX_PUSH_DEPTH {
                    return Err(invalid(
                        offset,
                        format!("Push nested deeper than {MAX_PUSH_DEPTH}"),
                    ));
                }
                stack.push(globals);
            }
            (TYPE_GLOBAL, GLOBAL_POP) => {
                globals = stack
                    .pop()
                    .ok_or_else(|| invalid(offset, "Pop without Push".into()))?;
            }
            // A 4-byte Usage carries its own page; a shorter one needs the global Usage Page.
            (TYPE_LOCAL, LOCAL_USAGE) if size < 4 => locals.short_usage = true,
            // Extended (4-byte) bounds are compared whole: the parser iterates over the full
            // 32-bit span when their pages differ.
            (TYPE_LOCAL, LOCAL_USAGE_MINIMUM) => {
                locals.short_usage |= size < 4;
                locals.usage_minimum = Some(value);
            }
            (TYPE_LOCAL, LOCAL_USAGE_MAXIMUM) => {
                locals.short_usage |= size < 4;
                locals.usage_maximum = Some(value);
            }
            _ => {}
        }
        offset += 1 + size;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unsigned_maxima_are_widened_and_offsets_map_back() {
        // Logical Minimum 0, Logical Maximum 0xff (one byte), Physical Minimum -1, Physical
        // Maximum 0xff (stays signed: its minimum is negative), End Collection at byte 8.
        let d = [0x15, 0x00, 0x25, 0xff, 0x35, 0xff, 0x45, 0xff, 0xc0];
        let checked = check_items(&d).expect_err("End Collection without Collection");
        assert_eq!(
            checked,
            HidError::DescriptorInvalid {
                offset: 8,
                message: "End Collection without Collection".into()
            }
        );
        let ok = check_items(&d[..8]).expect("checks");
        assert_eq!(
            ok.bytes,
            [0x15, 0x00, 0x26, 0xff, 0x00, 0x35, 0xff, 0x45, 0xff]
        );
        assert_eq!(ok.original_offset(5), 4);
        assert_eq!(ok.original_offset(7), 6);
        assert_eq!(ok.original_offset(2), 2);
    }
}
