//! The export dispatch: one fitted file written as any of kansei's four output formats
//! ([`Format`]), with the options each format takes ([`FormatOptions`]). The command line
//! (`kansei fit --json/--svg/--dxf/--png`), the app's export buttons and the service's
//! `/v1/fit` and `/v1/export/*` endpoints all write through [`Format::export`], so the same fit
//! and options give the same bytes whichever of them is asked.
//!
//! Each format is the writer of its own module, driven the same way every time:
//! - [`Format::Json`]: the `kansei-curve` document ([`CurveFile::from_output_with`]), indented
//!   ([`CurveFile::to_json`]) or on one line ([`JsonLayout`]).
//! - [`Format::Svg`]: [`svg_document`] with the units' defaults ([`SvgOptions::for_units`]),
//!   the requested accuracy and [`SvgLayers`].
//! - [`Format::Dxf`]: [`dxf_drawing`], saved as ASCII DXF
//!   ([`DxfExport::to_bytes`](super::DxfExport::to_bytes)). The `dxf` crate stamps each new
//!   drawing's header with the time of writing (`$TDCREATE`, `$TDUPDATE`, …) and fresh
//!   `$FINGERPRINTGUID`/`$VERSIONGUID`, so two writes of one fit differ there and only there.
//! - [`Format::Png`]: the whole scene in view ([`View::fit`]) drawn by
//!   [`render_png`](crate::render::render_png) ([`PngOptions`]).

use crate::pipeline::FitOutput;
use crate::render::{
    QUICK_LOOK_MARGIN_PX, RenderError, RenderOptions, Scene, View, render_png, scene_bounds,
};
use crate::stroke::StrokeFile;

use super::{
    CurveFile, DxfOptions, DxfWriteError, ExportOptions, SvgLayers, SvgOptions, dxf_drawing,
    svg_document,
};

/// Size of a PNG, pixels, when none is given: what `kansei fit --size`, the service's `size`
/// and the app's PNG export default to.
pub const DEFAULT_PNG_SIZE: (u32, u32) = (1600, 1000);

/// An output format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// `kansei-curve` v1 JSON ([`CurveFile`]).
    Json,
    /// SVG: lines and arcs exact, spirals as cubic Béziers within the export accuracy.
    Svg,
    /// DXF: one degree-3 SPLINE per fitted piece, within the export accuracy.
    Dxf,
    /// A PNG picture of the fit.
    Png,
}

impl Format {
    /// Every format, in the order the app's file panel shows them.
    pub const ALL: [Format; 4] = [Format::Json, Format::Svg, Format::Dxf, Format::Png];

