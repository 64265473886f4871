//! One located field of a report: where its bits are, and how its logical value maps to a
//! physical one.

/// HID unit system nibble (HID 1.11, 6.2.2.7, Unit): SI linear, lengths in centimetres.
const SYSTEM_SI_LINEAR: u32 = 1;
/// SI rotation: angles in radians.
const SYSTEM_SI_ROTATION: u32 = 2;
/// English linear: lengths in inches.
const SYSTEM_ENGLISH_LINEAR: u32 = 3;
/// English rotation: angles in degrees.
const SYSTEM_ENGLISH_ROTATION: u32 = 4;
/// The Unit value whose only non-zero nibbles are the system (low) and a length exponent of 1
/// (next nibble): a pure length (or, in a rotation system, a pure angle).
const LENGTH_NIBBLE_ONE: u32 = 0x10;
/// Millimetres per centimetre.
const MM_PER_CM: f64 = 10.0;
/// Millimetres per inch (exact by definition).
const MM_PER_INCH: f64 = 25.4;
/// The widest field read: values are held in i64 after sign extension from at most 32 bits,
/// as the HID logical range (32-bit items) allows.
pub const MAX_FIELD_BITS: usize = 32;

/// The physical quantity a unit describes, as far as pen fields need.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PhysicalUnit {
    /// A length; the factor turns one physical unit (after the exponent) into millimetres.
    Length {
        /// Millimetres per physical unit (10 for cm, 25.4 for inch).
        mm_per_unit: f64,
    },
    /// An angle; the factor turns one physical unit into degrees.
    Angle {
        /// Degrees per physical unit (1 for degrees, 180/π for radians).
        deg_per_unit: f64,
    },
    /// No unit, or one that is neither a pure length nor a pure angle.
    Other,
}

/// A field of a report located by the descriptor: its bits (counted from the start of the
/// report, the report ID byte included) and its value ranges.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldSpec {
    /// First bit, counted from bit 0 of byte 0 of the report (the report ID byte, when present).
    pub bit_offset: usize,
    /// Width in bits, 1..=[`MAX_FIELD_BITS`].
    pub bit_size: usize,
    /// Logical Minimum; a negative minimum makes the field signed (two's complement).
    pub logical_min: i64,
    /// Logical Maximum.
    pub logical_max: i64,
    /// Physical Minimum, when the descriptor declares a physical range.
    pub physical_min: Option<i64>,
    /// Physical Maximum, when the descriptor declares a physical range.
    pub physical_max: Option<i64>,
    /// The raw Unit item (0 when absent).
    pub unit: u32,
    /// The Unit Exponent, a power of ten (0 when absent).
    pub unit_exponent: i32,
}

impl FieldSpec {
    /// Whether values are two's complement: the HID rule, a negative Logical Minimum.
    pub fn is_signed(&self) -> bool {
        self.logical_min < 0
    }

    /// The index of the last byte the field touches.
    pub fn last_byte(&self) -> usize {
        (self.bit_offset + self.bit_size.max(1) - 1) / 8
    }

    /// The field's logical value in `report`, or `None` when the report is too short.
    /// Bits are little-endian, as HID reports are.
    /// Also `None` for a width outside 1..=[`MAX_FIELD_BITS`] (a layout never holds one).
    pub fn extract(&self, report: &[u8]) -> Option<i64> {
        if !(1..=MAX_FIELD_BITS).contains(&self.bit_size) {
            return None;
        }
        let first = self.bit_offset / 8;
        let bytes = report.get(first..=self.last_byte())?;
        let word = bytes
            .iter()
            .rev()
            .fold(0u64, |acc, &b| (acc << 8) | u64::from(b));
        let shifted = word >> (self.bit_offset % 8);
        let mask = (1u64 << self.bit_size) - 1;
        let value = shifted & mask;
        let sign_bit = 1u64 << (self.bit_size - 1);
        if self.is_signed() && value & sign_bit != 0 {
            Some(value as i64 - (1i64 << self.bit_size))
        } else {
            Some(value as i64)
        }
    }

    /// Whether a 1-bit-style switch is on: any non-zero value.
    pub fn is_on(&self, report: &[u8]) -> Option<bool> {
        self.extract(report).map(|v| v != 0)
    }

