//! `dynarole view --video`: the page rendered frame by frame in headless Chromium, driven
//! through the DevTools protocol over a pipe (`--remote-debugging-pipe`: requests on fd 3,
//! answers on fd 4, each message ending in a NUL byte), the screenshots encoded by ffmpeg.

use crate::load::Failure;
use base64::Engine;
use dynarole_recording::Recording;
use serde_json::{json, Value};
use std::fs::File;
use std::io::{BufRead, BufReader, Write};
use std::os::fd::{FromRawFd, RawFd};
use std::os::unix::process::CommandExt;
use std::path::Path;
use std::process::{Child, Command, Stdio};

/// The most frames one video may have (an hour at 25 frames per second).
const MAX_FRAMES: u64 = 90_000;
/// Attempts (100 ms apart) to see the page's viewer ready.
const READY_TRIES: u32 = 300;

/// How the video is made.
#[derive(Clone, Copy, Debug)]
pub struct VideoOptions {
    pub fps: u32,
    /// Run seconds per video second.
    pub speed: f64,
}

/// Renders `recording` (its page already written to `page`) into `out` (MP4, H.264).
pub fn render(
    recording: &Recording,
    page: &Path,
    out: &Path,
    options: VideoOptions,
) -> Result<(), Failure> {
    let step_ms = 1000.0 * options.speed / f64::from(options.fps);
    if !(options.fps > 0 && step_ms.is_finite() && step_ms > 0.0) {
        return Err(Failure::Usage(
            "--fps and --speed must be more than 0".into(),
        ));
    }
    let frames = (recording.end_ms / step_ms).ceil() as u64 + 1;
    if frames > MAX_FRAMES {
        return Err(Failure::Usage(format!(
            "{frames} frames: more than {MAX_FRAMES}; raise --speed or lower --fps"
        )));
    }
    require("chromium", "scripts/ensure-chromium")?;
    require("ffmpeg", "scripts/ensure-chromium --ffmpeg")?;
    let page = std::fs::canonicalize(page)
        .map_err(|e| Failure::Internal(format!("{}: {e}", page.display())))?;
    let mut browser = Browser::start()?;
    let result = browser.frames(&page, frames, step_ms, options.fps, out);
    browser.stop();
    result
}

fn require(tool: &str, installer: &str) -> Result<(), Failure> {
    let found = Command::new("sh")
        .args(["-c", &format!("command -v {tool}")])
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if found {
        Ok(())
    } else {
        Err(Failure::Internal(format!(
            "`{tool}` is not installed (Debian's package; `{installer}` installs it)"
        )))
    }
}

/// A headless Chromium and the two ends of its DevTools pipe.
struct Browser {
    child: Child,
    to: File,
    from: BufReader<File>,
    next_id: u64,
    session: Option<String>,
}

fn pipe() -> Result<(RawFd, RawFd), Failure> {
    let mut fds = [0 as libc::c_int; 2];
    // SAFETY: `fds` has room for the two descriptors pipe2 writes.
    let rc = unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC) };
    if rc != 0 {
        return Err(Failure::Internal(format!(
            "pipe: {}",
            std::io::Error::last_os_error()
        )));
    }
    Ok((fds[0], fds[1]))
}

/// The flags of every headless Chromium the project starts (the video export and the viewer's
/// tests): no network services, no GPU, no first-run pages; pages from files may load files.
pub const HEADLESS_FLAGS: &[&str] = &[
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--no-first-run",
    "--allow-file-access-from-files",
];

