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
/// it if it hangs. Returns stdout. Its shared memory goes to a temporary
/// folder of its own (`--disable-dev-shm-usage` with `TMPDIR` there),
/// removed after it: chromium leaves files in /dev/shm otherwise. That
/// folder is a short path under the system's temporary folder, not in
/// `work`: chromium makes a Unix socket in `TMPDIR`, and a socket's path
/// may not pass 108 bytes, which a checkout a few folders deep did (the
/// browser crashed when the repository's path passed about 20 characters).
fn headless(work: &Path, extra: &[String], url: &str) -> String {
    headless_sized(work, "1200,900", extra, url)
}

/// A folder of its own under the system's temporary folder, removed when
/// dropped (also when a test panics).
struct ShortTmp(PathBuf);

impl ShortTmp {
    fn new() -> Self {
        static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let k = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let d = std::env::temp_dir().join(format!("gridswarm-chromium-{}-{k}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        fs::create_dir_all(&d).unwrap();
        ShortTmp(d)
    }
}

impl Drop for ShortTmp {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.0);
    }
}

/// [`headless`] in a window of `size` (`W,H` pixels).
fn headless_sized(work: &Path, size: &str, extra: &[String], url: &str) -> String {
    let profile = work.join(format!("profile-{}", std::process::id()));
    let _ = fs::remove_dir_all(&profile);
    fs::create_dir_all(&profile).unwrap();
    let tmp = ShortTmp::new();
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
        "--disable-dev-shm-usage",
    ])
    .arg(format!("--window-size={size}"))
    .env("TMPDIR", &tmp.0)
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
    // Robot 1's orange fill appears (robots are drawn on top of everything).
    let orange = (0..h).any(|y| (0..w * 3 / 4).any(|x| px(x, y) == (0xff, 0x7f, 0x0e)));
    assert!(orange, "robot 1 is not on the screenshot");
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

#[test]
fn replay_marks_crashed_and_frozen_robots_and_says_the_conditions() {
    let d = scratch("faults");
    let run = d.join("run");
    assert_ok(&gridswarm(&[
        "simulate",
        "--robots",
        "30",
        "--seed",
        "2",
        "--kill",
        "1@3",
        "--freeze",
        "2@4",
        "--loss",
        "0.1",
        "--out",
        run.to_str().unwrap(),
    ]));
    let page = run.join("replay.html");
    let state = page_state(&d, &page, "#round=2&paused=1");
    assert_no_errors(&state);
    assert_eq!((state["robots_crashed"].as_u64(), state["robots_frozen"].as_u64()), (Some(0), Some(0)), "{state}");
    let state = page_state(&d, &page, "#round=5&paused=1");
    assert_no_errors(&state);
    assert_eq!(state["robots_crashed"], 1, "{state}");
    assert_eq!(state["robots_frozen"], 1, "{state}");
    assert_eq!(state["robots_active"], 28, "{state}");
    let faults: Vec<&str> = state["settings"]["faults"].as_array().unwrap().iter().filter_map(Value::as_str).collect();
    assert_eq!(faults, ["--kill 1@3", "--freeze 2@4"], "{state}");
    assert!(state["settings"]["radio"].as_str().unwrap().contains("loss 0.1"), "{state}");
    // 24 colours for the first 24 robots, none the targets' red.
    let colours: Vec<&str> = state["robot_colours"].as_array().unwrap().iter().filter_map(Value::as_str).collect();
    let distinct: std::collections::HashSet<&&str> = colours[..24].iter().collect();
    assert_eq!(distinct.len(), 24, "{colours:?}");
    assert!(colours.iter().all(|c| !c.eq_ignore_ascii_case("#d62728")), "{colours:?}");
}

/// A report opened at 940 px (its text column 884 px wide): the smallest
/// text of any figure on screen, whether any table scrolls sideways, and
/// how many figures there are, measured by a script added to a copy.
fn measure(work: &Path, report: &Path) -> Value {
    const SCRIPT: &str = r#"<script>(function () {
  var r = { min_font: 1e9, smallest: "", overflow: [], svgs: 0 };
  document.querySelectorAll("svg").forEach(function (svg) {
    var w = svg.width.baseVal.value, box = svg.getBoundingClientRect();
    if (!w || !box.width) return;
    r.svgs++;
    svg.querySelectorAll("text").forEach(function (t) {
      if (!t.textContent.trim()) return;
      var px = parseFloat(getComputedStyle(t).fontSize) * box.width / w;
      if (px < r.min_font) { r.min_font = px; r.smallest = t.textContent.slice(0, 60); }
    });
  });
  document.querySelectorAll(".scroll").forEach(function (d) {
    if (d.scrollWidth > d.clientWidth + 1) r.overflow.push(d.querySelector("th") ? d.textContent.slice(0, 60) : "?");
  });
  var pre = document.createElement("pre"); pre.id = "measure"; pre.textContent = JSON.stringify(r);
  document.body.appendChild(pre);
})();</script>"#;
    let html = fs::read_to_string(report).unwrap().replace("</body>", &format!("{SCRIPT}</body>"));
    let copy = report.with_file_name("measured.html");
    fs::write(&copy, html).unwrap();
    let dom = headless_sized(work, "940,900", &["--dump-dom".to_string()], &file_url(&copy, ""));
    let start = dom.find("<pre id=\"measure\">").unwrap_or_else(|| panic!("no measure in:\n{dom:.2000}"));
    let rest = &dom[start..];
    let text = &rest[rest.find('>').unwrap() + 1..rest.find("</pre>").unwrap()];
    serde_json::from_str(&text.replace("&quot;", "\"").replace("&amp;", "&")).unwrap()
}

#[test]
fn reports_read_at_880_px() {
    let d = scratch("readable");
    let o = |name: &str| d.join(name);
    let reports: [(&[&str], &str, &str); 7] = [
        (&["experiment", "--runs", "2", "--robots", "1-3"], "fig7", "report.html"),
        (
            &["experiment", "--scenario", "random:1", "--maps", "2", "--runs", "2", "--robots", "1-2"],
            "maps",
            "report.html",
        ),
        (&["experiment", "--grids"], "grids", "grids.html"),
        (&["experiment", "failures", "--runs", "3", "--robots", "6"], "failures", "report.html"),
        (&["experiment", "radio", "--runs", "2"], "radio", "report.html"),
        (&["experiment", "readings", "--robots", "1-2", "--runs", "2", "--seeds", "1"], "readings", "report.html"),
        (&["experiment", "scale", "--robots", "2,3", "--runs", "1"], "scale", "report.html"),
    ];
    for (args, name, page) in reports {
        let out = o(name);
        let mut all = args.to_vec();
        all.extend(["--out", out.to_str().unwrap()]);
        assert_ok(&gridswarm(&all));
        let m = measure(&d, &out.join(page));
        assert!(m["svgs"].as_u64().unwrap() >= 1, "{name}: no figure: {m}");
        let min = m["min_font"].as_f64().unwrap();
        assert!(min >= 11.0, "{name}: text of {min:.1} px on screen: {m}");
        assert_eq!(m["overflow"].as_array().map(Vec::len), Some(0), "{name}: a table is cut off: {m}");
    }
}
