//! The tablet in the app: [`TabletFeed`] reads a capture source on its own thread and cuts its
//! reports into strokes with the capture layer's
//! [`StrokeBuilder`] — the code `kansei capture` runs, so pressure and tilt arrive in the
//! drawing exactly as a capture file would hold them.
//!
//! The source is a live tablet (HID or evdev, feature `live`) or a hid-recorder recording
//! replayed at its recorded pace ([`Paced`]): the recording goes through the same decoder,
//! builder and app path as the live tablet, which is how the path is tested without hardware.
//! The thread opens the source itself (device handles need not cross threads), sends every pen
//! report to the UI thread, and stops when the feed is dropped (it polls a flag at least every
//! 0.1 s: live sources and [`Paced`] return an idle tick that often).

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::thread::JoinHandle;

use crate::capture::hid::PenReport;
use crate::capture::paced::Paced;
use crate::capture::recorder::Recording;
use crate::capture::source::{Decoded, DeviceInfo, Next, PenSource, RecordingSource, SourceError};
use crate::capture::stroke_builder::{StrokeBuilder, Tool};
use crate::geom::Point;
use crate::stroke::Stroke;

/// Where the app's tablet input comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum TabletChoice {
    /// A live tablet: the node `kansei devices` lists, or the first one found.
    Live(Option<String>),
    /// A hid-recorder recording played as if live, at `speed` × its recorded pace.
    Recording {
        /// The `.hid` file.
        path: PathBuf,
        /// Pace factor (1 = as recorded).
        speed: f64,
    },
}

/// What the reading thread says.
#[derive(Debug)]
enum Message {
    Opened(Box<DeviceInfo>),
    Report(f64, Box<PenReport>),
    Ended,
    Failed(String),
}

/// Where the feed is.
#[derive(Clone, Debug, PartialEq)]
pub enum FeedState {
    /// The thread is opening the source.
    Opening,
    /// Reports are arriving (or may).
    Running,
    /// The recording has ended.
    Ended,
    /// The source failed (not found, no permission, unplugged): the reason.
    Failed(String),
}

/// A tablet read on a background thread (see the module documentation).
#[derive(Debug)]
pub struct TabletFeed {
    rx: Receiver<Message>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
    builder: StrokeBuilder,
    info: Option<DeviceInfo>,
    state: FeedState,
    /// Eraser strokes seen (not drawn: the app has no erasing yet).
    erasers: usize,
}

