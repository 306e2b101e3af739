//! dynarole-viewer: writes the one self-contained HTML page of `dynarole view` (the front end
//! bundled at build time from `web/`, its styles, the recording and the trace event
//! vocabulary inlined; a content security policy forbids every request, so the page opens
//! from disk with no network).

use dynarole_recording::{vocabulary_json, Recording};

/// The front end, bundled by `build.rs`.
const BUNDLE: &str = include_str!(concat!(env!("OUT_DIR"), "/viewer.js"));
const STYLE: &str = include_str!("../web/viewer.css");

/// No request of any kind: scripts, styles and data are in the page.
const POLICY: &str = "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; img-src data: blob:";

/// The page showing `recording`.
pub fn html(recording: &Recording) -> Result<String, String> {
    let data = serde_json::to_string(recording).map_err(|e| format!("the recording: {e}"))?;
    // In JSON `<` only occurs inside strings, where `\u003c` means the same: no `</script>`.
    let data = data.replace('<', "\\u003c");
    // The events' colours and meanings come from the one table (`TraceEvent`), so the page
    // spells none of them; it goes beside the recording, whose file format is unchanged.
    let vocabulary = vocabulary_json().to_string().replace('<', "\\u003c");
    let title = escape(&recording.title);
    Ok(format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta http-equiv=\"Content-Security-Policy\" content=\"{POLICY}\">\n\
         <title>dynarole view: {title}</title>\n<style>\n{STYLE}</style>\n</head>\n<body>\n\
         <script type=\"application/json\" id=\"recording\">{data}</script>\n\
         <script type=\"application/json\" id=\"vocabulary\">{vocabulary}</script>\n\
         <script>\n{}\n</script>\n</body>\n</html>\n",
        BUNDLE.replace("</script", "<\\/script")
    ))
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