    /// The unit, as far as a pen needs to know it.
    pub fn physical_unit(&self) -> PhysicalUnit {
        let system = self.unit & 0xF;
        if self.unit & !0xF != LENGTH_NIBBLE_ONE {
            return PhysicalUnit::Other;
        }
        match system {
            SYSTEM_SI_LINEAR => PhysicalUnit::Length {
                mm_per_unit: MM_PER_CM,
            },
            SYSTEM_ENGLISH_LINEAR => PhysicalUnit::Length {
                mm_per_unit: MM_PER_INCH,
            },
            SYSTEM_SI_ROTATION => PhysicalUnit::Angle {
                deg_per_unit: 180.0 / std::f64::consts::PI,
            },
            SYSTEM_ENGLISH_ROTATION => PhysicalUnit::Angle { deg_per_unit: 1.0 },
            _ => PhysicalUnit::Other,
        }
    }

    /// The physical range the logical range maps onto: the declared one, or the logical range
    /// itself when none is declared or it is empty (HID 1.11, 6.2.2.7).
    fn physical_range(&self) -> (f64, f64) {
        match (self.physical_min, self.physical_max) {
            (Some(lo), Some(hi)) if lo != hi => (lo as f64, hi as f64),
            _ => (self.logical_min as f64, self.logical_max as f64),
        }
    }

    /// A logical value in physical units, unit exponent applied: the linear map of the logical
    /// range onto the physical range, times 10^exponent. Requires `logical_max > logical_min`
    /// (checked when the layout is built).
    pub fn to_physical(&self, logical: i64) -> f64 {
        let (p0, p1) = self.physical_range();
        let span = (self.logical_max - self.logical_min) as f64;
        let fraction = (logical - self.logical_min) as f64 / span;
        let value = p0 + fraction * (p1 - p0);
        // Dividing by an exact power of ten rounds once: 22400 / 10^3 is 22.4, where
        // 22400 * 10^-3 (10^-3 is inexact) is 22.400000000000002.
        if self.unit_exponent < 0 {
            value / 10f64.powi(-self.unit_exponent)
        } else {
            value * 10f64.powi(self.unit_exponent)
        }
    }

    /// The logical value as a fraction of the logical range: 0 at the minimum, 1 at the maximum,
    /// clamped to 0..1 (devices overshoot their declared range).
    pub fn normalised(&self, logical: i64) -> f64 {
        let span = (self.logical_max - self.logical_min) as f64;
        ((logical - self.logical_min) as f64 / span).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(bit_offset: usize, bit_size: usize, logical_min: i64, logical_max: i64) -> FieldSpec {
        FieldSpec {
            bit_offset,
            bit_size,
            logical_min,
            logical_max,
            physical_min: None,
            physical_max: None,
            unit: 0,
            unit_exponent: 0,
        }
    }

    #[test]
    fn extracts_unaligned_little_endian_bits_with_sign() {
        // 0b1011_0110 0b0000_0001: bits 1..=9 are 0b1_1011_011 = 0xDB.
        let report = [0b1011_0110, 0b0000_0001];
        assert_eq!(field(1, 9, 0, 511).extract(&report), Some(0xDB));
        // The same bits signed: 0x1DB... 9-bit 0b0_1101_1011 is positive 219.
        assert_eq!(field(1, 9, -256, 255).extract(&report), Some(219));
        // Bits 4..=7 = 0b1011 as 4-bit two's complement is -5.
        assert_eq!(field(4, 4, -8, 7).extract(&report), Some(-5));
        // 32-bit fields at byte 1 need bytes 1..=4.
        assert_eq!(field(8, 32, 0, i64::from(u32::MAX)).extract(&report), None);
        let wide = [0, 0xff, 0xff, 0xff, 0xff];
        assert_eq!(
            field(8, 32, i64::from(i32::MIN), i64::from(i32::MAX)).extract(&wide),
            Some(-1)
        );
        assert_eq!(
            field(8, 32, 0, i64::from(u32::MAX)).extract(&wide),
            Some(i64::from(u32::MAX))
        );
    }

    #[test]
    fn physical_mapping_and_units() {
        let mut x = field(0, 16, 0, 44800);
        x.physical_max = Some(22400);
        x.physical_min = Some(0);
        x.unit = 0x11;
        x.unit_exponent = -3;
        assert_eq!(
            x.physical_unit(),
            PhysicalUnit::Length {
                mm_per_unit: MM_PER_CM
            }
        );
        assert_eq!(x.to_physical(44800) * MM_PER_CM, 224.0);
        assert_eq!(x.to_physical(200) * MM_PER_CM, 1.0);
        // Without a physical range, physical = logical.
        let t = field(0, 8, -64, 63);
        assert_eq!(t.to_physical(-64), -64.0);
        assert_eq!(t.physical_unit(), PhysicalUnit::Other);
        // cm² is not a length.
        let mut area = x.clone();
        area.unit = 0x21;
        assert_eq!(area.physical_unit(), PhysicalUnit::Other);
        assert_eq!(field(0, 16, 0, 8191).normalised(9000), 1.0);
    }
}
