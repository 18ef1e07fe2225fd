//! How the world wakes one robot: one event service for every robot, each
//! robot's listener named after it, and the world's one notifier reaching
//! a single listener at a time ([`Waker`]).
//!
//! Why not an event service per robot: each cost the world three
//! descriptors (static config, dynamic config, port tag) besides the two
//! of the connection itself. Why not `notify` on the shared service: it
//! wakes every listener.
//!
//! iceoryx2 0.10's `notify_single_listener` reports a listener it has no
//! connection to (none could be opened, e.g. out of descriptors, or the
//! listener is gone) as an error, but a send over an open connection that
//! fails only as a warning in its log. The run's logger ([`install_logger`])
//! counts those warnings, and [`Waker::wake`] turns one into an error: no
//! wake-up is lost in silence.

use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, AtomicU8, Ordering};

use iceoryx2::port::notifier::ListenerKey;
use iceoryx2::prelude::*;
use iceoryx2_log::Log;

use super::{names, EventService, Listener, Notifier};

/// Warnings of a notifier whose send failed, since the process started.
static SEND_FAILURES: AtomicU64 = AtomicU64::new(0);
/// The lowest level the run's logger prints (iceoryx2 itself must let
/// warnings through, so that send failures are seen).
static PRINT_FROM: AtomicU8 = AtomicU8::new(LogLevel::Error as u8);

/// The start of iceoryx2's warning when a notification could not be sent
/// over an open connection (`Notifier`, 0.10).
const SEND_FAILED: &str = "Unable to send notification";

struct RunLogger;

impl Log for RunLogger {
    fn log(&self, level: LogLevel, origin: core::fmt::Arguments, message: core::fmt::Arguments) {
        let text = message.to_string();
        if level == LogLevel::Warn && is_send_failure(&text) {
            SEND_FAILURES.fetch_add(1, Ordering::SeqCst);
        }
        if level as u8 >= PRINT_FROM.load(Ordering::Relaxed) {
            eprintln!("iceoryx2 {level:?}: {origin}: {text}");
        }
    }
}

static LOGGER: RunLogger = RunLogger;

fn is_send_failure(message: &str) -> bool {
    message.starts_with(SEND_FAILED)
}

/// Routes iceoryx2's log through the run's logger: it prints errors only
/// (or from the level `IOX2_LOG_LEVEL` names), and counts failed sends of
/// notifications. Call it before anything of iceoryx2 logs.
pub fn install_logger() {
    // Another logger already in place (a test harness) still gets messages.
    let _ = set_logger(&LOGGER);
    set_log_level_from_env_or(LogLevel::Error);
    let wanted = iceoryx2_log::get_log_level();
    PRINT_FROM.store(wanted, Ordering::Relaxed);
    set_log_level(if wanted > LogLevel::Warn as u8 { LogLevel::Warn } else { level_of(wanted) });
}

fn level_of(v: u8) -> LogLevel {
    match v {
        0 => LogLevel::Trace,
        1 => LogLevel::Debug,
        2 => LogLevel::Info,
        3 => LogLevel::Warn,
        4 => LogLevel::Error,
        _ => LogLevel::Fatal,
    }
}

/// Creates the robots' wake service: one notifier (the world's), one
/// listener a robot.
pub fn create(node: &Node<super::Svc>, robots: usize) -> Result<EventService, String> {
    let name = names::robots_wake();
    node.service_builder(&super::service_name(&name)?)
        .event()
        .max_notifiers(1)
        .max_listeners(robots.max(1))
        .max_nodes(robots + 3)
        .event_id_max_value(1)
        .create()
        .map_err(|e| format!("cannot create event service `{name}`: {e:?}"))
}

/// Robot `robot`'s listener on the wake service, named so that the world
/// can find it.
pub fn listener(service: &EventService, robot: usize) -> Result<Listener, String> {
    let name = PortName::new(&names::robot_node(robot)).map_err(|e| format!("bad port name: {e:?}"))?;
    service.listener_builder().name(&name).create().map_err(|e| format!("cannot create listener: {e:?}"))
}

/// The world's side: wakes one robot at a time.
pub struct Waker {
    notifier: Notifier,
    /// The connection to each robot's listener, once found.
    keys: RefCell<Vec<Option<ListenerKey>>>,
}

