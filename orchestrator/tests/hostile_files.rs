//! The hostile scenario files of issue 11 (shared/tests/fixtures/hostile)
//! through the real binary: `check` and `simulate` on each end within the
//! issue's 5 s with one `error:` line naming the field, never a panic, a
//! hang or an abort.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The bound for any file of at most 1 MB.
const BOUND: Duration = Duration::from_secs(5);

fn fixtures() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/tests/fixtures/hostile");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files
}

/// Runs the binary, killing it (and failing) past [`BOUND`].
fn within_bound(args: &[&str]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gridswarm"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let start = Instant::now();
    while child.try_wait().expect("wait").is_none() {
        if start.elapsed() > BOUND {
            let _ = child.kill();
            let _ = child.wait();
            panic!("gridswarm {args:?} still running after {BOUND:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("output")
}

#[test]
fn check_and_simulate_refuse_every_hostile_file_quickly() {
    let files = fixtures();
    assert!(files.len() >= 6, "{files:?}");
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        let field = text
            .lines()
            .find_map(|l| l.strip_prefix("# expect:"))
            .and_then(|l| l.split('|').next())
            .map(str::trim)
            .expect("an expect line");
        let path = file.to_str().unwrap();
        for args in [vec!["check", path], vec!["simulate", "--scenario", path]] {
            let out = within_bound(&args);
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
            assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
            assert!(err.starts_with("error: ") && err.contains(&format!(": {field}: ")), "{args:?}: {err}");
        }
    }
}

/// Issue 23: a scenario named with an escape sequence that clears the
/// screen and a newline that fakes an `error:` line. Every command that
/// prints the name prints it with its control characters escaped.
#[test]
fn a_name_with_control_characters_is_printed_escaped() {
    let small = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/scenarios/small.toml"))
        .expect("the small scenario");
    let hostile = small.replacen("name = \"small\"", "name = \"\\u001b[2J\\nerror: fake\"", 1);
    assert_ne!(hostile, small, "the name line was replaced");
    let dir = std::env::temp_dir().join(format!("gs-e2e-names-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("hostile-name.toml");
    std::fs::write(&file, hostile).unwrap();
    let (path, out) = (file.to_str().unwrap(), dir.join("out"));
    let experiment = ["experiment", "--scenario", path, "--robots", "1", "--runs", "1", "--algorithms", "repulsive"];
    let cases: [Vec<&str>; 3] = [
        vec!["check", path],
        vec!["simulate", "--scenario", path],
        [&experiment[..], &["--out", out.to_str().unwrap()]].concat(),
    ];
    let outputs: Vec<(Vec<&str>, Output)> = cases.into_iter().map(|args| (args.clone(), within_bound(&args))).collect();
    std::fs::remove_dir_all(&dir).unwrap();
    for (args, o) in outputs {
        let all = format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
        assert!(o.status.success(), "{args:?}: {all}");
        assert!(!all.contains('\u{1b}'), "{args:?} printed a raw escape: {all:?}");
        assert!(!all.lines().any(|l| l.starts_with("error: fake")), "{args:?} printed a fake error line: {all}");
        assert!(all.contains("\\u{1b}[2J\\nerror: fake"), "{args:?} does not show the name escaped: {all}");
    }
}

/// Issue 23: what `--scenario` may name. A device would be read until
/// memory runs out and a FIFO would block forever; a file over 1 MB and a
/// point of three elements are refused too. Each ends within the bound,
/// exit 1, one `error:` line saying why.
#[test]
fn devices_fifos_big_files_and_long_points_are_refused_quickly() {
    let dir = std::env::temp_dir().join(format!("gs-e2e-inputs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("fifo.toml");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0, "mkfifo");
    let big = dir.join("big.toml");
    std::fs::write(&big, "#".repeat(1 << 20) + "\n").unwrap();
    let point = dir.join("point.toml");
    std::fs::write(&point, "targets = [[10, 0, \"x\"]]\n[area]\npolygon = [[0, 0], [20, 0], [20, 10], [0, 10]]\n")
        .unwrap();
    let cases = [
        ("/dev/zero".to_string(), "a character device, not a regular file"),
        (fifo.to_str().unwrap().to_string(), "a FIFO, not a regular file"),
        (big.to_str().unwrap().to_string(), "1048577 bytes, above the limit MAX_FILE_BYTES = 1048576 bytes (1 MB)"),
        (
            point.to_str().unwrap().to_string(),
            "targets[0]: invalid length 3, expected a point [x, y] of exactly two numbers",
        ),
    ];
    let mut outputs = Vec::new();
    for (path, why) in &cases {
        for args in [vec!["check", path.as_str()], vec!["simulate", "--scenario", path.as_str()]] {
            outputs.push((args.join(" "), *why, within_bound(&args)));
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
    for (args, why, out) in outputs {
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args}: {err}");
        assert_eq!(err.lines().count(), 1, "{args}: {err}");
        assert!(err.starts_with("error: ") && err.contains(why), "{args}: {err}");
    }
}

/// Issue 23: a scenario file's own text in an error (an unknown key, here
/// holding a screen-clearing escape) is printed escaped too.
#[test]
fn an_error_quoting_the_file_prints_its_control_characters_escaped() {
    let dir = std::env::temp_dir().join(format!("gs-e2e-keys-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("key.toml");
    std::fs::write(&file, "\"a\\u001b[2Jb\" = 1\n[area]\npolygon = [[0, 0], [20, 0], [20, 10], [0, 10]]\n").unwrap();
    let out = within_bound(&["check", file.to_str().unwrap()]);
    std::fs::remove_dir_all(&dir).unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(!err.contains('\u{1b}'), "a raw escape: {err:?}");
    assert!(err.contains("unknown field `a\\u{1b}[2Jb`"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
}
