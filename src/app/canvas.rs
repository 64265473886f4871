//! The drawing surface: the scene rendered by [`render`] into a texture,
//! pan and zoom, and the pen (mouse, touch) turned into stroke samples.
//!
//! One transform, a render [`View`], maps model points to the canvas's physical pixels; a screen
//! position (egui points) becomes a pixel by `(pos − canvas origin)·pixels_per_point`, and a
//! model point by [`View::to_model`]. The texture is drawn again only when the scene, the view or
//! the options change; the stroke being drawn is painted over it with egui's painter, so drawing
//! never waits for the renderer.
//!
//! Pointer positions become samples through the capture layer's [`StrokeBuilder`], as a tablet's
//! reports do: the same rules decide when a run is a stroke (two distinct positions) and drop a
//! sample whose time goes backwards. Positions arriving within one frame get times spread evenly
//! between the previous frame and this one (egui stamps frames, not events).

use eframe::egui;
use egui::{Color32, PointerButton, Pos2, Rect, Sense, TextureHandle, TextureOptions, Ui};

use crate::capture::hid::PenReport;
use crate::capture::stroke_builder::StrokeBuilder;
use crate::geom::{Point, Vec2};
use crate::render::{Pixmap, RenderOptions, Scene, View, render, scene_bounds};
use crate::stroke::{Stroke, Units};

/// Free space around the drawing when the view is fitted to it, physical pixels.
pub const FIT_MARGIN_PX: f64 = 32.0;

/// Zoom per scrolled point: a wheel notch (about 50 points) zooms by e^0.25 ≈ 1.28.
pub const ZOOM_PER_SCROLL_POINT: f64 = 0.005;

/// The live stroke's line width, points: as wide as the render's sample dots read.
const LIVE_STROKE_WIDTH: f32 = 1.5;

/// The live stroke's colour: the ink of the raw samples, darker so it reads over the texture.
const LIVE_STROKE_COLOUR: Color32 = Color32::from_rgb(60, 60, 60);

/// Pixels per unit of an empty drawing: about actual size on a 100 dpi screen for millimetres;
/// one to one for pixels; a Wacom's 200 counts per millimetre at 4 pixels per millimetre.
pub const fn default_pixels_per_unit(units: Units) -> f64 {
    match units {
        Units::Mm => 4.0,
        Units::Px => 1.0,
        Units::Device => 0.02,
    }
}

/// What the canvas last rendered: the inputs and the image, for tests and for the PNG export.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The view.
    pub view: View,
    /// The options.
    pub options: RenderOptions,
    /// The scene key it was drawn for.
    pub scene_key: u64,
    /// The image.
    pub pixmap: Pixmap,
}

/// The stroke being drawn.
#[derive(Debug, Default)]
struct LiveStroke {
    builder: StrokeBuilder,
    /// Model points, for painting.
    points: Vec<Point>,
}

/// Line width of the growing fit drawn while the pen moves, points.
pub const PREVIEW_WIDTH: f32 = 2.5;

/// How near a click must be to a segment to select it, points.
pub const PICK_RADIUS_POINTS: f64 = 8.0;

/// The canvas's runtime state (none of it is saved).
#[derive(Default)]
pub struct Canvas {
    view: Option<View>,
    fit_requested: bool,
    /// The view was fitted and the user has not moved it since: refit when the canvas resizes
    /// (the panels settle their widths over the first frames).
    fitted: bool,
    live: Option<LiveStroke>,
    last_time: Option<f64>,
    texture: Option<TextureHandle>,
    rendered: Option<Rendered>,
    error: Option<String>,
    rect: Option<Rect>,
    /// The tablet's stroke in progress, in model units (drawn like the pointer's).
    pub tablet_live: Vec<Point>,
    /// The fit of the stroke being drawn so far, as polylines in model units with their α colour
    /// (drawn over the live stroke while the pen moves).
    pub preview: Vec<(Vec<Point>, [u8; 3])>,
    /// Where the primary button clicked (pressed and released without drawing) this frame, in
    /// model units, with the pick radius in model units.
    click: Option<(Point, f64)>,
}

impl std::fmt::Debug for Canvas {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Canvas")
            .field("view", &self.view)
            .field("drawing", &self.live.is_some())
            .finish_non_exhaustive()
    }
}

impl Canvas {
    /// The samples of the stroke the pointer is drawing, if any.
    pub fn live_stroke(&self) -> Option<&Stroke> {
        self.live
            .as_ref()
            .and_then(|l| l.builder.current())
            .map(|b| &b.stroke)
    }