impl Browser {
    fn start() -> Result<Browser, Failure> {
        let (request_read, request_write) = pipe()?;
        let (answer_read, answer_write) = pipe()?;
        let mut command = Command::new("chromium");
        command
            .args(HEADLESS_FLAGS)
            .args([
                "--hide-scrollbars",
                "--window-size=1280,720",
                "--remote-debugging-pipe",
                "about:blank",
            ])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null());
        // SAFETY: between fork and exec the child only calls fcntl and dup2 (async-signal-safe)
        // to put the pipe's ends on fds 3 and 4, where Chromium expects them. They are first
        // copied above 10 (the pipe's own fds may be 3 or 4, and dup2 onto itself would keep
        // close-on-exec); dup2 clears close-on-exec on the final copies.
        unsafe {
            command.pre_exec(move || {
                let request = libc::fcntl(request_read, libc::F_DUPFD_CLOEXEC, 10);
                let answer = libc::fcntl(answer_write, libc::F_DUPFD_CLOEXEC, 10);
                if request < 0
                    || answer < 0
                    || libc::dup2(request, 3) < 0
                    || libc::dup2(answer, 4) < 0
                {
                    return Err(std::io::Error::last_os_error());
                }
                Ok(())
            });
        }
        let child = command
            .spawn()
            .map_err(|e| Failure::Internal(format!("cannot start chromium: {e}")))?;
        // SAFETY: each descriptor came from pipe2 above and is owned by exactly one File (the
        // child's ends are closed here, the parent's wrapped once).
        let (to, from) = unsafe {
            libc::close(request_read);
            libc::close(answer_write);
            (
                File::from_raw_fd(request_write),
                File::from_raw_fd(answer_read),
            )
        };
        Ok(Browser {
            child,
            to,
            from: BufReader::new(from),
            next_id: 0,
            session: None,
        })
    }

    /// Sends one request and waits for its answer (events in between are skipped).
    fn call(&mut self, method: &str, params: Value) -> Result<Value, Failure> {
        self.next_id += 1;
        let id = self.next_id;
        let mut message = json!({ "id": id, "method": method, "params": params });
        if let Some(session) = &self.session {
            message["sessionId"] = json!(session);
        }
        let mut bytes = message.to_string().into_bytes();
        bytes.push(0);
        let broken =
            |e: std::io::Error| Failure::Internal(format!("chromium's DevTools pipe: {e}"));
        self.to.write_all(&bytes).map_err(broken)?;
        loop {
            let mut raw = Vec::new();
            let n = self.from.read_until(0, &mut raw).map_err(broken)?;
            if n == 0 {
                return Err(Failure::Internal(
                    "chromium closed its DevTools pipe".into(),
                ));
            }
            raw.pop();
            let answer: Value = serde_json::from_slice(&raw)
                .map_err(|e| Failure::Internal(format!("chromium's DevTools answer: {e}")))?;
            if answer["id"] != json!(id) {
                continue;
            }
            if let Some(error) = answer.get("error") {
                return Err(Failure::Internal(format!("chromium: {method}: {error}")));
            }
            return Ok(answer["result"].clone());
        }
    }

    fn evaluate(&mut self, expression: &str) -> Result<Value, Failure> {
        let result = self.call(
            "Runtime.evaluate",
            json!({ "expression": expression, "returnByValue": true }),
        )?;
        Ok(result["result"]["value"].clone())
    }

    fn open(&mut self, page: &Path) -> Result<(), Failure> {
        let url = format!("file://{}", page.display());
        let target = self.call("Target.createTarget", json!({ "url": url }))?;
        let attached = self.call(
            "Target.attachToTarget",
            json!({ "targetId": target["targetId"], "flatten": true }),
        )?;
        self.session = attached["sessionId"].as_str().map(str::to_string);
        for _ in 0..READY_TRIES {
            if self.evaluate("!!window.dynaroleViewer")? == json!(true) {
                return Ok(());
            }
            std::thread::sleep(std::time::Duration::from_millis(100));
        }
        Err(Failure::Internal(
            "the page's viewer did not start in chromium".into(),
        ))
    }

    fn frames(
        &mut self,
        page: &Path,
        frames: u64,
        step_ms: f64,
        fps: u32,
        out: &Path,
    ) -> Result<(), Failure> {
        self.open(page)?;
        let mut ffmpeg = Command::new("ffmpeg")
            .args(["-y", "-loglevel", "error", "-f", "image2pipe", "-framerate"])
            .arg(fps.to_string())
            .args(["-i", "-", "-c:v", "libx264", "-pix_fmt", "yuv420p"])
            .args(["-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2"])
            .arg(out)
            .stdin(Stdio::piped())
            .spawn()
            .map_err(|e| Failure::Internal(format!("cannot start ffmpeg: {e}")))?;
        let mode = crate::progress::ProgressMode::for_stderr().map_err(Failure::Usage)?;
        let progress = crate::progress::Progress::start(mode, "video", frames, "frames");
        let written = self.write_frames(&mut ffmpeg, frames, step_ms, &progress);
        progress.finish();
        drop(ffmpeg.stdin.take());
        let status = ffmpeg
            .wait()
            .map_err(|e| Failure::Internal(format!("ffmpeg: {e}")))?;
        written?;
        if !status.success() {
            return Err(Failure::Internal(format!("ffmpeg failed ({status})")));
        }
        Ok(())
    }

    fn write_frames(
        &mut self,
        ffmpeg: &mut Child,
        frames: u64,
        step_ms: f64,
        progress: &crate::progress::Progress,
    ) -> Result<(), Failure> {
        let Some(stdin) = ffmpeg.stdin.as_mut() else {
            return Err(Failure::Internal("ffmpeg has no input".into()));
        };
        for k in 0..frames {
            self.evaluate(&format!("dynaroleViewer.seek({})", k as f64 * step_ms))?;
            let shot = self.call("Page.captureScreenshot", json!({ "format": "png" }))?;
            let data = shot["data"].as_str().unwrap_or_default();
            let png = base64::engine::general_purpose::STANDARD
                .decode(data)
                .map_err(|e| Failure::Internal(format!("a screenshot: {e}")))?;
            stdin
                .write_all(&png)
                .map_err(|e| Failure::Internal(format!("ffmpeg's input: {e}")))?;
            progress.inc();
        }
        Ok(())
    }

    fn stop(&mut self) {
        let _ = self.call("Browser.close", json!({}));
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
