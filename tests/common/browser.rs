//! Headless Chromium for the browser tests (`svg_browser`, `serve_browser`): which command runs
//! here, and the command line both start it with.

use std::path::Path;
use std::process::{Command, Stdio};

/// The browser's executable names, tried in order (Debian's package installs `chromium`).
pub const BROWSERS: [&str; 2] = ["chromium", "chromium-browser"];

/// The browser command, or the reason none runs here.
pub fn browser() -> Result<&'static str, String> {
    for name in BROWSERS {
        let ok = Command::new(name)
            .arg("--version")
            .stdin(Stdio::null())
            .output()
            .is_ok_and(|o| o.status.success());
        if ok {
            return Ok(name);
        }
    }
    Err(format!("none of {BROWSERS:?} runs"))
}

/// `browser` headless with a fresh profile in `profile` (emptied first) and a `size` window,
/// stdin and stdout closed, stderr piped. Without the background-networking flags the browser's
/// connections are refused on a closed network, and it may wait on them.
pub fn headless(browser: &str, profile: &Path, size: (u32, u32)) -> Result<Command, String> {
    let _ = std::fs::remove_dir_all(profile);
    std::fs::create_dir_all(profile).map_err(|e| format!("{}: {e}", profile.display()))?;
    let mut command = Command::new(browser);
    command
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--hide-scrollbars",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--window-size={},{}", size.0, size.1))
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    Ok(command)
}