    /// The extension a file of this format gets, without the leading dot: `curve.json` (so that
    /// a fit's JSON never takes the name of its `kansei-stroke` input), `svg`, `dxf`, `png`.
    pub const fn extension(self) -> &'static str {
        match self {
            Format::Json => "curve.json",
            Format::Svg => "svg",
            Format::Dxf => "dxf",
            Format::Png => "png",
        }
    }

    /// The media type of this format's bytes (the service's `Content-Type`).
    pub const fn mime_type(self) -> &'static str {
        match self {
            Format::Json => "application/json",
            Format::Svg => "image/svg+xml",
            Format::Dxf => "image/vnd.dxf",
            Format::Png => "image/png",
        }
    }

    /// The format's usual name, in capitals: `JSON`, `SVG`, `DXF`, `PNG`.
    pub const fn name(self) -> &'static str {
        match self {
            Format::Json => "JSON",
            Format::Svg => "SVG",
            Format::Dxf => "DXF",
            Format::Png => "PNG",
        }
    }

    /// `output`, the fit of `file`, written in this format with `options` (each format reads
    /// its own fields of them). `file` gives the SVG's samples layer and the PNG's strokes; the
    /// JSON and DXF are the fit's alone.
    ///
    /// Fails when the DXF or PNG encoder fails, the PNG's size is out of range
    /// ([`RenderError`]), or the drawing is empty and [`PngOptions::empty`] refuses it.
    pub fn export(
        self,
        file: &StrokeFile,
        output: &FitOutput,
        options: &FormatOptions,
    ) -> Result<Exported, FormatError> {
        match self {
            Format::Json => {
                let doc = CurveFile::from_output_with(output, &options.json);
                let text = match options.json_layout {
                    JsonLayout::Pretty => serde_json::to_string_pretty(&doc),
                    JsonLayout::Compact => serde_json::to_string(&doc),
                }
                .map_err(FormatError::Json)?;
                Ok(Exported::exact(text.into_bytes()))
            }
            Format::Svg => {
                let svg = svg_document(output, Some(file), &options.svg_options(file));
                Ok(Exported {
                    accuracy: Some(AccuracyReport {
                        accuracy: svg.accuracy,
                        max_error: svg.max_error(),
                    }),
                    bytes: svg.svg.into_bytes(),
                })
            }
            Format::Dxf => {
                let dxf = dxf_drawing(
                    output,
                    &DxfOptions {
                        accuracy: options.accuracy,
                    },
                );
                Ok(Exported {
                    accuracy: Some(AccuracyReport {
                        accuracy: dxf.accuracy,
                        max_error: dxf.max_error(),
                    }),
                    bytes: dxf.to_bytes()?,
                })
            }
            Format::Png => Ok(Exported::exact(options.png.render(file, output)?)),
        }
    }
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// How the JSON is laid out.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum JsonLayout {
    /// Indented, one field a line ([`CurveFile::to_json`]): the files `kansei fit` writes.
    #[default]
    Pretty,
    /// One line: each document of `kansei fit`'s stdout with several inputs, and the
    /// service's stream.
    Compact,
}

/// What to do with a PNG of an empty drawing (no sample, no curve).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EmptyDrawing {
    /// Draw it anyway: a blank picture (the overlays' frame around the origin), as
    /// `kansei fit --png` and the service do.
    #[default]
    Draw,
    /// Refuse it with [`FormatError::EmptyDrawing`], as the app does.
    Refuse,
}

/// How the PNG is drawn: the whole scene fitted into the picture ([`View::fit`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PngOptions {
    /// Width and height, pixels. Default [`DEFAULT_PNG_SIZE`]; the render refuses sizes beyond
    /// [`MAX_IMAGE_SIDE`](crate::render::MAX_IMAGE_SIDE) and
    /// [`MAX_IMAGE_PIXELS`](crate::render::MAX_IMAGE_PIXELS).
    pub size: (u32, u32),
    /// Margin between the scene and the picture's edges, pixels. Default
    /// [`QUICK_LOOK_MARGIN_PX`]: room for the scale bar and the split markers at the edges.
    pub margin_px: f64,
    /// Overlays, widths and colours. Default [`RenderOptions::default`].
    pub render: RenderOptions,
    /// An empty drawing. Default [`EmptyDrawing::Draw`].
    pub empty: EmptyDrawing,
}

impl Default for PngOptions {
    fn default() -> Self {
        PngOptions {
            size: DEFAULT_PNG_SIZE,
            margin_px: QUICK_LOOK_MARGIN_PX,
            render: RenderOptions::default(),
            empty: EmptyDrawing::Draw,
        }
    }
}

impl PngOptions {
    /// The options with `render`.
    pub const fn with_render(mut self, render: RenderOptions) -> Self {
        self.render = render;
        self
    }

    /// The options with `size`.
    pub const fn with_size(mut self, size: (u32, u32)) -> Self {
        self.size = size;
        self
    }

    /// The options with `margin_px`.
    pub const fn with_margin(mut self, margin_px: f64) -> Self {
        self.margin_px = margin_px;
        self
    }

    /// The options with `empty`.
    pub const fn with_empty(mut self, empty: EmptyDrawing) -> Self {
        self.empty = empty;
        self
    }

