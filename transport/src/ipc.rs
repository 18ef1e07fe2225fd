//! What the distributed engine's three programs share over iceoryx2:
//! `world-server`, `robot-agent` and the orchestrator's `gridswarm run`.
//!
//! - the iceoryx2 [`Config`] of a run, built in code from the run's prefix
//!   (never from a file: iceoryx2's global config silently reads
//!   `config/iceoryx2.toml`, `~/.config/iceoryx2/` and `/etc/iceoryx2/`);
//! - the service and node names, and the limits every service is created with;
//! - liveness of a node or a process;
//! - the run's own iceoryx2 root folder and node counter file, out of other
//!   users' reach ([`private`]);
//! - [`cleanup_run`], which removes every file of a run from `/dev/shm` and
//!   iceoryx2's root directory, and [`sweep_stale`] for runs whose owner died
//!   ([`files`]);
//!
//! Topology (one run, `N` robots; the world creates every service):
//!
//! | service | kind | writer | reader |
//! |---|---|---|---|
//! | `gridswarm/robot/<i>/in` | publish-subscribe `[u8]` | world | robot `i` |
//! | `gridswarm/robots/<g>/out` | publish-subscribe `[u8]`, user header = robot | robots `32g..32g+31` | world |
//! | `gridswarm/robots/wake` | event, one listener a robot, named `robot-<i>` | world (one listener at a time) | every robot |
//! | `gridswarm/world/wake` | event, id = the robot's outbox group | every robot | world |
//!
//! Only the inbox is a service per robot: a service costs the world three
//! descriptors (static config, dynamic config, port tag) on top of a
//! connection's own, so the outboxes are shared by groups ([`outbox`]) and
//! the wake-ups by all ([`wake`]). The world holds 9 descriptors a robot
//! ([`crate::nofile`]).
//!
//! Payloads are chunks ([`gridswarm_robot::wire::chunks`]) of postcard bytes of
//! [`gridswarm_robot::wire::ToWorld`] (out) and [`gridswarm_robot::wire::ToAgent`] (in). The
//! world is the radio medium: it carries a robot's frames, as opaque bytes,
//! to the robots in range at their simulated arrival times.

use std::fs;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU32, Ordering};

use iceoryx2::config::Config;
use iceoryx2::node::NodeView;
use iceoryx2::prelude::*;

pub mod files;
pub mod outbox;
pub mod private;
pub mod wake;

pub use files::{cleanup_run, is_own_folder, run_files, sweep_stale};
pub use private::{describe_uid, run_root};

/// Every prefix of a run starts with this, followed by the owner's pid.
pub const PREFIX_HEAD: &str = "gs";

/// Bytes of one sample (a chunk of a message, header included).
pub const CHUNK_BYTES: usize = 16 * 1024;
/// Chunks a robot's inbox holds: one wake-up at a time, up to this many
/// chunks (2 MiB). A bigger wake-up is an error, never a silent drop.
pub const INBOX_CHUNKS: usize = 128;
/// Chunks a robot's outbox holds (its hello and one answer at a time).
pub const OUTBOX_CHUNKS: usize = 64;

/// Robots are numbered below this.
pub const MAX_ROBOTS: usize = 4096;

/// Exit status of a robot-agent whose world-server vanished.
pub const EXIT_WORLD_GONE: i32 = 3;

