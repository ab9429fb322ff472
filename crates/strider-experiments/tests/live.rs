//! The live view: a mission served over the Foxglove WebSocket protocol reaches a WebSocket
//! client that subscribes as Foxglove does (map grids and robot poses, decodable with
//! Foxglove's schemas); serving and pacing do not change the mission or its MCAP recording; an
//! interrupt stops a paced mission and the server closes the viewer's connection.
//!
//! Waits are bounded and fail with what was missing; nothing asserts on durations.

use std::collections::{BTreeMap, HashMap};
use std::net::{SocketAddr, TcpStream};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::thread;
use std::time::{Duration, Instant};

use foxglove::Decode;
use foxglove::messages::{FrameTransform, Grid};
use serde_json::Value;
use strider_experiments::cancel::Cancel;
use strider_experiments::live::{LiveServer, Watch};
use strider_experiments::pace::Rate;
use strider_experiments::trial::{mission_params, run_mission};
use strider_explore::{MissionParams, Strategy};
use strider_scenario::Scenario;
use tungstenite::client::IntoClientRequest;
use tungstenite::{Message, WebSocket};

/// The longest any single wait of these tests lasts before it fails.
const PATIENCE: Duration = Duration::from_secs(120);

const MAP: &str = "/strider/map";
const ROBOT: &str = "/strider/robot";

fn mission(time_limit_s: f64) -> (Scenario, MissionParams) {
    let sc = Scenario::from_name_or_file("courtyard-small", 1).unwrap();
    let mut params = mission_params(&sc, Strategy::Gtsp, 1).unwrap();
    params.time_limit_s = time_limit_s;
    (sc, params)
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("strider-live-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A WebSocket client speaking the Foxglove protocol: connects with the SDK's subprotocol,
/// reads with a short timeout so that its loop can also notice the end of the test.
fn connect(addr: SocketAddr) -> WebSocket<TcpStream> {
    let stream = TcpStream::connect(addr).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_millis(100)))
        .unwrap();
    let mut req = format!("ws://{addr}").into_client_request().unwrap();
    req.headers_mut()
        .insert("sec-websocket-protocol", "foxglove.sdk.v1".parse().unwrap());
    let (ws, resp) = tungstenite::client(req, stream).expect("WebSocket handshake");
    assert_eq!(
        resp.headers()["sec-websocket-protocol"],
        "foxglove.sdk.v1",
        "the server speaks the Foxglove SDK subprotocol"
    );
    ws
}

/// What the client saw, sent to the test as it happens.
#[derive(Debug)]
enum Seen {
    /// A message on a subscribed topic: topic, log time (ns), payload.
    Message(String, u64, Vec<u8>),
    /// The server closed the connection.
    Closed,
}

/// Reads the server's messages: subscribes to `topics` once all are advertised (again when the
/// server rejects a subscription), forwards the messages received on them, and reports when
/// the server closes the connection.
fn viewer(mut ws: WebSocket<TcpStream>, topics: &[&str], tx: mpsc::Sender<Seen>) {
    let mut channels: HashMap<String, u64> = HashMap::new();
    let mut subscribed: BTreeMap<u32, String> = BTreeMap::new();
    loop {
        let msg = match ws.read() {
            Ok(m) => m,
            Err(tungstenite::Error::Io(e))
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) =>
            {
                continue;
            }
            Err(_) => break,
        };
        match msg {
            Message::Text(text) => {
                let v: Value = serde_json::from_str(&text).unwrap();
                if v["op"] == "advertise" {
                    for c in v["channels"].as_array().unwrap() {
                        let topic = c["topic"].as_str().unwrap().to_string();
                        channels.insert(topic, c["id"].as_u64().unwrap());
                    }
                }
                // The server sends an advertisement before it records the channel as advertised
                // to this client, so a viewer that answers at once can be told the channel is
                // unknown; Foxglove then keeps no subscription. Subscribe again.
                if v["op"] == "status"
                    && v["message"]
                        .as_str()
                        .is_some_and(|m| m.starts_with("Unknown channel ID"))
                {
                    subscribed.clear();
                }
                if subscribed.is_empty() && topics.iter().all(|t| channels.contains_key(*t)) {
                    let subs: Vec<Value> = topics
                        .iter()
                        .enumerate()
                        .map(|(i, t)| serde_json::json!({"id": i, "channelId": channels[*t]}))
                        .collect();
                    let op = serde_json::json!({"op": "subscribe", "subscriptions": subs});
                    ws.send(Message::Text(op.to_string().into())).unwrap();
                    subscribed = (0..).zip(topics.iter().map(|t| t.to_string())).collect();
                }
            }
            // Message data: opcode 1, subscription id (u32 LE), log time (u64 LE), payload.
            Message::Binary(b) if b.first() == Some(&1) && b.len() >= 13 => {
                let sub = u32::from_le_bytes(b[1..5].try_into().unwrap());
                let t = u64::from_le_bytes(b[5..13].try_into().unwrap());
                let topic = subscribed.get(&sub).expect("a subscribed id").clone();
                let _ = tx.send(Seen::Message(topic, t, b[13..].to_vec()));
            }
            Message::Close(_) => break,
            _ => {}
        }
    }
    let _ = tx.send(Seen::Closed);
}

/// Waits until `ok` holds, polling; fails with `what` after [`PATIENCE`].
fn wait_for(what: &str, mut ok: impl FnMut() -> bool) {
    let start = Instant::now();
    while !ok() {
        assert!(start.elapsed() < PATIENCE, "gave up waiting: {what}");
        thread::sleep(Duration::from_millis(10));
    }
}

