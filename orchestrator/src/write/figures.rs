//! A run's protocol figures (how it ended, moves, radio traffic, failure
//! detection) as `summary.json` and the terminal show them, whichever
//! engine ran it: both report the world's [`ProtocolStats`].

use gridswarm::outcome::RunResult;
use gridswarm::sim::{FailureRecord, ProtocolStats};
use serde_json::{json, Value};

/// The `ended_by` labels, as the terminal says them.
pub fn ended_by_phrase(ended_by: &str) -> &'static str {
    match ended_by {
        "stop" => "a robot's stop ended the search",
        "exhausted" => "a robot found nothing left to visit with targets unfound",
        "false_stop" => "a robot's stop ended the search early (a protocol fault)",
        "cut_off" => "every live robot halted, cut off behind failed robots",
        "no_robots" => "no robot was left searching",
        "max_rounds" => "round limit reached",
        "past_bound" => "the run went past a stated bound and stalled",
        _ => "unknown end",
    }
}

/// How a run ended, as the terminal says it: [`ended_by_phrase`], and for
/// a run past a stated bound which bound and which robots
/// (`ProtocolStats::past_bound`), so that no such run ends silently.
pub fn ended_text(p: &ProtocolStats) -> String {
    let phrase = ended_by_phrase(&p.ended_by);
    match (&p.past_bound, p.ended_by.as_str()) {
        (Some(why), "past_bound") => why.clone(),
        (Some(why), _) => format!("{phrase}; past a stated bound: {why}"),
        (None, _) => phrase.to_string(),
    }
}

/// The conditions a run ran under, from its `summary.json`: the injected
/// faults as their options read, and the radio's loss, delay, duplication
/// and retries. Heads routes.svg and the replay's side bar, so that a
/// picture alone says what it shows.
pub fn settings_line(summary: &Value) -> String {
    let faults = faults_given(summary);
    let faults = if faults.is_empty() { "none".to_string() } else { faults.join(", ") };
    format!("faults: {faults}; radio: {}", radio_text(summary))
}

/// The faults injected, as their options read (`--kill 2@20`).
pub fn faults_given(summary: &Value) -> Vec<String> {
    let list = summary.get("faults").and_then(Value::as_array).map(Vec::as_slice).unwrap_or_default();
    list.iter().filter_map(Value::as_str).map(str::to_string).collect()
}

/// The radio's settings: loss, delay, jitter, duplication, retries.
pub fn radio_text(summary: &Value) -> String {
    let num = |v: Option<&Value>| v.map(|v| v.to_string()).unwrap_or_else(|| "?".into());
    let radio = match summary.get("radio") {
        Some(r) if r.is_object() => format!(
            "loss {}, delay {} ms (jitter {} ms), duplication {}",
            num(r.get("loss")),
            num(r.get("delay")),
            num(r.get("jitter")),
            num(r.get("dup"))
        ),
        _ => "not recorded".into(),
    };
    let retries = summary.get("retries").or_else(|| summary.get("params").and_then(|p| p.get("retries")));
    format!("{radio}, retries {}", num(retries))
}

/// One injected failure as `summary.json` lists it.
pub fn failure_value(f: &FailureRecord) -> Value {
    json!({
        "robot": f.robot,
        "kind": f.kind,
        "round": f.round,
        "at_s": f.at_s,
        "thawed_s": f.thawed_s,
        "detected_round": f.detected_round,
        "detected_s": f.detected_s,
        "detection_delay_rounds": f.delay_rounds(),
        "detection_delay_s": f.delay_s(),
        "declared_by": f.declared_by,
        "unaware": f.unaware,
    })
}

/// The protocol's fields of `summary.json`, top-level keys.
pub fn summary_fields(result: &RunResult) -> Value {
    let p: &ProtocolStats = &result.protocol;
    let mut v = json!({
        "ended_by": p.ended_by,
        "stop_round": p.stop_round,
        "stop_s": p.stop_s,
        "moves": p.moves,
        "collisions_per_million_moves": p.collisions_per_million_moves(result.collisions),
        "refused_moves": p.refused,
        "frames": p.frames,
        "transmissions": p.transmissions,
        "retransmissions": p.retransmissions,
        "deliveries": p.deliveries,
        "lost": p.lost,
        "duplicated": p.duplicated,
        "wakes": p.wakes,
        "declarations": p.declarations,
        "false_suspicions": p.false_suspicions,
        "rejoins": p.rejoins,
        "timeouts": p.timeouts,
        "unsure": p.unsure,
        "forced_slots": p.forced_slots,
        "late_motors": p.late_motors,
        "failures": p.failures.iter().map(failure_value).collect::<Vec<_>>(),
    });
    // Only a run past a stated bound has it: every other summary is unchanged.
    if let Some(why) = &p.past_bound {
        v["past_bound"] = json!(why);
    }
    v
}