    /// The PNG of `output` over the strokes of `file`.
    fn render(&self, file: &StrokeFile, output: &FitOutput) -> Result<Vec<u8>, FormatError> {
        let scene = Scene::new(&file.strokes, &output.curves, file.units);
        let bounds = match (scene_bounds(&scene), self.empty) {
            (Some(bounds), _) => bounds,
            (None, EmptyDrawing::Draw) => Default::default(),
            (None, EmptyDrawing::Refuse) => return Err(FormatError::EmptyDrawing),
        };
        let (width, height) = self.size;
        let view = View::fit(bounds, width, height, self.margin_px);
        Ok(render_png(&scene, &view, &self.render)?)
    }
}

/// The options of every format; each format reads its own fields. The default is what
/// `kansei fit` writes without options.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FormatOptions {
    /// JSON: the document's extras (the LCGs). Default [`ExportOptions::default`]: none.
    pub json: ExportOptions,
    /// JSON: the layout. Default [`JsonLayout::Pretty`].
    pub json_layout: JsonLayout,
    /// SVG and DXF: largest distance between the written curves and the exact LAC chain.
    /// Default `None`: [`DEFAULT_ACCURACY_FRACTION`](super::DEFAULT_ACCURACY_FRACTION) of the
    /// fitting tolerance (a value that is not a positive number also means that).
    pub accuracy: Option<f64>,
    /// SVG: the layers beside the chain. Default [`SvgLayers::NONE`].
    pub svg_layers: SvgLayers,
    /// PNG: size, margin, overlays. Default [`PngOptions::default`].
    pub png: PngOptions,
}

impl FormatOptions {
    /// The SVG options for `file`: its units' defaults, with [`FormatOptions::accuracy`] and
    /// [`FormatOptions::svg_layers`].
    pub fn svg_options(&self, file: &StrokeFile) -> SvgOptions {
        SvgOptions {
            accuracy: self.accuracy,
            ..SvgOptions::for_units(file.units)
        }
        .with_layer_set(self.svg_layers)
    }
}

/// The bytes of an export, and how closely its curves follow the chain.
#[derive(Clone, Debug, PartialEq)]
pub struct Exported {
    /// The file's contents.
    pub bytes: Vec<u8>,
    /// SVG and DXF: the accuracy their curves were written to and the largest error measured.
    /// `None` for JSON (the chain's own parameters) and PNG (a picture).
    pub accuracy: Option<AccuracyReport>,
}

impl Exported {
    /// Bytes with no approximation to report.
    fn exact(bytes: Vec<u8>) -> Self {
        Exported {
            bytes,
            accuracy: None,
        }
    }

    /// The accuracy report when the measured error exceeds the accuracy asked for (a segment
    /// beyond the exporter's work bounds, see [`segment_beziers`](super::segment_beziers)):
    /// the bytes are still complete, and state each segment's error.
    pub fn beyond_accuracy(&self) -> Option<AccuracyReport> {
        self.accuracy.filter(|a| a.max_error > a.accuracy)
    }
}

/// The accuracy an SVG or DXF was written to, and the largest error it has.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AccuracyReport {
    /// The accuracy asked of the curves (the default resolved), in the file's units.
    pub accuracy: f64,
    /// The largest distance measured between a written curve and the exact chain.
    pub max_error: f64,
}

