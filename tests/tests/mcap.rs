//! `gridswarm run --mcap` against `simulate --mcap`: the world-server's
//! tape, followed by the orchestrator, gives the very messages the
//! in-process world gives, channel by channel, with a fault and loss.

use std::path::Path;

use gridswarm_e2e::{finished, gridswarm, serial};
use gridswarm_orchestrator::mcap::{topics, Topics};

fn read(path: &Path) -> Topics {
    topics(&std::fs::read(path).unwrap()).expect("an MCAP file")
}

#[test]
fn run_writes_the_same_mcap_as_simulate() {
    let _one = serial();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mcap_run");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let args = ["--robots", "4", "--seed", "5", "--kill", "2@2", "--loss", "0.15", "--json"];
    let mut files = Vec::new();
    for cmd in ["simulate", "run"] {
        let file = dir.join(format!("{cmd}.mcap"));
        let all = [&[cmd][..], &args, &["--mcap", file.to_str().unwrap()]].concat();
        let out = gridswarm().args(&all).output().unwrap();
        finished(&out, &all);
        files.push(read(&file));
    }
    let (sim, run) = (&files[0], &files[1]);
    assert_eq!(sim.keys().collect::<Vec<_>>(), run.keys().collect::<Vec<_>>());
    for (topic, msgs) in sim {
        assert!(!msgs.is_empty(), "{topic}");
        assert_eq!(msgs.len(), run[topic].len(), "{topic}: message counts differ");
        assert!(msgs == &run[topic], "{topic}: the messages differ");
    }
}