/// A fresh prefix for a run owned by this process: `gs<pid>x<nonce>_`.
pub fn new_prefix() -> String {
    static COUNTER: AtomicU32 = AtomicU32::new(0);
    let nanos =
        std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map(|d| d.subsec_nanos()).unwrap_or(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let nonce = gridswarm_robot::rng::mix(((nanos as u64) << 20) ^ n as u64) & 0xff_ffff;
    format!("{PREFIX_HEAD}{}x{nonce:06x}_", std::process::id())
}

/// Whether `prefix` has the shape [`new_prefix`] makes (so it is safe to
/// remove files by it), and the pid of the process that owns it.
pub fn prefix_owner(prefix: &str) -> Option<u32> {
    let rest = prefix.strip_prefix(PREFIX_HEAD)?;
    let (pid, rest) = rest.split_once('x')?;
    let nonce = rest.strip_suffix('_')?;
    if pid.is_empty() || !pid.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    if nonce.is_empty() || !nonce.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    pid.parse().ok()
}

/// The iceoryx2 configuration of the run with this prefix, built in code.
pub fn config(prefix: &str) -> Result<Config, String> {
    if prefix_owner(prefix).is_none() {
        return Err(format!("`{prefix}` is not a run prefix (expected gs<pid>x<hex>_)"));
    }
    let mut c = Config::default();
    c.global.prefix = FileName::new(prefix.as_bytes()).map_err(|e| format!("bad prefix `{prefix}`: {e:?}"))?;
    // Its own root, not the `/tmp/iceoryx2/` every user shares (see [`private`]).
    let root = run_root(prefix);
    let root_path = iceoryx2::prelude::Path::new(root.as_os_str().as_encoded_bytes())
        .map_err(|e| format!("iceoryx2 cannot use {} as its root folder: {e:?}", root.display()))?;
    c.global.set_root_path(&root_path);
    // Big memory win (notes: ~470 KB -> ~28 KB of heap per subscriber).
    c.defaults.publish_subscribe.subscriber_expired_connection_buffer = 2;
    // A run's prefix is fresh: there are no dead nodes to look for when a
    // node or service comes up, and scanning 200 nodes on every one of 200
    // starts is quadratic. The run removes its own files when it ends.
    c.global.node.cleanup_dead_nodes_on_creation = false;
    c.global.node.cleanup_dead_nodes_on_destruction = false;
    c.global.service.cleanup_dead_nodes_on_open = false;
    Ok(c)
}

/// iceoryx2's root directory for `config` (the run's [`run_root`]).
pub fn root_dir(config: &Config) -> PathBuf {
    PathBuf::from(config.global.root_path().to_string())
}

/// iceoryx2's log through the run's logger: errors only, unless
/// `IOX2_LOG_LEVEL` says otherwise, and failed notifications counted
/// ([`wake::install_logger`]).
pub fn quiet_logs() {
    wake::install_logger();
}

/// Service and node names.
pub mod names {
    pub const WORLD_NODE: &str = "world";

    pub fn robot_node(i: usize) -> String {
        format!("robot-{i}")
    }

    /// The robot number of a robot node's name.
    pub fn robot_of_node(name: &str) -> Option<usize> {
        name.strip_prefix("robot-")?.parse().ok()
    }

    pub fn world_wake() -> String {
        "gridswarm/world/wake".into()
    }

    /// The outbox of robots `g * OUTBOX_GROUP ..` (see [`super::outbox`]).
    pub fn group_out(g: usize) -> String {
        format!("gridswarm/robots/{g}/out")
    }

    pub fn robot_in(i: usize) -> String {
        format!("gridswarm/robot/{i}/in")
    }

    /// Every robot's wake-up, one listener a robot (see [`super::wake`]).
    pub fn robots_wake() -> String {
        "gridswarm/robots/wake".into()
    }
}

pub fn service_name(name: &str) -> Result<ServiceName, String> {
    ServiceName::new(name).map_err(|e| format!("bad service name `{name}`: {e:?}"))
}

pub fn node_name(name: &str) -> Result<NodeName, String> {
    NodeName::new(name).map_err(|e| format!("bad node name `{name}`: {e:?}"))
}

/// The iceoryx2 service flavour every process of a run uses.
pub type Svc = iceoryx2::prelude::ipc::Service;
pub type BytesService = iceoryx2::service::port_factory::publish_subscribe::PortFactory<Svc, [u8], ()>;
pub type EventService = iceoryx2::service::port_factory::event::PortFactory<Svc>;
pub type BytesPublisher = iceoryx2::port::publisher::Publisher<Svc, [u8], ()>;
pub type BytesSubscriber = iceoryx2::port::subscriber::Subscriber<Svc, [u8], ()>;
pub type Notifier = iceoryx2::port::notifier::Notifier<Svc>;
pub type Listener = iceoryx2::port::listener::Listener<Svc>;

/// A node of the run named `name`, once the run's root folder and node
/// counter are known to be this user's alone ([`private`]). Signal
/// handling is left to the process (iceoryx2 would otherwise catch
/// SIGINT/SIGTERM for its own waits).
pub fn create_node(config: &Config, name: &str) -> Result<Node<Svc>, String> {
    let prefix = config.global.prefix.to_string();
    let root = root_dir(config);
    private::prepare_root(&root)?;
    private::guard_node_counter(&prefix)?;
    let node = NodeBuilder::new()
        .name(&node_name(name)?)
        .config(config)
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<Svc>()
        .map_err(|e| format!("cannot create node `{name}` (iceoryx2's root folder {}): {e:?}", root.display()))?;
    // A counter still at 0 means iceoryx2 counted in a file of its own
    // making, world-writable: its name or layout changed with iceoryx2.
    if private::nodes_counted(&prefix)? == 0 {
        return Err(format!(
            "iceoryx2 did not use the node counter {} gridswarm made private; does this iceoryx2 name it differently?",
            private::node_counter_path(&prefix).display()
        ));
    }
    Ok(node)
}

/// Creates a byte-slice publish-subscribe service with one publisher and
/// one subscriber whose buffer holds `buffer` samples.
pub fn create_bytes(node: &Node<Svc>, name: &str, buffer: usize) -> Result<BytesService, String> {
    node.service_builder(&service_name(name)?)
        .publish_subscribe::<[u8]>()
        .max_publishers(1)
        .max_subscribers(1)
        .max_nodes(4)
        .history_size(0)
        .subscriber_max_buffer_size(buffer)
        .subscriber_max_borrowed_samples(2)
        // A full buffer would drop the oldest message; buffers are sized so
        // that never happens, and so that a frozen reader can never block
        // the writer.
        .enable_safe_overflow(true)
        .create()
        .map_err(|e| format!("cannot create service `{name}`: {e:?}"))
}

/// Opens a service [`create_bytes`] made, checking it has room for a
/// subscriber buffer of `buffer` samples.
pub fn open_bytes(node: &Node<Svc>, name: &str, buffer: usize) -> Result<BytesService, String> {
    node.service_builder(&service_name(name)?)
        .publish_subscribe::<[u8]>()
        .subscriber_max_buffer_size(buffer)
        .open()
        .map_err(|e| format!("cannot open service `{name}`: {e:?}"))
}

/// Creates an event service with room for `notifiers` notifiers, one
/// listener, and event ids up to `max_id`.
pub fn create_event(node: &Node<Svc>, name: &str, notifiers: usize, max_id: usize) -> Result<EventService, String> {
    node.service_builder(&service_name(name)?)
        .event()
        .max_notifiers(notifiers)
        .max_listeners(1)
        .max_nodes(notifiers + 3)
        .event_id_max_value(max_id)
        .create()
        .map_err(|e| format!("cannot create event service `{name}`: {e:?}"))
}

pub fn open_event(node: &Node<Svc>, name: &str) -> Result<EventService, String> {
    node.service_builder(&service_name(name)?)
        .event()
        .open()
        .map_err(|e| format!("cannot open event service `{name}`: {e:?}"))
}

/// A publisher for postcard bytes of at most `max_len` bytes (see
/// [`max_message_len`]). Free samples are reused last-in first-out, so only
/// the pages of the few samples in flight at once are ever touched.
pub fn bytes_publisher(service: &BytesService, max_len: usize) -> Result<BytesPublisher, String> {
    service
        .publisher_builder()
        .initial_max_slice_len(max_len)
        .allocation_strategy(AllocationStrategy::Static)
        .create()
        .map_err(|e| format!("cannot create publisher: {e:?}"))
}

pub fn bytes_subscriber(service: &BytesService, buffer: usize) -> Result<BytesSubscriber, String> {
    service.subscriber_builder().buffer_size(buffer).create().map_err(|e| format!("cannot create subscriber: {e:?}"))
}

/// Publishes one message.
pub fn publish(publisher: &BytesPublisher, bytes: &[u8]) -> Result<(), String> {
    let sample = publisher.loan_slice_uninit(bytes.len()).map_err(|e| format!("cannot loan a sample: {e:?}"))?;
    sample.write_from_slice(bytes).send().map_err(|e| format!("cannot send: {e:?}"))?;
    Ok(())
}

/// Takes the next message, if any, into `buf`.
pub fn receive(subscriber: &BytesSubscriber, buf: &mut Vec<u8>) -> Result<bool, String> {
    match subscriber.receive().map_err(|e| format!("cannot receive: {e:?}"))? {
        Some(sample) => {
            buf.clear();
            buf.extend_from_slice(sample.payload());
            Ok(true)
        }
        None => Ok(false),
    }
}

/// A node of the run, as [`list_nodes`] sees it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NodeInfo {
    pub name: String,
    pub pid: Option<u32>,
    /// The node's process is gone (its monitor says so).
    pub dead: bool,
}

