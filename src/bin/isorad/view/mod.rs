//! `isorad view`: solve a scene and show it converge in a web browser.
//!
//! The command binds its port first (127.0.0.1 unless `--bind` says
//! otherwise), prints the page's address, and loads, meshes and solves the
//! scene on a thread of its own (`solve.rs`), publishing the mesh, its
//! light and the status as they change (`publisher.rs`, `broadcast.rs`).
//! The server (`server.rs`, `http.rs`, `socket.rs`) serves the page's
//! embedded files (`assets.rs`, from `assets/viewer/`) and pushes the
//! published state to every page over a WebSocket. Ctrl-C ends the command
//! with status 130; a scene that cannot be loaded or meshed
//! ends it with its error, as in every command.

mod assets;
mod broadcast;
mod http;
mod publisher;
mod server;
mod socket;
mod solve;

use std::io::Write;
use std::net::{IpAddr, Ipv4Addr, SocketAddr, TcpListener};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use anyhow::Context as _;
use clap::Args;

use crate::args::SolveArgs;
use crate::progress::{INTERRUPTED, Interrupted};
use broadcast::Broadcast;
use server::Context;

#[derive(Args)]
pub struct ViewArgs {
    #[command(flatten)]
    solve: SolveArgs,
    /// The port to serve on; 0 picks a free one.
    #[arg(long, default_value_t = 8750)]
    port: u16,
    /// The address to listen on. Anything but loopback lets every machine
    /// that reaches this one see the scene.
    #[arg(long, default_value_t = IpAddr::V4(Ipv4Addr::LOCALHOST))]
    bind: IpAddr,
}

pub fn view(args: ViewArgs) -> anyhow::Result<()> {
    let listener = TcpListener::bind((args.bind, args.port))
        .with_context(|| format!("cannot listen on {}:{}", args.bind, args.port))?;
    let address = listener.local_addr()?;
    ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::Relaxed))
        .context("cannot install the Ctrl-C handler")?;
    let broadcast = Arc::new(Broadcast::default());
    // A page that asks before the solve thread has begun sees it loading.
    broadcast.set_status(publisher::Status::loading().to_json());
    let solve = solve::start(args.solve, Arc::clone(&broadcast));
    let watched = solve.clone();
    let context = Arc::new(Context {
        broadcast,
        solve,
        loopback: address.ip().is_loopback(),
        connections: AtomicUsize::new(0),
    });
    std::thread::spawn(move || server::serve(&listener, &context));
    let shown = match address.ip() {
        ip if ip.is_unspecified() => {
            SocketAddr::new(IpAddr::V4(Ipv4Addr::LOCALHOST), address.port())
        }
        _ => address,
    };
    println!("isorad view: http://{shown}/ (Ctrl-C stops)");
    std::io::stdout().flush()?;
    if !address.ip().is_loopback() {
        eprintln!(
            "warning: listening on {address}: every machine that reaches this one can see the scene"
        );
    }
    while !INTERRUPTED.load(Ordering::Relaxed) {
        // A scene that cannot be loaded or meshed ends the command.
        if let Some(failure) = watched.failure() {
            anyhow::bail!("{failure}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    Err(Interrupted("interrupted: the viewer stopped".into()).into())
}
