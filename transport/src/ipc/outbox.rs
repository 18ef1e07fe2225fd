//! The robots' outboxes: one publish-subscribe service per group of
//! [`OUTBOX_GROUP`] robots instead of one per robot, every sample tagged
//! with its robot's number in iceoryx2's user header.
//!
//! Why groups: a service costs its reader three descriptors (static config,
//! dynamic config, port tag) whatever its number of writers, so sharing
//! one among robots saves the world three descriptors a robot. Why not one
//! for all: iceoryx2's `receive` looks at the writers' queues in order, so
//! one sample costs a look at up to a group's worth of queues; a group of
//! 32 keeps that a few hundred nanoseconds.

use iceoryx2::prelude::*;

use super::{service_name, Svc, CHUNK_BYTES};

/// Robots that share one outbox service.
pub const OUTBOX_GROUP: usize = 32;

pub type OutboxService = iceoryx2::service::port_factory::publish_subscribe::PortFactory<Svc, [u8], u32>;
pub type OutboxPublisher = iceoryx2::port::publisher::Publisher<Svc, [u8], u32>;
pub type OutboxSubscriber = iceoryx2::port::subscriber::Subscriber<Svc, [u8], u32>;

/// The outbox group of robot `r`.
pub fn group_of(r: usize) -> usize {
    r / OUTBOX_GROUP
}

/// How many outbox groups a run of `robots` robots has.
pub fn groups(robots: usize) -> usize {
    robots.div_ceil(OUTBOX_GROUP)
}

/// The robots of group `g` in a run of `robots` robots.
pub fn members(g: usize, robots: usize) -> usize {
    robots.saturating_sub(g * OUTBOX_GROUP).min(OUTBOX_GROUP)
}

/// Creates group `g`'s outbox for `writers` robots and one reader whose
/// buffer holds `buffer` samples of each writer.
pub fn create(node: &Node<Svc>, name: &str, writers: usize, buffer: usize) -> Result<OutboxService, String> {
    node.service_builder(&service_name(name)?)
        .publish_subscribe::<[u8]>()
        .user_header::<u32>()
        .max_publishers(writers.max(1))
        .max_subscribers(1)
        .max_nodes(writers + 3)
        .history_size(0)
        .subscriber_max_buffer_size(buffer)
        .subscriber_max_borrowed_samples(2)
        // Buffers are sized so a full one never drops, and so a frozen
        // reader can never block a writer.
        .enable_safe_overflow(true)
        .create()
        .map_err(|e| format!("cannot create service `{name}`: {e:?}"))
}

/// Opens an outbox [`create`] made, checking it has room for a reader
/// buffer of `buffer` samples.
pub fn open(node: &Node<Svc>, name: &str, buffer: usize) -> Result<OutboxService, String> {
    node.service_builder(&service_name(name)?)
        .publish_subscribe::<[u8]>()
        .user_header::<u32>()
        .subscriber_max_buffer_size(buffer)
        .open()
        .map_err(|e| format!("cannot open service `{name}`: {e:?}"))
}

/// A robot's writer into its group's outbox (see [`super::bytes_publisher`]).
pub fn publisher(service: &OutboxService) -> Result<OutboxPublisher, String> {
    service
        .publisher_builder()
        .initial_max_slice_len(CHUNK_BYTES)
        .allocation_strategy(AllocationStrategy::Static)
        .create()
        .map_err(|e| format!("cannot create publisher: {e:?}"))
}

pub fn subscriber(service: &OutboxService, buffer: usize) -> Result<OutboxSubscriber, String> {
    service.subscriber_builder().buffer_size(buffer).create().map_err(|e| format!("cannot create subscriber: {e:?}"))
}

/// Publishes one chunk of robot `robot`.
pub fn publish(publisher: &OutboxPublisher, robot: u32, bytes: &[u8]) -> Result<(), String> {
    let mut sample = publisher.loan_slice_uninit(bytes.len()).map_err(|e| format!("cannot loan a sample: {e:?}"))?;
    *sample.user_header_mut() = robot;
    sample.write_from_slice(bytes).send().map_err(|e| format!("cannot send: {e:?}"))?;
    Ok(())
}

/// Takes the next chunk of any writer of the group into `buf`, and says
/// whose it is (the robot number its writer tagged it with).
pub fn receive(subscriber: &OutboxSubscriber, buf: &mut Vec<u8>) -> Result<Option<u32>, String> {
    let Some(sample) = subscriber.receive().map_err(|e| format!("cannot receive: {e:?}"))? else {
        return Ok(None);
    };
    buf.clear();
    buf.extend_from_slice(sample.payload());
    Ok(Some(*sample.user_header()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_cover_every_robot_once() {
        for n in [1, 31, 32, 33, 64, 1000] {
            let total: usize = (0..groups(n)).map(|g| members(g, n)).sum();
            assert_eq!(total, n, "{n}");
            assert!((0..n).all(|r| group_of(r) < groups(n)));
            assert_eq!(members(groups(n), n), 0);
        }
        assert_eq!(groups(1000), 32);
        assert_eq!(group_of(31), 0);
        assert_eq!(group_of(32), 1);
    }

    /// Two robots write into one group's outbox; the reader gets each
    /// chunk with its writer's number, and a group full of writers refuses
    /// one more.
    #[test]
    fn a_shared_outbox_tells_whose_each_chunk_is() {
        use crate::ipc::{cleanup_run, config, create_node, PREFIX_HEAD};
        let prefix = format!("{PREFIX_HEAD}{}x{:06x}_", std::process::id(), 0x0b0);
        let c = config(&prefix).unwrap();
        let node = create_node(&c, "probe").unwrap();
        let service = create(&node, "probe/out", 2, 4).unwrap();
        let reader = subscriber(&service, 4).unwrap();
        let (a, b) = (publisher(&service).unwrap(), publisher(&service).unwrap());
        assert!(publisher(&service).is_err(), "room for two writers only");
        publish(&b, 7, b"from b").unwrap();
        publish(&a, 6, b"from a").unwrap();
        let mut got = Vec::new();
        let mut buf = Vec::new();
        while let Some(from) = receive(&reader, &mut buf).unwrap() {
            got.push((from, buf.clone()));
        }
        got.sort();
        assert_eq!(got, [(6, b"from a".to_vec()), (7, b"from b".to_vec())]);
        assert!(open(&node, "probe/out", 8).is_err(), "a bigger buffer than the creator gave is refused");
        drop((a, b, reader, service, node));
        cleanup_run(&prefix).unwrap();
    }
}