/// Every node of the run `config` belongs to, alive or dead.
pub fn list_nodes(config: &Config) -> Result<Vec<NodeInfo>, String> {
    let mut out = Vec::new();
    Node::<ipc::Service>::list(config, |state| {
        let (details, dead) = match &state {
            NodeState::Alive(v) => (v.details().clone(), false),
            NodeState::Dead(v) => (v.details().clone(), true),
            _ => (None, false),
        };
        if let Some(d) = details {
            out.push(NodeInfo { name: d.name().to_string(), pid: Some(d.process_id().value() as u32), dead });
        }
        CallbackProgression::Continue
    })
    .map_err(|e| format!("cannot list nodes: {e:?}"))?;
    Ok(out)
}

/// Whether process `pid` is running: it exists and is not a zombie (a
/// killed child stays a zombie until its parent reaps it). Only proof of
/// death counts: no such entry (`ENOENT`/`ESRCH`) or a zombie or dead
/// state. An entry that cannot be read for any other reason (`EMFILE`
/// under a low descriptor limit, a permission) means alive.
pub fn pid_alive(pid: u32) -> bool {
    pid_liveness(pid).unwrap_or(true)
}

/// What `/proc` says about process `pid`: `Some(true)` running, `Some(false)`
/// gone or a zombie, `None` when its entry cannot be read (it cannot tell).
pub fn pid_liveness(pid: u32) -> Option<bool> {
    match fs::read_to_string(format!("/proc/{pid}/stat")) {
        Ok(stat) => Some(!stat_state(&stat).is_some_and(|c| matches!(c, 'Z' | 'X' | 'x'))),
        Err(e) if matches!(e.raw_os_error(), Some(libc::ENOENT) | Some(libc::ESRCH)) => Some(false),
        Err(_) => None,
    }
}