impl TabletFeed {
    /// Starts reading `choice` on a new thread; `wake` is called after every message (the UI
    /// repaints and polls).
    pub fn start(choice: TabletChoice, wake: Box<dyn Fn() + Send>) -> Self {
        let (tx, rx) = channel();
        let stop = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&stop);
        let spawned = std::thread::Builder::new()
            .name("kansei-tablet".into())
            .spawn(move || {
                let send = |message: Message| {
                    let sent = tx.send(message).is_ok();
                    wake();
                    sent
                };
                let mut source = match open(&choice) {
                    Ok(source) => source,
                    Err(e) => {
                        send(Message::Failed(e));
                        return;
                    }
                };
                if !send(Message::Opened(Box::new(source.info().clone()))) {
                    return;
                }
                while !flag.load(Ordering::Relaxed) {
                    let message = match source.next() {
                        Ok(Next::Event(event)) => match event.decoded {
                            Decoded::Pen(report) => Message::Report(event.t, Box::new(report)),
                            Decoded::Other | Decoded::Error(_) => continue,
                        },
                        Ok(Next::Idle) => continue,
                        Ok(Next::End) => Message::Ended,
                        Err(e) => Message::Failed(e.to_string()),
                    };
                    let last = matches!(message, Message::Ended | Message::Failed(_));
                    if !send(message) || last {
                        return;
                    }
                }
            });
        let (thread, state) = match spawned {
            Ok(handle) => (Some(handle), FeedState::Opening),
            Err(e) => (
                None,
                FeedState::Failed(format!("cannot start a thread: {e}")),
            ),
        };
        TabletFeed {
            rx,
            stop,
            thread,
            builder: StrokeBuilder::new(),
            info: None,
            state,
            erasers: 0,
        }
    }

    /// Takes in what has arrived; returns the pen strokes finished since the last call, in
    /// millimetres on the tablet (eraser strokes are counted, not returned).
    pub fn poll(&mut self) -> Vec<Stroke> {
        loop {
            match self.rx.try_recv() {
                Ok(Message::Opened(info)) => {
                    self.info = Some(*info);
                    self.state = FeedState::Running;
                }
                Ok(Message::Report(t, report)) => self.builder.push(t, &report),
                Ok(Message::Ended) => {
                    self.builder.end_run();
                    self.state = FeedState::Ended;
                }
                Ok(Message::Failed(reason)) => {
                    // The stroke in progress is kept, as `kansei capture` keeps it.
                    self.builder.end_run();
                    self.state = FeedState::Failed(reason);
                }
                Err(TryRecvError::Empty) => break,
                Err(TryRecvError::Disconnected) => {
                    self.builder.end_run();
                    if matches!(self.state, FeedState::Opening | FeedState::Running) {
                        self.state = FeedState::Failed("the tablet thread stopped".into());
                    }
                    break;
                }
            }
        }
        let mut strokes = Vec::new();
        for built in self.builder.take_finished() {
            match built.tool {
                Tool::Pen => strokes.push(built.stroke),
                Tool::Eraser => self.erasers += 1,
            }
        }
        strokes
    }

    /// The stroke being drawn, as points (empty between strokes or while the eraser is down).
    pub fn live_points(&self) -> Vec<Point> {
        match self.builder.current() {
            Some(run) if run.tool == Tool::Pen => {
                run.stroke.samples.iter().map(|s| s.point()).collect()
            }
            _ => Vec::new(),
        }
    }

    /// The stroke being drawn, in millimetres (`None` between strokes or while the eraser is
    /// down).
    pub fn live_stroke(&self) -> Option<Stroke> {
        match self.builder.current() {
            Some(run) if run.tool == Tool::Pen => Some(run.stroke.clone()),
            _ => None,
        }
    }

    /// Whether the pen is down.
    pub fn is_drawing(&self) -> bool {
        self.builder.current().is_some()
    }

    /// Where the feed is.
    pub fn state(&self) -> &FeedState {
        &self.state
    }

    /// The tablet, once opened.
    pub fn info(&self) -> Option<&DeviceInfo> {
        self.info.as_ref()
    }

    /// One line for the status bar.
    pub fn summary(&self) -> String {
        let name = self
            .info
            .as_ref()
            .and_then(|i| i.name.clone())
            .unwrap_or_else(|| "tablet".into());
        let erasers = if self.erasers > 0 {
            format!(" ({} eraser strokes ignored)", self.erasers)
        } else {
            String::new()
        };
        match &self.state {
            FeedState::Opening => "tablet: opening…".into(),
            FeedState::Running => format!("tablet: {name}{erasers}"),
            FeedState::Ended => format!("tablet: {name}: recording ended{erasers}"),
            FeedState::Failed(reason) => format!("tablet: {reason}"),
        }
    }
}

impl Drop for TabletFeed {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(thread) = self.thread.take() {
            // The thread sees the flag within a poll interval.
            let _ = thread.join();
        }
    }
}

/// Opens the source (on the reading thread).
fn open(choice: &TabletChoice) -> Result<Box<dyn PenSource>, String> {
    match choice {
        TabletChoice::Recording { path, speed } => {
            let label = path.display().to_string();
            let text = std::fs::read_to_string(path).map_err(|e| format!("{label}: {e}"))?;
            let recording = Recording::parse(&text).map_err(|e| format!("{label}: {e}"))?;
            let source = RecordingSource::new(recording, &label).map_err(|e| e.to_string())?;
            let paced = Paced::new(source, *speed).map_err(|e: SourceError| e.to_string())?;
            Ok(Box::new(paced))
        }
        TabletChoice::Live(device) => open_live(device.as_deref()),
    }
}

#[cfg(feature = "live")]
fn open_live(device: Option<&str>) -> Result<Box<dyn PenSource>, String> {
    crate::capture::open::open_live(device).map_err(|e| e.to_string())
}

#[cfg(not(feature = "live"))]
fn open_live(_device: Option<&str>) -> Result<Box<dyn PenSource>, String> {
    Err("kansei was built without the `live` feature: no tablet access".into())
}