impl Waker {
    pub fn new(service: &EventService, robots: usize) -> Result<Self, String> {
        let notifier =
            service.notifier_builder().create().map_err(|e| format!("cannot create the robots' notifier: {e:?}"))?;
        Ok(Waker { notifier, keys: RefCell::new(vec![None; robots]) })
    }

    /// Wakes robot `r`. An error when its listener cannot be reached: there
    /// is none, no connection to it could be opened, or the send failed.
    pub fn wake(&self, r: usize) -> Result<(), String> {
        let key = match self.key(r) {
            Some(k) => k,
            None => return Err(format!("robot {r} has no listener the world can reach")),
        };
        let before = SEND_FAILURES.load(Ordering::SeqCst);
        if let Err(e) = self.notifier.notify_single_listener(&key) {
            // The connection is gone (the listener closed): look again next time.
            self.keys.borrow_mut()[r] = None;
            return Err(format!("cannot wake robot {r}: {e:?}"));
        }
        if SEND_FAILURES.load(Ordering::SeqCst) != before {
            return Err(format!("cannot wake robot {r}: the notification could not be sent"));
        }
        Ok(())
    }

    fn key(&self, r: usize) -> Option<ListenerKey> {
        if let Some(k) = *self.keys.borrow().get(r)? {
            return Some(k);
        }
        self.find_listeners();
        self.keys.borrow()[r]
    }

    /// Learns every robot listener the notifier has a connection to.
    fn find_listeners(&self) {
        let mut keys = self.keys.borrow_mut();
        self.notifier.for_each_listener(|m, details| {
            let r = names::robot_of_node(&details.listener_name.to_string());
            if let Some(slot) = r.and_then(|r| keys.get_mut(r)) {
                *slot = Some(m.listener_key());
            }
            CallbackProgression::Continue
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ipc::{cleanup_run, config, create_node, PREFIX_HEAD};
    use std::time::Duration;

    fn woken(l: &Listener) -> usize {
        let mut n = 0;
        l.timed_wait(|_| n += 1, Duration::from_millis(20)).unwrap();
        n
    }

    /// One robot woken, the other not; a robot whose listener is gone is
    /// an error, not a silent miss.
    #[test]
    fn the_world_wakes_one_robot_at_a_time_and_says_when_it_cannot() {
        install_logger();
        let prefix = format!("{PREFIX_HEAD}{}x{:06x}_", std::process::id(), 0x3a7e);
        let c = config(&prefix).unwrap();
        let node = create_node(&c, "probe").unwrap();
        let service = create(&node, 3).unwrap();
        let l0 = listener(&service, 0).unwrap();
        let l2 = listener(&service, 2).unwrap();
        let waker = Waker::new(&service, 3).unwrap();
        waker.wake(2).unwrap();
        assert_eq!((woken(&l0), woken(&l2)), (0, 1));
        waker.wake(0).unwrap();
        assert_eq!((woken(&l0), woken(&l2)), (1, 0));
        assert!(waker.wake(1).unwrap_err().contains("robot 1 has no listener"));
        assert!(waker.wake(3).is_err(), "no such robot");
        drop(l2);
        assert!(waker.wake(2).is_err(), "a listener gone is an error");
        drop((l0, waker, service, node));
        cleanup_run(&prefix).unwrap();
    }

    /// A failed send that iceoryx2 only logs is counted by the run's logger.
    #[test]
    fn a_send_failure_iceoryx2_only_logs_is_counted() {
        let before = SEND_FAILURES.load(Ordering::SeqCst);
        LOGGER.log(
            LogLevel::Warn,
            format_args!("Notifier"),
            format_args!("Unable to send notification to single listener via connection x due to y."),
        );
        LOGGER.log(LogLevel::Warn, format_args!("Notifier"), format_args!("Something else."));
        LOGGER.log(
            LogLevel::Error,
            format_args!("Notifier"),
            format_args!("Unable to send notification, but an error"),
        );
        assert_eq!(SEND_FAILURES.load(Ordering::SeqCst), before + 1);
        assert!(is_send_failure("Unable to send notification via connection c due to e."), "notify's own wording too");
    }
}
