//! The live view: a mission served over the Foxglove WebSocket protocol while it runs, by the
//! [`foxglove`] crate's server, so that Foxglove (Open connection → Foxglove WebSocket →
//! `ws://127.0.0.1:8765`) shows it as it happens.
//!
//! [`LiveServer`] is the server: it listens until [`LiveServer::stop`] (or drop), whoever
//! records into it. [`LiveServer::sink`] gives a [`MessageSink`] for the
//! [`crate::recorder::Recorder`], which then publishes exactly the channels, schemas and
//! payloads it writes to an MCAP file (see [`crate::sink`]). A viewer receives the messages of
//! the channels it subscribed to from the moment it subscribed; the server keeps no history.
//!
//! Each server has its own [`foxglove::Context`], so servers (and tests) do not see each
//! other's channels. The server accepts the subprotocols of the `foxglove` crate
//! (`foxglove.sdk.v1`, `foxglove.sdk.v1.1`), which Foxglove offers.

use crate::error::LogError;
use crate::sink::{Channel, MessageSink};
use foxglove::websocket::ShutdownHandle;
use foxglove::{ChannelBuilder, Context, PartialMetadata, RawChannel, Schema};
use foxglove::{WebSocketServer, WebSocketServerHandle};
use std::collections::HashMap;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::sync::Arc;
use std::time::Duration;

/// The address served when none is given: the port Foxglove's connection dialog suggests, on
/// loopback only (the view carries the whole mission; serving other hosts is an explicit
/// choice).
pub const DEFAULT_ADDR: SocketAddr = SocketAddr::new(IpAddr::V4(Ipv4Addr::LOCALHOST), 8765);

/// Messages queued per viewer before the oldest are dropped: about 12 s of 20 Hz poses, so a
/// viewer that falls behind briefly loses nothing, while the memory one stalled viewer can
/// hold stays at this many messages (a map grid of a large world is a few MB).
pub const BACKLOG_MESSAGES: usize = 256;

/// How long stopping waits for the viewers' connections to close before cutting them: a
/// viewer that stopped reading must not hold the command open.
pub const SHUTDOWN_GRACE: Duration = Duration::from_secs(2);

/// The live view could not start.
#[derive(Debug, thiserror::Error)]
#[error(
    "live view: cannot serve on {addr}: {reason} (choose another address with --live HOST:PORT)"
)]
pub struct LiveError {
    /// The address asked for.
    pub addr: SocketAddr,
    /// What went wrong, one line.
    pub reason: String,
}

/// A Foxglove WebSocket server with its own channels.
pub struct LiveServer {
    ctx: Arc<Context>,
    handle: Option<WebSocketServerHandle>,
    addr: SocketAddr,
}

impl LiveServer {
    /// Starts serving on `addr` (port 0: any free port, see [`LiveServer::addr`]).
    pub fn start(addr: SocketAddr) -> Result<Self, LiveError> {
        let ctx = Context::new();
        // foxglove binds "host:port", which needs brackets around an IPv6 host.
        let host = match addr.ip() {
            IpAddr::V4(ip) => ip.to_string(),
            IpAddr::V6(ip) => format!("[{ip}]"),
        };
        let handle = WebSocketServer::new()
            .name("strider")
            .context(&ctx)
            .bind(host, addr.port())
            .message_backlog_size(BACKLOG_MESSAGES)
            .start_blocking()
            .map_err(|e| LiveError {
                addr,
                reason: strider_core::text::one_line(&e.to_string()),
            })?;
        let bound = SocketAddr::new(addr.ip(), handle.port());
        Ok(Self {
            ctx,
            handle: Some(handle),
            addr: bound,
        })
    }

    /// The address served (with the port chosen when 0 was asked for).
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// The URL to open in Foxglove.
    pub fn url(&self) -> String {
        format!("ws://{}", self.addr)
    }

    /// A sink publishing on this server's channels.
    pub fn sink(&self) -> LiveSink {
        LiveSink {
            ctx: self.ctx.clone(),
            channels: HashMap::new(),
        }
    }

    /// Whether a channel of `topic` exists and a viewer subscribed to it.
    pub fn subscribed(&self, topic: &str) -> bool {
        self.ctx
            .get_channel_by_topic(topic)
            .is_some_and(|c| c.has_sinks())
    }

    /// Viewers connected.
    pub fn clients(&self) -> usize {
        self.handle.as_ref().map_or(0, |h| h.client_count())
    }

    /// Stops serving: closes the viewers' connections, waiting at most [`SHUTDOWN_GRACE`].
    pub fn stop(mut self) {
        self.shutdown();
    }

    fn shutdown(&mut self) {
        if let Some(h) = self.handle.take() {
            wait_bounded(h.stop());
        }
    }
}

impl std::fmt::Debug for LiveServer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LiveServer")
            .field("addr", &self.addr)
            .finish_non_exhaustive()
    }
}

impl Drop for LiveServer {
    fn drop(&mut self) {
        self.shutdown();
    }
}

/// Waits for the server's tasks to end, at most [`SHUTDOWN_GRACE`]; dropping the handle after
/// that aborts whatever is left.
fn wait_bounded(h: ShutdownHandle) {
    let Ok(rt) = tokio::runtime::Builder::new_current_thread()
        .enable_time()
        .build()
    else {
        return; // dropping `h` aborts the tasks at once
    };
    let _ = rt.block_on(async { tokio::time::timeout(SHUTDOWN_GRACE, h.wait()).await });
}

/// Publishes recorded messages on a [`LiveServer`]'s channels.
pub struct LiveSink {
    ctx: Arc<Context>,
    channels: HashMap<String, Arc<RawChannel>>,
}

impl MessageSink for LiveSink {
    fn open(&mut self, ch: &Channel<'_>) -> Result<(), LogError> {
        if self.channels.contains_key(ch.topic) {
            return Ok(());
        }
        let schema = Schema::new(ch.schema_name, ch.schema_encoding, ch.schema.to_vec());
        let raw = ChannelBuilder::new(ch.topic)
            .context(&self.ctx)
            .message_encoding(ch.message_encoding)
            .schema(schema)
            .build_raw()
            .map_err(|e| LogError::Config(format!("live view, topic {}: {e}", ch.topic)))?;
        self.channels.insert(ch.topic.to_string(), raw);
        Ok(())
    }

    fn write(&mut self, topic: &str, stamp_ns: i64, data: &[u8]) -> Result<(), LogError> {
        let Some(c) = self.channels.get(topic) else {
            return Err(LogError::Config(format!("topic {topic}: no channel")));
        };
        c.log_with_meta(
            data,
            PartialMetadata {
                log_time: Some(stamp_ns.max(0) as u64),
            },
        );
        Ok(())
    }

    /// The channels stay advertised until the server stops, so a viewer keeps the last state.
    fn finish(&mut self) -> Result<(), LogError> {
        Ok(())
    }
}
