//! `--mcap` and `--live`: the file read back with the `mcap` crate's reader,
//! message by message and channel by channel, and the live server read by
//! a plain WebSocket client speaking Foxglove's protocol.

mod common;

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};

use common::{gridswarm, scratch, text};
use foxglove::messages::PosesInFrame;
use foxglove::Decode;
use gridswarm_orchestrator::mcap::{topics, Topics};
use serde_json::Value;

const ROBOTS: usize = 5;

fn read(path: &std::path::Path) -> Topics {
    topics(&std::fs::read(path).unwrap()).expect("an MCAP file")
}

#[test]
fn the_mcap_file_holds_every_channel_with_the_runs_counts() {
    let dir = scratch("file");
    let file = dir.join("run.mcap");
    let robots = ROBOTS.to_string();
    let args = ["simulate", "--robots", &robots, "--seed", "3", "--kill", "1@3", "--loss", "0.2", "--json"];
    let o = gridswarm(&[&args[..], &["--mcap", file.to_str().unwrap()]].concat());
    // The search may end incomplete (exit 3) with a robot crashed, or
    // collide under loss (4); it must run.
    assert!(matches!(o.status.code(), Some(0 | 3 | 4)), "{}", text(&o.stderr));
    let summary: Value = serde_json::from_slice(&o.stdout).unwrap();
    let rounds = summary["rounds"].as_u64().unwrap() as usize;
    // Watching changes nothing: the same run without the file (but for the
    // provenance, which records the command line and the times).
    let plain = gridswarm(&args);
    let mut plain: Value = serde_json::from_slice(&plain.stdout).unwrap();
    let mut watched = summary.clone();
    for v in [&mut plain, &mut watched] {
        v.as_object_mut().unwrap().remove("provenance").expect("a provenance");
    }
    assert_eq!(plain, watched);

    let topics = read(&file);
    let count = |t: &str| topics.get(t).map_or(0, Vec::len);
    for t in ["/robots", "/targets", "/radio", "/faults", "/collisions", "/log"] {
        assert!(count(t) > 0, "no message on {t}: {:?}", topics.keys().collect::<Vec<_>>());
    }
    for k in 0..ROBOTS {
        assert!(count(&format!("/maps/robot_{k}")) > 0, "robot {k}'s map never logged");
    }
    // One pose set at time 0 and one as every slot closes, each with every robot.
    assert_eq!(count("/robots"), rounds + 1);
    for (_, data) in &topics["/robots"] {
        assert_eq!(PosesInFrame::decode(&data[..]).unwrap().poses.len(), ROBOTS);
    }
    // The referee's count of every slot.
    assert_eq!(count("/collisions"), rounds);
    let faults: Vec<Value> = topics["/faults"].iter().map(|(_, d)| serde_json::from_slice(d).unwrap()).collect();
    assert_eq!(faults.len(), 1);
    assert_eq!((faults[0]["robot"].as_u64(), faults[0]["kind"].as_str()), (Some(1), Some("crash")));
    let frames: Vec<Value> = topics["/radio"].iter().map(|(_, d)| serde_json::from_slice(d).unwrap()).collect();
    assert!(frames.iter().any(|f| f["lost"].as_array().is_some_and(|l| !l.is_empty())), "loss 0.2 lost nothing");
    assert!(frames.iter().any(|f| f["kind"] == "map") && frames.iter().any(|f| f["kind"] == "choice"));
    // Frames sent are the protocol's count (retries are copies of one frame).
    assert_eq!(frames.len() as u64, summary["frames"].as_u64().unwrap());
    // Simulated time: the last poses are stamped with the last slot's end.
    let last = topics["/robots"].last().unwrap().0 as f64 / 1e9;
    let end = summary["search_time_s"].as_f64().unwrap();
    assert!(last >= end - 1e-6, "poses end at {last} s, the search at {end} s");
    if summary["targets_found"].as_u64().unwrap() > 0 {
        assert!(count("/targets") >= 2, "targets were found but never shown found");
    }
}

#[test]
fn bad_view_flags_are_usage_errors() {
    for (args, says) in [
        (&["simulate", "--live", "127.0.0.1:0", "--speed", "fast"][..], "invalid speed `fast`"),
        (&["simulate", "--live", "127.0.0.1:0", "--speed", "0x"][..], "invalid speed `0x`"),
        (&["simulate", "--speed", "10x"][..], "--live"),
        (&["simulate", "--live", "localhost"][..], "invalid --live address `localhost`"),
        (&["simulate", "--algorithm", "lfp", "--mcap", "x.mcap"][..], "lfp has no radio"),
    ] {
        let o = gridswarm(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", text(&o.stderr));
        assert!(text(&o.stderr).contains(says), "{args:?}: {}", text(&o.stderr));
    }
}

/// Kills the run if the test fails half-way.
struct Reaped(Child);

impl Drop for Reaped {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[test]
fn a_websocket_client_of_the_live_view_receives_poses() {
    let child = Command::new(env!("CARGO_BIN_EXE_gridswarm"))
        .args(["simulate", "--robots", "3", "--seed", "2", "--live", "127.0.0.1:0", "--speed", "50x"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut run = Reaped(child);
    let mut lines = BufReader::new(run.0.stderr.take().unwrap()).lines();
    let url = loop {
        let line = lines.next().expect("the address is printed").unwrap();
        if let Some(rest) = line.strip_prefix("live view at ") {
            break rest.split(':').take(3).collect::<Vec<_>>().join(":");
        }
    };
    let mut req = tungstenite::client::IntoClientRequest::into_client_request(url.as_str()).unwrap();
    req.headers_mut().insert("Sec-WebSocket-Protocol", "foxglove.sdk.v1".parse().unwrap());
    let (mut ws, _) = tungstenite::connect(req).expect("the live server accepts");
    let poses = loop {
        match ws.read().expect("the server keeps talking") {
            tungstenite::Message::Text(t) => {
                let v: Value = serde_json::from_str(&t).unwrap();
                if v["op"] != "advertise" {
                    continue;
                }
                let chans = v["channels"].as_array().unwrap();
                let Some(c) = chans.iter().find(|c| c["topic"] == "/robots") else { continue };
                let sub = serde_json::json!({"op": "subscribe", "subscriptions": [{"id": 7, "channelId": c["id"]}]});
                ws.send(tungstenite::Message::text(sub.to_string())).unwrap();
            }
            // Message data: opcode 1, subscription id, log time, payload.
            tungstenite::Message::Binary(b) if b[0] == 1 => {
                assert_eq!(u32::from_le_bytes(b[1..5].try_into().unwrap()), 7);
                break PosesInFrame::decode(&b[13..]).unwrap();
            }
            _ => {}
        }
    };
    assert_eq!(poses.poses.len(), 3);
    drop(ws);
    let status = run.0.wait().unwrap();
    assert!(matches!(status.code(), Some(0 | 3 | 4)), "{status:?}");
}
