//! The pictures and files the commands leave, from the real binary: every
//! file a command writes is named in its output, the route map marks a
//! crashed robot apart from one that searched to the end and says the
//! run's faults and radio, and a `--maps` report shows its maps.

use std::collections::BTreeSet;
use std::fs;
use std::path::Path;

mod common;
use common::{assert_ok, gridswarm, scratch, text};

const KINDS: [&str; 7] = [".csv", ".svg", ".html", ".txt", ".json", ".jsonl", ".toml"];

/// Every file under `dir`, relative to it, but the hidden marker by which
/// gridswarm knows a folder as its own (`staging.rs`), which is no output.
fn files(dir: &Path) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for e in fs::read_dir(dir).unwrap() {
        let e = e.unwrap();
        let name = e.file_name().to_string_lossy().into_owned();
        if name == ".gridswarm-output" {
            continue;
        }
        if e.file_type().unwrap().is_dir() {
            out.extend(files(&e.path()).into_iter().map(|f| format!("{name}/{f}")));
        } else {
            out.insert(name);
        }
    }
    out
}

/// The file names a command's output mentions: words ending in a known
/// kind, relative to `dir` when a path.
fn listed(out: &str, dir: &Path) -> BTreeSet<String> {
    let prefix = format!("{}/", dir.display());
    out.split(|c: char| c.is_whitespace() || c == ',')
        .filter(|w| KINDS.iter().any(|k| w.ends_with(k)))
        .map(|w| w.strip_prefix(&prefix).unwrap_or(w).to_string())
        .collect()
}

#[test]
fn every_file_a_command_writes_is_listed() {
    let d = scratch("listed");
    let commands: [&[&str]; 8] = [
        &["simulate", "--robots", "3", "--kill", "1@2"],
        &["experiment", "--runs", "2", "--robots", "1-2"],
        &["experiment", "--scenario", "random:1", "--maps", "2", "--runs", "2", "--robots", "1-2"],
        &["experiment", "--grids"],
        &["experiment", "failures", "--runs", "2", "--killed", "0-1", "--robots", "3"],
        &["experiment", "radio", "--runs", "2", "--loss", "0,0.1", "--robots", "2,3", "--retries", "0,1"],
        &["experiment", "readings", "--robots", "1-2", "--runs", "2", "--seeds", "1"],
        &["experiment", "scale", "--robots", "2", "--runs", "1"],
    ];
    for (k, args) in commands.iter().enumerate() {
        let out = d.join(format!("out-{k}"));
        let mut all: Vec<&str> = args.to_vec();
        all.extend(["--out", out.to_str().unwrap()]);
        let o = gridswarm(&all);
        assert_ok(&o);
        let said = listed(&text(&o.stdout), &out);
        assert_eq!(said, files(&out), "gridswarm {}:\n{}", args.join(" "), text(&o.stdout));
    }
}

#[test]
fn route_map_marks_fates_and_says_the_conditions() {
    let d = scratch("routes");
    let run = d.join("run");
    let o = gridswarm(&[
        "simulate",
        "--robots",
        "4",
        "--seed",
        "2",
        "--kill",
        "1@3",
        "--freeze",
        "2@4",
        "--loss",
        "0.1",
        "--retries",
        "1",
        "--out",
        run.to_str().unwrap(),
    ]);
    assert_ok(&o);
    let svg = fs::read_to_string(run.join("routes.svg")).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let end = |r: &str| {
        doc.descendants()
            .find(|n| {
                n.attribute("data-robot") == Some(r) && n.attribute("class").is_some_and(|c| c.starts_with("end "))
            })
            .and_then(|n| n.attribute("class"))
            .unwrap_or_else(|| panic!("robot {r} has no end mark"))
    };
    assert_eq!(end("0"), "end running");
    assert_eq!(end("1"), "end crashed");
    assert_eq!(end("2"), "end frozen");
    let settings = doc.descendants().find(|n| n.attribute("id") == Some("settings")).unwrap().text().unwrap();
    for part in ["--kill 1@3", "--freeze 2@4", "loss 0.1", "retries 1"] {
        assert!(settings.contains(part), "{part} missing from {settings}");
    }
}

#[test]
fn a_maps_report_shows_each_map() {
    let d = scratch("maps");
    let out = d.join("out");
    assert_ok(&gridswarm(&[
        "experiment",
        "--scenario",
        "random:5",
        "--maps",
        "3",
        "--runs",
        "2",
        "--robots",
        "1-2",
        "--out",
        out.to_str().unwrap(),
    ]));
    let html = fs::read_to_string(out.join("report.html")).unwrap();
    for k in 0..3 {
        let name = format!("random:{}", 5 + k);
        let thumb = html
            .find(&format!("<svg id=\"map-{k}\""))
            .unwrap_or_else(|| panic!("no thumbnail of map {k} in report.html"));
        assert!(html[thumb..].find("</svg>").is_some_and(|e| html[thumb..thumb + e].contains("<polygon")), "map {k}");
        assert!(html.contains(&name), "{name} not named");
    }
}