    /// A click of this frame (see the field), taken.
    pub fn take_click(&mut self) -> Option<(Point, f64)> {
        self.click.take()
    }

    /// Fit the view to the drawing on the next frame.
    pub fn request_fit(&mut self) {
        self.fit_requested = true;
    }

    /// The current view (`None` before the first frame).
    pub fn view(&self) -> Option<View> {
        self.view
    }

    /// What was last rendered.
    pub fn rendered(&self) -> Option<&Rendered> {
        self.rendered.as_ref()
    }

    /// Where the canvas was last shown, screen points.
    pub fn screen_rect(&self) -> Option<Rect> {
        self.rect
    }

    /// Whether a stroke is being drawn.
    pub fn is_drawing(&self) -> bool {
        self.live.is_some()
    }

    /// Shows the canvas filling `ui`; returns a stroke the pen has just finished. `scene_key`
    /// must change whenever `scene` does.
    pub fn ui(
        &mut self,
        ui: &mut Ui,
        scene: &Scene,
        scene_key: u64,
        options: &RenderOptions,
    ) -> Option<Stroke> {
        let (response, painter) = ui.allocate_painter(ui.available_size(), Sense::click_and_drag());
        let rect = response.rect;
        self.rect = Some(rect);
        let ppp = f64::from(ui.ctx().pixels_per_point());
        let width = (f64::from(rect.width()) * ppp).round().max(1.0) as u32;
        let height = (f64::from(rect.height()) * ppp).round().max(1.0) as u32;
        let view = self.sync_view(scene, width, height);
        let to_pixel = |pos: Pos2| {
            Point::new(
                f64::from(pos.x - rect.min.x) * ppp,
                f64::from(pos.y - rect.min.y) * ppp,
            )
        };
        let to_screen = |p: Point| {
            let q = view.to_pixel(p);
            Pos2::new(
                rect.min.x + (q.x / ppp) as f32,
                rect.min.y + (q.y / ppp) as f32,
            )
        };

        // Pan with the secondary or middle button, zoom with the wheel about the pointer.
        let mut view = view;
        if response.dragged_by(PointerButton::Secondary)
            || response.dragged_by(PointerButton::Middle)
        {
            let d = response.drag_delta();
            view = view.panned(Vec2::new(f64::from(d.x) * ppp, f64::from(d.y) * ppp));
            self.fitted = false;
        }
        if let Some(hover) = response.hover_pos() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            let pinch = ui.input(|i| i.zoom_delta());
            let factor = (f64::from(scroll) * ZOOM_PER_SCROLL_POINT).exp() * f64::from(pinch);
            if factor != 1.0 && factor.is_finite() && factor > 0.0 {
                view = view.zoomed(factor, to_pixel(hover));
                self.fitted = false;
            }
        }
        self.view = Some(view);

        let finished = self.pen(ui, &response, |pos| view.to_model(to_pixel(pos)));
        self.click = None;
        if response.clicked()
            && finished.is_none()
            && let Some(pos) = response.interact_pointer_pos()
        {
            let radius = PICK_RADIUS_POINTS * ppp / view.pixels_per_unit;
            self.click = Some((view.to_model(to_pixel(pos)), radius));
        }
        self.paint_texture(ui, &painter, rect, scene, scene_key, options, view);