/// Why an export could not be produced.
#[derive(Debug, thiserror::Error)]
pub enum FormatError {
    /// The JSON could not be serialised.
    #[error("writing the kansei-curve JSON: {0}")]
    Json(#[source] serde_json::Error),
    /// The DXF could not be written.
    #[error(transparent)]
    Dxf(#[from] DxfWriteError),
    /// The PNG could not be drawn or encoded.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The drawing is empty and [`PngOptions::empty`] refuses it.
    #[error("nothing to export: the drawing is empty")]
    EmptyDrawing,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Point;
    use crate::pipeline::{PipelineOptions, fit_file};
    use crate::render::{Overlays, quick_look_png};
    use crate::stroke::{Stroke, Units};

    /// Two strokes in mm: a quarter circle of radius 40 and an S of two arcs, so that the
    /// chains hold arcs and spirals and the SVG and DXF approximate something.
    fn fitted() -> (StrokeFile, FitOutput) {
        let arc = Stroke::from_points((0..=90).map(|d| {
            let a = f64::from(d).to_radians();
            Point::new(40.0 * a.cos(), 40.0 * a.sin())
        }));
        let s = Stroke::from_points((0..=120).map(|i| {
            let t = f64::from(i) / 120.0;
            let x = 100.0 * t;
            Point::new(x, 60.0 + 15.0 * (std::f64::consts::TAU * t).sin() + 0.3 * x)
        }));
        let file = StrokeFile::new(Units::Mm, vec![arc, s]);
        let output = fit_file(&file, &PipelineOptions::default()).expect("two smooth strokes fit");
        assert_eq!(output.curves.len(), 2, "one piece per stroke");
        (file, output)
    }

    #[test]
    fn extensions_and_media_types_name_each_format_once() {
        let ext: Vec<_> = Format::ALL.iter().map(|f| f.extension()).collect();
        assert_eq!(ext, ["curve.json", "svg", "dxf", "png"]);
        let mime: Vec<_> = Format::ALL.iter().map(|f| f.mime_type()).collect();
        assert_eq!(
            mime,
            [
                "application/json",
                "image/svg+xml",
                "image/vnd.dxf",
                "image/png"
            ]
        );
        for (i, a) in Format::ALL.iter().enumerate() {
            for b in &Format::ALL[i + 1..] {
                assert_ne!(a.extension(), b.extension());
                assert_ne!(a.mime_type(), b.mime_type());
            }
            assert_eq!(a.to_string(), a.name());
            assert_eq!(a.name(), a.name().to_ascii_uppercase());
            // The name is the extension's last part.
            assert!(
                a.extension().to_ascii_uppercase().ends_with(a.name()),
                "{a:?}"
            );
        }
    }

    #[test]
    fn json_is_the_curve_document_and_reads_back() {
        let (file, output) = fitted();
        for lcg in [false, true] {
            let json = ExportOptions { lcg };
            let doc = CurveFile::from_output_with(&output, &json);
            let pretty = Format::Json
                .export(
                    &file,
                    &output,
                    &FormatOptions {
                        json,
                        ..FormatOptions::default()
                    },
                )
                .expect("JSON");
            assert_eq!(pretty.bytes, doc.to_json().into_bytes());
            assert_eq!(pretty.accuracy, None);
            let compact = Format::Json
                .export(
                    &file,
                    &output,
                    &FormatOptions {
                        json,
                        json_layout: JsonLayout::Compact,
                        ..FormatOptions::default()
                    },
                )
                .expect("JSON");
            assert!(!compact.bytes.contains(&b'\n'), "one line");
            assert!(compact.bytes.len() < pretty.bytes.len());
            for bytes in [&pretty.bytes, &compact.bytes] {
                let text = std::str::from_utf8(bytes).expect("UTF-8");
                let back = CurveFile::from_json(text).expect("reads back");
                assert_eq!(back, doc, "lcg {lcg}");
                assert_eq!(back.curves.len(), output.curves.len());
                let has_lcg = back
                    .curves
                    .iter()
                    .flat_map(|c| &c.segments)
                    .any(|s| s.lcg.is_some());
                assert_eq!(has_lcg, lcg);
            }
        }
    }

    #[test]
    fn svg_is_the_svg_writer_with_the_units_defaults() {
        let (file, output) = fitted();
        for (accuracy, layers) in [
            (None, SvgLayers::NONE),
            (Some(0.001), SvgLayers::SAMPLES),
            (
                Some(0.05),
                SvgLayers::named(&["bspline".into(), "splits".into(), "other".into()]),
            ),
        ] {
            let options = FormatOptions {
                accuracy,
                svg_layers: layers,
                ..FormatOptions::default()
            };
            let direct = svg_document(
                &output,
                Some(&file),
                &SvgOptions {
                    accuracy,
                    ..SvgOptions::for_units(file.units)
                }
                .with_layers(
                    layers.samples,
                    layers.bspline,
                    layers.alpha,
                    layers.splits,
                ),
            );
            let got = Format::Svg.export(&file, &output, &options).expect("SVG");
            assert_eq!(got.bytes, direct.svg.as_bytes());
            let report = got.accuracy.expect("an SVG reports its accuracy");
            assert_eq!(report.accuracy, direct.accuracy);
            assert_eq!(report.max_error, direct.max_error());
            if let Some(a) = accuracy {
                assert_eq!(report.accuracy, a, "the accuracy asked for is used");
            }
            assert_eq!(
                got.beyond_accuracy().is_some(),
                report.max_error > report.accuracy
            );
            let text = String::from_utf8(got.bytes).expect("UTF-8");
            assert!(text.starts_with("<?xml") || text.starts_with("<svg"));
            assert_eq!(text.contains("id=\"samples\""), layers.samples);
        }
    }

    #[test]
    fn svg_layer_names_match_the_svg_options() {
        let names: Vec<String> = SvgLayers::NAMES.iter().map(|&n| n.to_owned()).collect();
        let all = SvgLayers::named(&names);
        assert_eq!(
            all,
            SvgLayers {
                samples: true,
                bspline: true,
                alpha: true,
                splits: true
            }
        );
        assert_eq!(SvgLayers::named(&[]), SvgLayers::NONE);
        assert_eq!(SvgLayers::default(), SvgLayers::NONE);
        for name in SvgLayers::NAMES {
            let one = [name.to_owned()];
            let l = SvgLayers::named(&one);
            let o = SvgOptions::default().with_layer_names(&one);
            assert_eq!(
                (l.samples, l.bspline, l.alpha, l.splits),
                (o.show_samples, o.show_bspline, o.show_alpha, o.show_splits),
                "{name}"
            );
        }
    }

    /// A DXF's lines with the values of the header's dates (`$TDCREATE`, `$TDUPDATE`, …) and
    /// identifiers (`$FINGERPRINTGUID`, `$VERSIONGUID`) blanked: the `dxf` crate stamps each new
    /// drawing with the clock and fresh GUIDs, so two writes of the same fit differ there and
    /// only there.
    fn without_clock(bytes: &[u8]) -> Vec<String> {
        let text = std::str::from_utf8(bytes).expect("ASCII DXF");
        let mut lines: Vec<String> = text.split("\r\n").map(str::to_owned).collect();
        for i in 0..lines.len() {
            // A header variable: its name, its group code, its value.
            let stamp = lines[i].starts_with("$TD") || lines[i].ends_with("GUID");
            if stamp && i + 2 < lines.len() {
                lines[i + 2].clear();
            }
        }
        lines
    }

    #[test]
    fn dxf_is_the_dxf_writer_and_reads_back() {
        let (file, output) = fitted();
        for accuracy in [None, Some(0.002)] {
            let direct = dxf_drawing(&output, &DxfOptions { accuracy });
            let got = Format::Dxf
                .export(
                    &file,
                    &output,
                    &FormatOptions {
                        accuracy,
                        ..FormatOptions::default()
                    },
                )
                .expect("DXF");
            let direct_bytes = direct.to_bytes().expect("DXF writes");
            assert_eq!(without_clock(&got.bytes), without_clock(&direct_bytes));
            let report = got.accuracy.expect("a DXF reports its accuracy");
            assert_eq!(report.accuracy, direct.accuracy);
            assert_eq!(report.max_error, direct.max_error());
            let drawing = dxf::Drawing::load(&mut got.bytes.as_slice()).expect("reads back");
            let splines = drawing
                .entities()
                .filter(|e| matches!(e.specific, dxf::entities::EntityType::Spline(_)))
                .count();
            assert_eq!(splines, output.curves.len(), "one SPLINE per piece");
        }
    }

    #[test]
    fn png_is_the_quick_look_by_default() {
        let (file, output) = fitted();
        let render = RenderOptions::with_overlays(Overlays {
            comb: true,
            ..Overlays::default()
        });
        let options = FormatOptions {
            png: PngOptions::default()
                .with_size((320, 200))
                .with_render(render),
            ..FormatOptions::default()
        };
        let got = Format::Png.export(&file, &output, &options).expect("PNG");
        let direct = quick_look_png(&file, &output, (320, 200), &render).expect("PNG");
        assert_eq!(got.bytes, direct);
        assert_eq!(got.accuracy, None);
        let pixmap = tiny_skia::Pixmap::decode_png(&got.bytes).expect("a PNG");
        assert_eq!((pixmap.width(), pixmap.height()), (320, 200));
    }

    #[test]
    fn png_margin_and_size_are_the_views() {
        let (file, output) = fitted();
        let png = PngOptions::default()
            .with_size((300, 240))
            .with_margin(24.0);
        let got = Format::Png
            .export(
                &file,
                &output,
                &FormatOptions {
                    png,
                    ..FormatOptions::default()
                },
            )
            .expect("PNG");
        let scene = Scene::new(&file.strokes, &output.curves, file.units);
        let bounds = scene_bounds(&scene).expect("strokes to draw");
        let view = View::fit(bounds, 300, 240, 24.0);
        let direct = render_png(&scene, &view, &RenderOptions::default()).expect("PNG");
        assert_eq!(got.bytes, direct);
        let wider = PngOptions {
            margin_px: 48.0,
            ..png
        };
        let other = Format::Png
            .export(
                &file,
                &output,
                &FormatOptions {
                    png: wider,
                    ..FormatOptions::default()
                },
            )
            .expect("PNG");
        assert_ne!(other.bytes, got.bytes, "the margin moves the drawing");
    }

    #[test]
    fn an_empty_drawing_is_drawn_or_refused_as_asked() {
        let file = StrokeFile::new(Units::Px, Vec::new());
        let output = fit_file(&file, &PipelineOptions::default()).expect("nothing to fit");
        let small = PngOptions::default().with_size((64, 48));
        let drawn = Format::Png
            .export(
                &file,
                &output,
                &FormatOptions {
                    png: small,
                    ..FormatOptions::default()
                },
            )
            .expect("a blank picture");
        let blank =
            quick_look_png(&file, &output, (64, 48), &RenderOptions::default()).expect("PNG");
        assert_eq!(drawn.bytes, blank);
        let refused = Format::Png.export(
            &file,
            &output,
            &FormatOptions {
                png: small.with_empty(EmptyDrawing::Refuse),
                ..FormatOptions::default()
            },
        );
        assert!(
            matches!(refused, Err(FormatError::EmptyDrawing)),
            "{refused:?}"
        );
        // The other formats write an empty drawing as such.
        for format in [Format::Json, Format::Svg, Format::Dxf] {
            let got = format
                .export(&file, &output, &FormatOptions::default())
                .expect("writes");
            assert!(!got.bytes.is_empty(), "{format}");
        }
    }

    #[test]
    fn a_png_too_large_is_a_render_error() {
        let (file, output) = fitted();
        let huge = PngOptions::default().with_size((u32::MAX, 1));
        let result = Format::Png.export(
            &file,
            &output,
            &FormatOptions {
                png: huge,
                ..FormatOptions::default()
            },
        );
        assert!(matches!(result, Err(FormatError::Render(_))), "{result:?}");
    }

    #[test]
    fn defaults_are_what_kansei_fit_writes_without_options() {
        let o = FormatOptions::default();
        assert!(!o.json.lcg);
        assert_eq!(o.json_layout, JsonLayout::Pretty);
        assert_eq!(o.accuracy, None);
        assert_eq!(o.svg_layers, SvgLayers::NONE);
        assert_eq!(o.png.size, DEFAULT_PNG_SIZE);
        assert_eq!(o.png.margin_px, QUICK_LOOK_MARGIN_PX);
        assert_eq!(o.png.render, RenderOptions::default());
        assert_eq!(o.png.empty, EmptyDrawing::Draw);
    }
}
