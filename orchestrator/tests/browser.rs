//! The replay page and the experiment report in a real headless browser:
//! Debian's `chromium` (`.ci/run` installs it). The page must load without
//! script errors, draw the expected robots at a given round (its state is
//! read back from `#replay-state` in the dumped DOM), and a screenshot must
//! show a picture, not a blank canvas.
//!
//! Without chromium these tests fail, saying so: a browser test that passes
//! without a browser would prove nothing.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use serde_json::Value;

mod common;
use common::{assert_ok, gridswarm, scratch};

/// The browser: `$GRIDSWARM_CHROMIUM`, else `chromium` or `chromium-browser` on the PATH.
fn chromium() -> PathBuf {
    if let Some(p) = std::env::var_os("GRIDSWARM_CHROMIUM") {
        return PathBuf::from(p);
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    for dir in std::env::split_paths(&path) {
        for name in ["chromium", "chromium-browser"] {
            let p = dir.join(name);
            if p.is_file() {
                return p;
            }
        }
    }
    panic!(
        "the browser tests need a headless chromium and none was found on the PATH: install it \
         (`apt-get install -y chromium` on Debian; .ci/run does this) or set GRIDSWARM_CHROMIUM"
    );
}

/// Runs chromium headless on `url` with a fresh profile in `work`, killing
/// it if it hangs. Returns stdout. Its shared memory goes to the profile
/// (`--disable-dev-shm-usage` with `TMPDIR` there), removed with it: chromium
/// leaves files in /dev/shm otherwise.
fn headless(work: &Path, extra: &[String], url: &str) -> String {
    let profile = work.join(format!("profile-{}", std::process::id()));
    let _ = fs::remove_dir_all(&profile);
    fs::create_dir_all(&profile).unwrap();
    let mut cmd = Command::new(chromium());
    cmd.args([
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--hide-scrollbars",
        "--window-size=1200,900",
        "--disable-dev-shm-usage",
    ])
    .env("TMPDIR", &profile)
    .arg(format!("--user-data-dir={}", profile.display()))
    .args(extra)
    .arg(url)
    // Files, not pipes: nobody reads a pipe until chromium exits, and a
    // page's DOM over the pipe's 64 KB (an LFP replay of 800 rounds) would
    // block it for ever.
    .stdout(fs::File::create(profile.join("stdout")).unwrap())
    .stderr(fs::File::create(profile.join("stderr")).unwrap());
    let mut child = cmd.spawn().expect("chromium starts");
    let started = Instant::now();
    loop {
        if child.try_wait().expect("chromium can be waited for").is_some() {
            break;
        }
        if started.elapsed() > Duration::from_secs(90) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("chromium did not finish within 90 s on {url}");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let status = child.wait().unwrap();
    let stdout = String::from_utf8_lossy(&fs::read(profile.join("stdout")).unwrap()).into_owned();
    let stderr = String::from_utf8_lossy(&fs::read(profile.join("stderr")).unwrap()).into_owned();
    let _ = fs::remove_dir_all(&profile);
    assert!(
        status.success(),
        "chromium failed ({status:?}) on {url}:\n{}",
        stderr.lines().rev().take(15).collect::<Vec<_>>().join("\n")
    );
    stdout
}

fn file_url(path: &Path, hash: &str) -> String {
    let abs = fs::canonicalize(path).unwrap();
    format!("file://{}{hash}", abs.display())
}

/// The page's state after load, from `<pre id="replay-state">` in the DOM.
fn page_state(work: &Path, page: &Path, hash: &str) -> Value {
    let dom = headless(work, &["--dump-dom".to_string()], &file_url(page, hash));
    let start = dom.find("<pre id=\"replay-state\">").unwrap_or_else(|| panic!("no state element in:\n{dom:.2000}"));
    let rest = &dom[start..];
    let text = &rest[rest.find('>').unwrap() + 1..rest.find("</pre>").unwrap()];
    let text = text.replace("&lt;", "<").replace("&gt;", ">").replace("&quot;", "\"").replace("&amp;", "&");
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("state is not JSON ({e}): {text}"))
}

fn assert_no_errors(state: &Value) {
    assert_eq!(state["ready"], true, "the page did not finish drawing: {state}");
    assert_eq!(state["errors"].as_array().map(Vec::len), Some(0), "script errors: {state}");
}

fn summary(dir: &Path) -> Value {
    serde_json::from_str(&fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

#[test]
fn replay_page_draws_every_robot_at_a_round() {
    let d = scratch("grid");
    let run = d.join("run");
    assert_ok(&gridswarm(&["simulate", "--robots", "5", "--seed", "2", "--out", run.to_str().unwrap()]));
    let s = summary(&run);
    let rounds = s["rounds"].as_u64().unwrap();
    let k = rounds / 2;
    let state = page_state(&d, &run.join("replay.html"), &format!("#round={k}&paused=1"));
    assert_no_errors(&state);
    assert_eq!(state["round"], k, "{state}");
    assert_eq!(state["rounds"], rounds);
    assert_eq!(state["robots_drawn"], 5, "{state}");
    assert_eq!(state["robots_active"], 5, "{state}");
    assert_eq!(state["playing"], false);
    assert!(state["canvas"][0].as_u64().unwrap() > 300, "{state}");

    // The last round shows the run's own totals.
    let state = page_state(&d, &run.join("replay.html"), &format!("#round={rounds}&paused=1"));
    assert_no_errors(&state);
    assert_eq!(state["targets_found"], s["targets_found"], "{state}");
    assert_eq!(state["targets_marked_found"], s["targets_found"], "{state}");
    // Sensing circles: one per target by default, none once the box is
    // unchecked (the hash unchecks it through the box's own change event).
    assert_eq!(state["sensing_circles"], s["targets_total"], "{state}");
    let state = page_state(&d, &run.join("replay.html"), &format!("#round={rounds}&paused=1&sensing=0"));
    assert_no_errors(&state);
    assert_eq!(state["sensing_circles"], 0, "unchecked, yet circles drawn: {state}");
    let detected = state["detected"].as_f64().unwrap();
    assert!((detected - s["coverage"].as_f64().unwrap()).abs() < 1e-4, "{state} vs {s}");
    // The clock is the engine's (rounds.csv): the end of the last slot, in
    // which the stop that ended the search happened.
    let rounds_csv = fs::read_to_string(run.join("rounds.csv")).unwrap();
    let last: f64 = rounds_csv.lines().last().unwrap().split(',').nth(1).unwrap().parse().unwrap();
    let t = state["time_s"].as_f64().unwrap();
    assert!((t - last).abs() < 1e-2, "{state}: {last}");
    assert!(s["search_time_s"].as_f64().unwrap() <= t + 1e-2, "{state} vs {s}");

    // Playing (no hash) starts without errors either.
    let state = page_state(&d, &run.join("replay.html"), "");
    assert_no_errors(&state);
    assert_eq!(state["robots_drawn"], 5);
}

#[test]
fn replay_screenshot_is_a_picture() {
    let d = scratch("screenshot");
    let run = d.join("run");
    assert_ok(&gridswarm(&["simulate", "--robots", "4", "--seed", "1", "--out", run.to_str().unwrap()]));
    let png_path = d.join("replay.png");
    headless(
        &d,
        &[format!("--screenshot={}", png_path.display())],
        &file_url(&run.join("replay.html"), "#round=40.5&paused=1"),
    );
    let decoder = png::Decoder::new(fs::File::open(&png_path).expect("chromium wrote the screenshot"));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let (w, h) = (info.width as usize, info.height as usize);
    assert_eq!((w, h), (1200, 900));
    let channels = info.color_type.samples();
    assert!(channels >= 3, "{:?}", info.color_type);
    let px = |x: usize, y: usize| {
        let i = (y * w + x) * channels;
        (buf[i], buf[i + 1], buf[i + 2])
    };
    // The map occupies the left three quarters below the header: count what is drawn there.
    let mut colours = std::collections::HashSet::new();
    let (mut drawn, mut total) = (0usize, 0usize);
    let background = px(w * 3 / 4 - 5, h - 70);
    for y in (60..h - 60).step_by(2) {
        for x in (5..w * 3 / 4).step_by(2) {
            let p = px(x, y);
            colours.insert(p);
            total += 1;
            if p != background && p != (255, 255, 255) {
                drawn += 1;
            }
        }
    }
    assert!(colours.len() > 200, "only {} distinct colours: a blank page?", colours.len());
    assert!(drawn * 4 > total, "only {drawn} of {total} sampled pixels drawn");
    // Robot 2's orange fill appears (robots are drawn on top of everything).
    let orange = (0..h).any(|y| (0..w * 3 / 4).any(|x| px(x, y) == (0xff, 0x7f, 0x0e)));
    assert!(orange, "robot 2 is not on the screenshot");
}

#[test]
fn lfp_replay_and_failures_load() {
    let d = scratch("lfp");
    let run = d.join("run");
    assert_ok(&gridswarm(&["simulate", "--algorithm", "lfp", "--robots", "3", "--out", run.to_str().unwrap()]));
    // As the distributed engine will report a failure and refused moves.
    let mut s = summary(&run);
    s["failures_detected"] = serde_json::json!([{ "robot": 2, "round": 3, "cause": "death" }]);
    s["refused_moves"] = serde_json::json!([{ "robot": 0, "round": 4 }]);
    fs::write(run.join("summary.json"), s.to_string()).unwrap();
    assert_ok(&gridswarm(&["replay", run.to_str().unwrap()]));
    let state = page_state(&d, &run.join("replay.html"), "#round=4.5&paused=1");
    assert_no_errors(&state);
    assert_eq!(state["round"], 4);
    assert_eq!(state["robots_drawn"], 3, "{state}");
    assert_eq!(state["robots_failed"], 1, "{state}");
    assert_eq!(state["robots_active"], 2, "{state}");
}

#[test]
fn experiment_report_loads() {
    let d = scratch("report");
    let out = d.join("out");
    assert_ok(&gridswarm(&["experiment", "--runs", "2", "--robots", "1-2", "--out", out.to_str().unwrap()]));
    let dom = headless(&d, &["--dump-dom".to_string()], &file_url(&out.join("report.html"), ""));
    assert!(dom.contains("<svg") && dom.contains("<table>"), "{dom:.2000}");
    assert!(dom.contains("Claim (a)"));
}