/// The state letter of a `/proc/PID/stat` line. It follows the command
/// name, which is in parentheses and may itself hold spaces or parentheses.
fn stat_state(stat: &str) -> Option<char> {
    let k = stat.rfind(')')?;
    stat[k + 1..].trim_start().chars().next()
}

/// Whether process `pid` is stopped (SIGSTOP), for reports and tests.
pub fn pid_stopped(pid: u32) -> bool {
    match fs::read_to_string(format!("/proc/{pid}/stat")) {
        Ok(stat) => matches!(stat_state(&stat), Some('T' | 't')),
        Err(_) => false,
    }
}

/// CPU time (user + system) process `pid` has used so far, in milliseconds.
pub fn cpu_ms_of(pid: u32) -> f64 {
    let Ok(stat) = fs::read_to_string(format!("/proc/{pid}/stat")) else {
        return 0.0;
    };
    let Some(k) = stat.rfind(')') else { return 0.0 };
    // Fields after the command: state is field 3; utime and stime are 14 and 15.
    let f: Vec<&str> = stat[k + 1..].split_whitespace().collect();
    let ticks = |i: usize| f.get(i).and_then(|v| v.parse::<f64>().ok()).unwrap_or(0.0);
    // SAFETY: sysconf has no preconditions.
    let hz = unsafe { libc::sysconf(libc::_SC_CLK_TCK) }.max(1) as f64;
    (ticks(11) + ticks(12)) * 1e3 / hz
}

/// Number of open file descriptors of this process.
pub fn open_fds() -> usize {
    fs::read_dir("/proc/self/fd").map(|d| d.count().saturating_sub(1)).unwrap_or(0)
}

/// Peak resident set size of this process, in KiB (`VmHWM`).
pub fn peak_rss_kib() -> u64 {
    status_field("/proc/self/status", "VmHWM:")
}

