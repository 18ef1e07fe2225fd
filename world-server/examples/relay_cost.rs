//! Relaying a frame through the world vs publishing it straight to its
//! receivers, measured in one process (no scheduling noise, no wake-ups:
//! the data path only). Prints microseconds per frame for a small frame
//! (a `paper` map) and a large one (a `large` map).
//!
//!     cargo run --release --example relay_cost
//!
//! - direct: one `[u8]` publish into a service with K subscribers, and K
//!   receives (what agent-to-agent publish-subscribe would cost);
//! - relay: the agent's answer (postcard, chunked, published), the world's
//!   receive, reassembly, decode and copy into `Rc<[u8]>`, then for each of
//!   K receivers a wake-up message with the frame (encode, publish,
//!   receive, reassemble, decode).

use std::rc::Rc;
use std::time::Instant;

use gridswarm::ipc;
use gridswarm::wire::{
    self, AgentOutput, Assembler, ByteSlice, Bytes, ToWorld, WakeRef, WireFrameRef, WireLimits, WireSend,
};

const ITERS: usize = 5000;

fn main() -> Result<(), String> {
    ipc::quiet_logs();
    let prefix = ipc::new_prefix();
    let config = ipc::config(&prefix)?;
    let node = ipc::create_node(&config, "bench")?;
    for (name, size) in [("paper map", 220usize), ("large map", 10_000)] {
        for k in [1usize, 6] {
            let direct = direct(&node, size, k)?;
            let relay = relay(&node, size, k)?;
            println!("{name} ({size} B) to {k} receiver(s): direct {direct:.2} us, relay {relay:.2} us per frame");
        }
    }
    drop(node);
    let _ = ipc::cleanup_run(&prefix);
    Ok(())
}

fn service(node: &iceoryx2::prelude::Node<ipc::Svc>, subs: usize) -> Result<ipc::BytesService, String> {
    let name = format!("bench/{}", rand_name());
    node.service_builder(&ipc::service_name(&name)?)
        .publish_subscribe::<[u8]>()
        .max_publishers(1)
        .max_subscribers(subs)
        .subscriber_max_buffer_size(ipc::INBOX_CHUNKS)
        .enable_safe_overflow(true)
        .create()
        .map_err(|e| format!("{e:?}"))
}

fn rand_name() -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static N: AtomicU64 = AtomicU64::new(0);
    N.fetch_add(1, Ordering::Relaxed)
}

fn direct(node: &iceoryx2::prelude::Node<ipc::Svc>, size: usize, k: usize) -> Result<f64, String> {
    let svc = service(node, k)?;
    let publisher = ipc::bytes_publisher(&svc, ipc::CHUNK_BYTES)?;
    let subs: Vec<_> = (0..k).map(|_| ipc::bytes_subscriber(&svc, ipc::INBOX_CHUNKS)).collect::<Result<_, _>>()?;
    let frame = vec![7u8; size];
    let mut buf = Vec::new();
    let t = Instant::now();
    for _ in 0..ITERS {
        ipc::publish(&publisher, &frame)?;
        for s in &subs {
            ipc::receive(s, &mut buf)?;
        }
    }
    Ok(t.elapsed().as_secs_f64() * 1e6 / ITERS as f64)
}

fn relay(node: &iceoryx2::prelude::Node<ipc::Svc>, size: usize, k: usize) -> Result<f64, String> {
    let up = service(node, 1)?;
    let up_pub = ipc::bytes_publisher(&up, ipc::CHUNK_BYTES)?;
    let up_sub = ipc::bytes_subscriber(&up, ipc::INBOX_CHUNKS)?;
    let downs: Vec<_> = (0..k).map(|_| service(node, 1)).collect::<Result<_, _>>()?;
    let down_pubs: Vec<_> =
        downs.iter().map(|s| ipc::bytes_publisher(s, ipc::CHUNK_BYTES)).collect::<Result<_, _>>()?;
    let down_subs: Vec<_> =
        downs.iter().map(|s| ipc::bytes_subscriber(s, ipc::INBOX_CHUNKS)).collect::<Result<_, _>>()?;
    let limits = WireLimits::for_world(16, 100_000, 100);
    let agent_limits = WireLimits::for_robot(100_000, 100);
    let frame = vec![7u8; size];
    let mut buf = Vec::new();
    let mut world_asm = Assembler::new(1 << 22);
    let mut agent_asm: Vec<Assembler> = (0..k).map(|_| Assembler::new(1 << 22)).collect();
    let mut encoded = Vec::new();
    let t = Instant::now();
    for seq in 0..ITERS as u64 {
        // The sender's answer carries the frame.
        let out = AgentOutput {
            seq,
            send: vec![WireSend { bytes: Bytes(frame.clone()), ready: 1, copies: 1 }],
            ..Default::default()
        };
        let bytes = wire::encode_to_world(&ToWorld::Output(out));
        let mut res = Ok(());
        wire::chunks(seq, &bytes, ipc::CHUNK_BYTES, |c| res = res.clone().and(ipc::publish(&up_pub, c)));
        res?;
        // The world takes it in, as an opaque payload.
        let mut payload: Option<Rc<[u8]>> = None;
        while ipc::receive(&up_sub, &mut buf)? {
            if let Ok(Some((_, m))) = world_asm.push(&buf) {
                if let Ok(ToWorld::Output(o)) = wire::decode_to_world(m, &limits) {
                    payload = o.send.into_iter().next().map(|s| Rc::from(s.bytes.0));
                }
            }
        }
        let payload = payload.ok_or("lost")?;
        // ... and delivers it to every receiver in a wake-up.
        for (r, p) in down_pubs.iter().enumerate() {
            let wake = WakeRef {
                seq,
                now: 2,
                tick: None,
                frames: vec![WireFrameRef { from: 1, at: 2, bytes: ByteSlice(&payload) }],
            };
            wire::encode_wake_into(&wake, &mut encoded);
            let bytes = &encoded;
            let mut res = Ok(());
            wire::chunks(seq, bytes, ipc::CHUNK_BYTES, |c| res = res.clone().and(ipc::publish(p, c)));
            res?;
            while ipc::receive(&down_subs[r], &mut buf)? {
                if let Ok(Some((_, m))) = agent_asm[r].push(&buf) {
                    let _ = wire::decode_to_agent(m, &agent_limits).map_err(|e| e.to_string())?;
                }
            }
        }
    }
    Ok(t.elapsed().as_secs_f64() * 1e6 / ITERS as f64)
}
