//! The file chooser: [`Chooser`], a window drawn by egui itself (a folder's listing, the parent
//! folder, a file name), so it needs no desktop portal or toolkit and behaves the same under
//! Xvfb and in the headless UI tests. It only chooses a path; the file panel's buttons act on it.

use std::path::{Path, PathBuf};

use eframe::egui;

/// Height of the folder listing, points.
const LISTING_HEIGHT: f32 = 260.0;

/// What the user did.
#[derive(Clone, Debug, PartialEq)]
pub enum Choice {
    /// Chose this path (the file may not exist yet: a save target).
    Chosen(PathBuf),
    /// Closed the chooser without choosing.
    Cancelled,
}

/// One entry of the listing.
#[derive(Clone, Debug, PartialEq)]
struct Entry {
    name: String,
    folder: bool,
}

/// A file chooser window (see the module documentation).
#[derive(Clone, Debug)]
pub struct Chooser {
    folder: PathBuf,
    name: String,
    listing: Result<Vec<Entry>, String>,
}

impl Chooser {
    /// A chooser showing `start`'s folder with `start`'s file name filled in; a `start` that is
    /// a folder is shown with no name, and an empty or missing one starts in the current folder.
    pub fn new(start: &Path) -> Self {
        let (folder, name) = if start.is_dir() {
            (start.to_path_buf(), String::new())
        } else {
            let name = start
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let folder = start
                .parent()
                .filter(|p| p.is_dir())
                .map(Path::to_path_buf)
                .or_else(|| std::env::current_dir().ok())
                .unwrap_or_else(|| PathBuf::from("."));
            (folder, name)
        };
        let listing = list(&folder);
        Chooser {
            folder,
            name,
            listing,
        }
    }

    /// The folder shown.
    pub fn folder(&self) -> &Path {
        &self.folder
    }

    /// Shows the window; returns what the user did this frame, if anything.
    pub fn show(&mut self, ctx: &egui::Context) -> Option<Choice> {
        let mut choice = None;
        let mut enter: Option<PathBuf> = None;
        let mut open = true;
        egui::Window::new("Choose a file")
            .open(&mut open)
            .collapsible(false)
            .default_width(420.0)
            .show(ctx, |ui| {
                ui.horizontal(|ui| {
                    if ui
                        .add_enabled(self.folder.parent().is_some(), egui::Button::new("Up"))
                        .on_hover_text("The parent folder")
                        .clicked()
                    {
                        enter = self.folder.parent().map(Path::to_path_buf);
                    }
                    ui.label(self.folder.display().to_string());
                });
                ui.separator();
                egui::ScrollArea::vertical()
                    .max_height(LISTING_HEIGHT)
                    .show(ui, |ui| match &self.listing {
                        Ok(entries) => {
                            for entry in entries {
                                let label = if entry.folder {
                                    format!("{}/", entry.name)
                                } else {
                                    entry.name.clone()
                                };
                                let picked = !entry.folder && entry.name == self.name;
                                if ui.selectable_label(picked, label).clicked() {
                                    if entry.folder {
                                        enter = Some(self.folder.join(&entry.name));
                                    } else {
                                        self.name = entry.name.clone();
                                    }
                                }
                            }
                        }
                        Err(why) => {
                            ui.colored_label(ui.visuals().error_fg_color, why);
                        }
                    });
                ui.separator();
                ui.horizontal(|ui| {
                    ui.label("File:");
                    ui.text_edit_singleline(&mut self.name);
                });
                ui.horizontal(|ui| {
                    let named = !self.name.trim().is_empty();
                    if ui.add_enabled(named, egui::Button::new("Choose")).clicked() {
                        choice = Some(Choice::Chosen(self.folder.join(self.name.trim())));
                    }
                    if ui.button("Cancel").clicked() {
                        choice = Some(Choice::Cancelled);
                    }
                });
            });
        if let Some(folder) = enter {
            self.listing = list(&folder);
            self.folder = folder;
        }
        if !open {
            choice = Some(Choice::Cancelled);
        }
        choice
    }
}

/// A folder's entries, folders first, each group by name; hidden entries (a leading dot) left
/// out. An unreadable folder gives the reason, naming it.
fn list(folder: &Path) -> Result<Vec<Entry>, String> {
    let read = std::fs::read_dir(folder).map_err(|e| format!("{}: {e}", folder.display()))?;
    let mut entries: Vec<Entry> = read
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            (!name.starts_with('.')).then(|| Entry {
                folder: e.path().is_dir(),
                name,
            })
        })
        .collect();
    entries.sort_by(|a, b| b.folder.cmp(&a.folder).then_with(|| a.name.cmp(&b.name)));
    Ok(entries)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_listing_puts_folders_first_and_hides_dot_files() {
        let dir = std::env::temp_dir().join(format!("kansei-chooser-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("b-folder")).expect("temp dir");
        for name in ["a.json", "c.hid", ".hidden"] {
            std::fs::write(dir.join(name), "x").expect("temp file");
        }
        let names: Vec<(String, bool)> = list(&dir)
            .expect("readable")
            .into_iter()
            .map(|e| (e.name, e.folder))
            .collect();
        assert_eq!(
            names,
            vec![
                ("b-folder".to_owned(), true),
                ("a.json".to_owned(), false),
                ("c.hid".to_owned(), false),
            ]
        );
        let chooser = Chooser::new(&dir.join("new.json"));
        assert_eq!(chooser.folder(), dir.as_path());
        assert_eq!(chooser.name, "new.json");
        let missing = list(&dir.join("missing")).expect_err("no such folder");
        assert!(missing.contains("missing"), "{missing}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