/// One line per injected failure: when, and how long until it was declared.
pub fn failure_lines(result: &RunResult) -> String {
    let mut s = String::new();
    for f in &result.protocol.failures {
        let thaw = f.thawed_s.map(|t| format!(", thawed at {t:.3} s")).unwrap_or_default();
        let found = match (f.delay_rounds(), f.delay_s()) {
            (Some(r), Some(d)) => format!(
                "declared after {r} rounds ({d:.3} s simulated) by robots {}",
                f.declared_by.iter().map(|r| r.to_string()).collect::<Vec<_>>().join(",")
            ),
            _ => "never declared".to_string(),
        };
        s += &format!("failure: robot {} {} in round {} at {:.3} s{thaw}: {found}\n", f.robot, f.kind, f.round, f.at_s);
    }
    s
}

/// The traffic and detection counts on one line, for runs with a protocol.
pub fn protocol_line(result: &RunResult) -> String {
    let p = &result.protocol;
    format!(
        "moves {} ({:.1} collisions per 10^6 moves); frames {}, transmissions {} ({} retransmissions), lost {}; \
         declarations {} ({} false), rejoins {}, time-outs {}, unsure stays {}, forced slots {}\n",
        p.moves,
        p.collisions_per_million_moves(result.collisions),
        p.frames,
        p.transmissions,
        p.retransmissions,
        p.lost,
        p.declarations,
        p.false_suspicions,
        p.rejoins,
        p.timeouts,
        p.unsure,
        p.forced_slots
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failures_name_their_delay() {
        let mut r: RunResult = serde_json::from_value(json!({
            "algorithm": "repulsive", "robots": 3, "seed": 1, "situation": 1, "rounds": 9,
            "search_time_s": 50.0, "targets_found": 1, "targets_total": 1, "collisions": 1,
            "coverage": null, "complete": true, "robot_rounds": 20
        }))
        .unwrap();
        r.protocol.moves = 500_000;
        r.protocol.ended_by = "stop".into();
        r.protocol.failures.push(FailureRecord {
            robot: 2,
            kind: "crash".into(),
            round: 3,
            at_s: 12.5,
            detected_round: Some(5),
            detected_s: Some(20.0),
            declared_by: vec![0, 1],
            ..FailureRecord::default()
        });
        let v = summary_fields(&r);
        assert_eq!(v["collisions_per_million_moves"], 2.0);
        assert_eq!(v["failures"][0]["detection_delay_rounds"], 2);
        assert_eq!(v["failures"][0]["detection_delay_s"], 7.5);
        let line = failure_lines(&r);
        let mut summary = json!({ "faults": ["--kill 2@3"], "radio": { "loss": 0.1, "delay": 5, "jitter": 2, "dup": 0.0 }, "retries": 2 });
        assert_eq!(
            settings_line(&summary),
            "faults: --kill 2@3; radio: loss 0.1, delay 5 ms (jitter 2 ms), duplication 0.0, retries 2"
        );
        summary["faults"] = json!([]);
        assert!(settings_line(&summary).starts_with("faults: none; "));
        assert!(line.contains("robot 2 crash in round 3") && line.contains("after 2 rounds (7.500 s"), "{line}");
        assert_eq!(ended_by_phrase("max_rounds"), "round limit reached");
        assert_eq!(ended_text(&r.protocol), "a robot's stop ended the search");
        assert!(v.get("past_bound").is_none());
        r.protocol.ended_by = "past_bound".into();
        r.protocol.past_bound = Some("no robot moved for 50 rounds, robot 0 slow by 4 s".into());
        assert_eq!(ended_text(&r.protocol), "no robot moved for 50 rounds, robot 0 slow by 4 s");
        assert_eq!(summary_fields(&r)["past_bound"], "no robot moved for 50 rounds, robot 0 slow by 4 s");
        r.protocol.ended_by = "max_rounds".into();
        assert!(ended_text(&r.protocol).starts_with("round limit reached; past a stated bound: no robot"));
    }
}