#[test]
fn a_viewer_subscribed_to_the_live_view_receives_map_grids_and_robot_poses() {
    let server = LiveServer::start("127.0.0.1:0".parse().unwrap()).unwrap();
    assert_ne!(server.addr().port(), 0);
    let ws = connect(server.addr());
    let (tx, rx) = mpsc::channel();
    let client = thread::spawn(move || viewer(ws, &[MAP, ROBOT], tx));
    wait_for("the viewer is connected", || server.clients() == 1);

    let (sc, params) = mission(20.0);
    let cancel = Cancel::new();
    let watch = Watch {
        mcap: None,
        live: Some(&server),
        rate: None,
        cancel: &cancel,
    };
    let mut calls = 0;
    run_mission(&sc, params, 1, watch, |_| {
        // From the second report on, the map and the pose channels exist: hold the mission
        // until the viewer has subscribed to them, so that what follows reaches it.
        calls += 1;
        if calls == 2 {
            wait_for(
                "the viewer subscribed to the map and the robot pose",
                || server.subscribed(MAP) && server.subscribed(ROBOT),
            );
        }
    })
    .unwrap();

    let (mut grids, mut poses) = (Vec::new(), Vec::new());
    let start = Instant::now();
    while grids.is_empty() || poses.is_empty() {
        let left = PATIENCE.saturating_sub(start.elapsed());
        match rx.recv_timeout(left) {
            Ok(Seen::Message(topic, t, data)) if topic == MAP => {
                grids.push((t, Grid::decode(&data[..]).expect("a foxglove.Grid")));
            }
            Ok(Seen::Message(_, t, data)) => {
                poses.push((
                    t,
                    FrameTransform::decode(&data[..]).expect("a FrameTransform"),
                ));
            }
            other => panic!(
                "{} map grids and {} poses received, then {other:?}",
                grids.len(),
                poses.len()
            ),
        }
    }
    let (t, grid) = &grids[0];
    assert!(*t > 0, "stamped in robot time");
    assert!(grid.column_count > 0 && !grid.data.is_empty(), "{grid:?}");
    assert_eq!(grid.frame_id, "map");
    let (_, pose) = &poses[0];
    assert_eq!(
        (pose.parent_frame_id.as_str(), pose.child_frame_id.as_str()),
        ("map", "base_link")
    );

    // Stopping the server closes the viewer's connection.
    server.stop();
    wait_for_close(&rx);
    client.join().unwrap();
}

/// The MCAP file of a mission on courtyard-small (seed 1) with `watch`'s live view and pace.
fn record(file: &Path, live: Option<&LiveServer>, rate: Option<Rate>) -> Vec<u8> {
    let (sc, params) = mission(30.0);
    let cancel = Cancel::new();
    let watch = Watch {
        mcap: Some(file),
        live,
        rate,
        cancel: &cancel,
    };
    run_mission(&sc, params, 1, watch, |_| {}).unwrap();
    std::fs::read(file).unwrap()
}

#[test]
fn serving_live_and_pacing_leave_the_recording_byte_for_byte_the_same() {
    let dir = temp_dir("same-recording");
    let alone = record(&dir.join("alone.mcap"), None, None);
    let server = LiveServer::start("127.0.0.1:0".parse().unwrap()).unwrap();
    let rate = Rate::new(300.0).ok();
    let served = record(&dir.join("served.mcap"), Some(&server), rate);
    assert!(alone.len() > 1000);
    assert!(alone == served, "the recordings differ");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_interrupt_stops_a_paced_live_mission_and_its_server() {
    let server = LiveServer::start("127.0.0.1:0".parse().unwrap()).unwrap();
    let ws = connect(server.addr());
    let (tx, rx) = mpsc::channel();
    let client = thread::spawn(move || viewer(ws, &[ROBOT], tx));
    let cancel = Cancel::new();
    let (done_tx, done_rx) = mpsc::channel();
    thread::scope(|s| {
        s.spawn(|| {
            // A whole hour at a hundredth of real time: only the interrupt ends it.
            let (sc, params) = mission(3600.0);
            let watch = Watch {
                mcap: None,
                live: Some(&server),
                rate: Rate::new(Rate::MIN).ok(),
                cancel: &cancel,
            };
            let (m, _, _) = run_mission(&sc, params, 1, watch, |_| {}).unwrap();
            done_tx.send(m.interrupted()).unwrap();
        });
        // Ctrl-C once the mission runs (the first pose is published).
        wait_for("the mission published its first pose", || {
            server.subscribed(ROBOT) || rx.try_recv().is_ok()
        });
        cancel.request();
        let interrupted = done_rx
            .recv_timeout(PATIENCE)
            .expect("the paced mission did not stop after the interrupt");
        assert!(interrupted);
    });
    server.stop();
    wait_for_close(&rx);
    client.join().unwrap();
}

/// Waits (at most `PATIENCE`) until the viewer reports its connection closed; fails otherwise.
fn wait_for_close(rx: &mpsc::Receiver<Seen>) {
    let start = Instant::now();
    loop {
        match rx.recv_timeout(PATIENCE.saturating_sub(start.elapsed())) {
            Ok(Seen::Closed) => return,
            Ok(Seen::Message(..)) => {}
            Err(e) => panic!("the viewer's connection was not closed: {e}"),
        }
    }
}
