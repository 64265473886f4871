use serde::{Deserialize, Serialize};

use super::StrokeError;
use crate::geom::{MAX_COORDINATE, MIN_EXTENT_RELATIVE, Point};

/// Units of a stroke's coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Units {
    /// Millimetres on the tablet surface (what the capture layer produces when it knows the size).
    Mm,
    /// Screen or canvas pixels.
    Px,
    /// Raw device counts.
    Device,
}

impl Units {
    /// The default fitting tolerance for coordinates in these units.
    ///
    /// - `mm`: 0.1 mm. A designer's pen wobbles by about that much on a careful stroke; finer
    ///   tolerances fit the tremor, coarser ones flatten deliberate shape.
    /// - `px`: 0.5 px. Recorded screen strokes are quantised at 0.1–0.5 px (the google-ink
    ///   fixtures at 0.5 px), so half a pixel is the smallest tolerance that does not chase the
    ///   quantisation; on a 96 dpi screen it is 0.13 mm, close to the `mm` default.
    /// - `device`: 20 counts, 0.1 mm on a 200 lines/mm Wacom tablet, matching the `mm` default.
    pub const fn default_tolerance(self) -> f64 {
        match self {
            Units::Mm => 0.1,
            Units::Px => 0.5,
            Units::Device => 20.0,
        }
    }

    /// The name used in the file formats.
    pub const fn name(self) -> &'static str {
        match self {
            Units::Mm => "mm",
            Units::Px => "px",
            Units::Device => "device",
        }
    }
}

/// One pen sample.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    /// Horizontal coordinate, in the file's units.
    pub x: f64,
    /// Vertical coordinate, in the file's units.
    pub y: f64,
    /// Time in seconds (any origin), non-decreasing along a stroke.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t: Option<f64>,
    /// Normalised pressure, 0..1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pressure: Option<f64>,
    /// Tilt towards +x, degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tilt_x: Option<f64>,
    /// Tilt towards +y, degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tilt_y: Option<f64>,
}

impl Sample {
    /// A sample with position only.
    pub const fn new(x: f64, y: f64) -> Self {
        Sample {
            x,
            y,
            t: None,
            pressure: None,
            tilt_x: None,
            tilt_y: None,
        }
    }

    /// The same sample with a time stamp.
    pub const fn with_t(mut self, t: f64) -> Self {
        self.t = Some(t);
        self
    }

    /// The same sample with a pressure (0..1 when valid).
    pub const fn with_pressure(mut self, pressure: f64) -> Self {
        self.pressure = Some(pressure);
        self
    }

    /// The sample's position.
    pub const fn point(&self) -> Point {
        Point::new(self.x, self.y)
    }
}

/// One pen-down run of samples.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Stroke {
    /// The samples in the order the pen produced them.
    pub samples: Vec<Sample>,
}

impl Stroke {
    /// A stroke from samples (not yet validated).
    pub fn new(samples: Vec<Sample>) -> Self {
        Stroke { samples }
    }

    /// A stroke from positions only.
    pub fn from_points(points: impl IntoIterator<Item = Point>) -> Self {
        Stroke {
            samples: points.into_iter().map(|p| Sample::new(p.x, p.y)).collect(),
        }
    }

    /// The sample positions.
    pub fn points(&self) -> Vec<Point> {
        self.samples.iter().map(Sample::point).collect()
    }

    /// Checks the boundary rules; `index` is the stroke's index, used in error messages.
    pub fn validate(&self, index: usize) -> Result<(), StrokeError> {
        let has_time = self.samples.first().is_some_and(|s| s.t.is_some());
        let mut previous_t: Option<f64> = None;
        for (i, s) in self.samples.iter().enumerate() {
            let fields: [(&'static str, Option<f64>); 6] = [
                ("x", Some(s.x)),
                ("y", Some(s.y)),
                ("t", s.t),
                ("pressure", s.pressure),
                ("tilt_x", s.tilt_x),
                ("tilt_y", s.tilt_y),
            ];
            for (field, value) in fields {
                if let Some(v) = value
                    && !v.is_finite()
                {
                    return Err(StrokeError::NonFinite {
                        stroke: index,
                        sample: i,
                        field,
                        value: v,
                    });
                }
            }
            for (field, v) in [("x", s.x), ("y", s.y)] {
                if v.abs() > MAX_COORDINATE {
                    return Err(StrokeError::OutOfRange {
                        stroke: index,
                        sample: i,
                        field,
                        value: v,
                        limit: MAX_COORDINATE,
                    });
                }
            }
            if let Some(p) = s.pressure
                && !(0.0..=1.0).contains(&p)
            {
                return Err(StrokeError::Pressure {
                    stroke: index,
                    sample: i,
                    value: p,
                });
            }
            match (has_time, s.t) {
                (true, Some(t)) => {
                    if let Some(prev) = previous_t
                        && t < prev
                    {
                        return Err(StrokeError::TimeBackwards {
                            stroke: index,
                            sample: i,
                            t,
                            previous: prev,
                        });
                    }
                    previous_t = Some(t);
                }
                (false, None) => {}
                _ => {
                    return Err(StrokeError::MixedTime {
                        stroke: index,
                        sample: i,
                    });
                }
            }
        }
        if self.samples.is_empty() {
            return Err(StrokeError::NoSamples { stroke: index });
        }
        Ok(())
    }

    /// The corners of the samples' bounding box, `None` for a stroke without samples.
    pub fn bounds(&self) -> Option<(Point, Point)> {
        let first = self.samples.first()?.point();
        Some(self.samples.iter().fold((first, first), |(lo, hi), s| {
            (
                Point::new(lo.x.min(s.x), lo.y.min(s.y)),
                Point::new(hi.x.max(s.x), hi.y.max(s.y)),
            )
        }))
    }

    /// The stroke as a dot: the centre of its samples' bounding box and the largest distance
    /// from a sample to it, when that distance is within `tolerance` (a tap, the dot of an
    /// "i": every sample is represented within the tolerance by one point). `None` otherwise,
    /// and for a stroke without samples.
    pub fn as_dot(&self, tolerance: f64) -> Option<(Point, f64)> {
        let (lo, hi) = self.bounds()?;
        let centre = lo.midpoint(hi);
        let radius = self
            .samples
            .iter()
            .map(|s| (s.point() - centre).hypot())
            .fold(0.0, f64::max);
        (radius <= tolerance).then_some((centre, radius))
    }

    /// Checks that `f64` resolves the stroke's shape where it lies: its extent (the diagonal of
    /// its samples' box) is at least [`MIN_EXTENT_RELATIVE`] of its largest coordinate. A
    /// stroke smaller than the fitting tolerance is a dot ([`Stroke::as_dot`]) and needs no
    /// such check; the pipeline asks this only of strokes it is about to fit as curves.
    pub fn check_resolvable(&self, index: usize) -> Result<(), StrokeError> {
        let Some((lo, hi)) = self.bounds() else {
            return Err(StrokeError::NoSamples { stroke: index });
        };
        let extent = (hi - lo).hypot();
        let magnitude = lo.x.abs().max(lo.y.abs()).max(hi.x.abs()).max(hi.y.abs());
        if extent < MIN_EXTENT_RELATIVE * magnitude {
            return Err(StrokeError::Unresolvable {
                stroke: index,
                extent,
                magnitude,
            });
        }
        Ok(())
    }
}