        if let Some(live) = &self.live {
            let line: Vec<Pos2> = live.points.iter().map(|&p| to_screen(p)).collect();
            painter.line(line, (LIVE_STROKE_WIDTH, LIVE_STROKE_COLOUR));
        }
        if self.tablet_live.len() >= 2 {
            let line: Vec<Pos2> = self.tablet_live.iter().map(|&p| to_screen(p)).collect();
            painter.line(line, (LIVE_STROKE_WIDTH, LIVE_STROKE_COLOUR));
        }
        for (points, [r, g, b]) in &self.preview {
            let line: Vec<Pos2> = points.iter().map(|&p| to_screen(p)).collect();
            painter.line(line, (PREVIEW_WIDTH, Color32::from_rgb(*r, *g, *b)));
        }
        if let Some(error) = &self.error {
            painter.text(
                rect.left_top() + egui::vec2(8.0, 8.0),
                egui::Align2::LEFT_TOP,
                error,
                egui::FontId::proportional(13.0),
                ui.visuals().error_fg_color,
            );
        }
        finished
    }

    /// The view for this frame: the last one resized, or a fitted one when asked or new.
    fn sync_view(&mut self, scene: &Scene, width: u32, height: u32) -> View {
        let fitted = || match scene_bounds(scene) {
            Some(bounds) => View::fit(bounds, width, height, FIT_MARGIN_PX),
            None => {
                let k = default_pixels_per_unit(scene.units);
                View {
                    width,
                    height,
                    center: Point::new(0.5 * f64::from(width) / k, 0.5 * f64::from(height) / k),
                    pixels_per_unit: k,
                }
            }
        };
        let resized = self
            .view
            .is_some_and(|v| (v.width, v.height) != (width, height));
        let refit = self.fit_requested || (self.fitted && resized);
        let view = match self.view {
            Some(view) if !refit => View {
                width,
                height,
                ..view
            },
            _ => {
                self.fitted = true;
                fitted()
            }
        };
        self.fit_requested = false;
        view
    }

    /// Turns this frame's primary-button events into samples; returns the stroke when the
    /// button is released.
    fn pen(
        &mut self,
        ui: &Ui,
        response: &egui::Response,
        to_model: impl Fn(Pos2) -> Point,
    ) -> Option<Stroke> {
        let (events, time, down, origin) = ui.input(|i| {
            (
                i.events.clone(),
                i.time,
                i.pointer.primary_down(),
                i.pointer.press_origin(),
            )
        });
        let previous = self.last_time.unwrap_or(time);
        self.last_time = Some(time);
        if self.live.is_none() && down && response.is_pointer_button_down_on() {
            let mut live = LiveStroke::default();
            if let Some(origin) = origin {
                push(&mut live, previous, to_model(origin));
            }
            self.live = Some(live);
            // The view the user draws in stays put from now on.
            self.fitted = false;
        }
        let live = self.live.as_mut()?;
        let moves: Vec<Pos2> = events
            .iter()
            .filter_map(|e| match e {
                egui::Event::PointerMoved(pos) => Some(*pos),
                egui::Event::PointerButton {
                    pos,
                    button: PointerButton::Primary,
                    pressed: false,
                    ..
                } => Some(*pos),
                _ => None,
            })
            .collect();
        let n = moves.len() as f64;
        for (k, pos) in moves.into_iter().enumerate() {
            let t = previous + (k as f64 + 1.0) / n * (time - previous);
            push(live, t, to_model(pos));
        }
        if down {
            return None;
        }
        let live = self.live.take()?;
        let (mut strokes, _) = live.builder.finish();
        strokes.pop().map(|built| built.stroke)
    }

    fn paint_texture(
        &mut self,
        ui: &Ui,
        painter: &egui::Painter,
        rect: Rect,
        scene: &Scene,
        scene_key: u64,
        options: &RenderOptions,
        view: View,
    ) {
        let stale = self
            .rendered
            .as_ref()
            .is_none_or(|r| r.view != view || r.scene_key != scene_key || r.options != *options);
        if stale {
            match render(scene, &view, options) {
                Ok(pixmap) => {
                    let size = [pixmap.width() as usize, pixmap.height() as usize];
                    let image = egui::ColorImage::from_rgba_premultiplied(size, pixmap.data());
                    match &mut self.texture {
                        Some(texture) => texture.set(image, TextureOptions::LINEAR),
                        None => {
                            self.texture = Some(ui.ctx().load_texture(
                                "kansei-canvas",
                                image,
                                TextureOptions::LINEAR,
                            ));
                        }
                    }
                    self.rendered = Some(Rendered {
                        view,
                        options: *options,
                        scene_key,
                        pixmap,
                    });
                    self.error = None;
                }
                Err(e) => self.error = Some(format!("cannot draw: {e}")),
            }
        }
        if let Some(texture) = &self.texture {
            let uv = Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0));
            painter.image(texture.id(), rect, uv, Color32::WHITE);
        }
    }
}

/// Feeds one position to the stroke builder as a pen report with the tip down.
fn push(live: &mut LiveStroke, t: f64, p: Point) {
    if !(p.x.is_finite() && p.y.is_finite() && t.is_finite()) {
        return;
    }
    live.builder.push(t, &pointer_report(p));
    live.points.push(p);
}

/// A pen report for a pointer position: tip down, no pressure or tilt (the window system gives
/// neither for a mouse).
pub fn pointer_report(p: Point) -> PenReport {
    PenReport {
        report_id: 0,
        in_range: true,
        tip: true,
        barrel: [false; 2],
        invert: false,
        eraser: false,
        contact: true,
        x_mm: p.x,
        y_mm: p.y,
        pressure: None,
        tilt_x_deg: None,
        tilt_y_deg: None,
        raw_x: 0,
        raw_y: 0,
        raw_pressure: None,
        raw_tilt_x: None,
        raw_tilt_y: None,
    }
}