/// Peak resident set size of process `pid`, in KiB (0 if unknown).
pub fn peak_rss_kib_of(pid: u32) -> u64 {
    status_field(&format!("/proc/{pid}/status"), "VmHWM:")
}

/// Resident set size of this process now, in KiB (`VmRSS`).
pub fn rss_kib() -> u64 {
    status_field("/proc/self/status", "VmRSS:")
}

fn status_field(file: &str, key: &str) -> u64 {
    fs::read_to_string(file)
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with(key))
                .and_then(|l| l[key.len()..].trim().trim_end_matches("kB").trim().parse().ok())
        })
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prefixes_are_recognised() {
        let p = new_prefix();
        assert_eq!(prefix_owner(&p), Some(std::process::id()));
        assert_ne!(new_prefix(), p);
        for bad in ["", "gs", "gs12x_", "gsx12_", "gs12x12", "iox2_", "gs1x2y_", "gs12x12_/.."] {
            assert_eq!(prefix_owner(bad), None, "{bad}");
        }
        assert!(config("iox2_").is_err());
        let c = config(&p).unwrap();
        assert_eq!(c.global.prefix.to_string(), p);
    }

    /// iceoryx2 (0.10) makes its node counter world-writable; the run's is
    /// the one gridswarm made, and no file of a run is writable by others.
    #[test]
    fn a_node_leaves_no_file_another_user_can_write() {
        use std::os::unix::fs::MetadataExt;
        let prefix = format!("{PREFIX_HEAD}{}x{:06x}_", std::process::id(), 0x0de);
        let c = config(&prefix).unwrap();
        let root = root_dir(&c);
        assert_eq!(root, run_root(&prefix));
        let node = create_node(&c, "probe").unwrap();
        let _service = create_event(&node, "probe/wake", 1, 1).unwrap();
        assert_eq!(private::nodes_counted(&prefix), Ok(1));
        let files = run_files(&prefix);
        let counters: Vec<_> = files.iter().filter(|f| f.to_string_lossy().ends_with(".global_mgmt")).collect();
        assert_eq!(counters, [&private::node_counter_path(&prefix)], "iceoryx2 used the counter gridswarm made");
        assert!(files.len() > 3, "{files:?}");
        for f in &files {
            let mode = fs::metadata(f).unwrap().mode();
            assert_eq!(mode & 0o022, 0, "{} is writable by others ({mode:o})", f.display());
        }
        assert_eq!(fs::metadata(&root).unwrap().mode() & 0o777, 0o700);
        drop(_service);
        drop(node);
        assert!(cleanup_run(&prefix).unwrap() > 0);
        assert!(run_files(&prefix).is_empty());
        assert!(!root.exists(), "the run's root folder goes with its files");
    }

    #[test]
    fn process_liveness() {
        assert!(pid_alive(std::process::id()));
        assert!(!pid_alive(u32::MAX - 7));
        assert!(!pid_stopped(std::process::id()));
        assert_eq!(stat_state("12 (a) b) Z 1"), Some('Z'));
        assert_eq!(stat_state("garbage"), None);
    }

    /// With no descriptor left, `/proc` cannot be read: that is not death.
    /// Runs itself again as a child process, so that exhausting the
    /// descriptors cannot disturb the other tests.
    #[test]
    fn an_unreadable_proc_entry_is_not_death() {
        const CHILD: &str = "GRIDSWARM_TEST_EMFILE_CHILD";
        if std::env::var_os(CHILD).is_some() {
            let mut held = Vec::new();
            while let Ok(f) = fs::File::open("/dev/null") {
                held.push(f);
                assert!(held.len() < 1 << 20, "no descriptor limit to reach");
            }
            let me = std::process::id();
            let (liveness, alive) = (pid_liveness(me), pid_alive(me));
            drop(held);
            assert_eq!(liveness, None, "EMFILE: /proc cannot tell");
            assert!(alive, "and that is not death");
            return;
        }
        let out = std::process::Command::new(std::env::current_exe().unwrap())
            .args(["--exact", "ipc::tests::an_unreadable_proc_entry_is_not_death", "--test-threads=1"])
            .env(CHILD, "1")
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success() && text.contains("1 passed"), "{text}{}", String::from_utf8_lossy(&out.stderr));
    }
}
