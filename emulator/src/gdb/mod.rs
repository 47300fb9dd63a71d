//! GDB remote server: the machine as a multi-threaded target for gdb-multiarch.
//!
//! Library API (the `trax run --gdb 127.0.0.1:PORT` CLI wires these):
//!
//! - [`bind`]`(addr, allow_remote) -> TcpListener` binds the address; non-loopback
//!   addresses are refused unless `allow_remote`.
//! - [`serve_listener`]`(&mut machine, listener, out)` waits for one GDB connection and
//!   serves it until GDB detaches or the program ends; returns the outcome (if the
//!   program ran to its end). [`serve`]`(&mut machine, addr, out)` = bind (loopback
//!   only) + serve.
//!
//! Protocol features: every hardware thread is a GDB thread (thread id = index in
//! `Machine::threads` + 1); registers as GDB's MIPS port numbers them ([`arch`]; r6 has
//! no HI/LO, they read 0); memory reads/writes through the thread's view (its local
//! store included); software breakpoints (`Z0`); single step, which steps over delay
//! and forbidden slots (stops at the next instruction that is not in a slot);
//! continue; Ctrl-C. A crash stops with the fault's signal (SIGSEGV for bad
//! addresses, SIGBUS misaligned, SIGFPE arithmetic, SIGILL reserved instructions,
//! SIGABRT `trax.abort`, SIGTRAP breaks and traps) with the thread at the faulting
//! instruction; the end of the program is reported as an exit (status 0).
//!
//! Threads are interleaved exactly as in an ordinary run (see
//! [`crate::sched`]); a single step runs only the stepped thread.

pub mod arch;
pub mod target;

use std::io::Write;
use std::net::{SocketAddr, TcpListener, ToSocketAddrs};

use gdbstub::stub::{DisconnectReason, GdbStub};

use crate::machine::{Machine, Outcome};
pub use target::{signal_for, DebugTarget};

/// Errors of the GDB server.
#[derive(Debug, thiserror::Error)]
pub enum GdbError {
    /// The address does not parse or resolve.
    #[error("gdb server address {addr}: {msg}")]
    Address {
        /// The address given.
        addr: String,
        /// Why it is unusable.
        msg: String,
    },
    /// A non-loopback address without `allow_remote`.
    #[error("gdb server address {0} is not a loopback address (refused: anyone on the network could control the simulator)")]
    NotLoopback(SocketAddr),
    /// Socket errors.
    #[error("gdb server: {0}")]
    Io(#[from] std::io::Error),
    /// The GDB session failed.
    #[error("gdb session: {0}")]
    Session(String),
}

/// Binds `addr` (e.g. `127.0.0.1:1234`). Only loopback addresses unless `allow_remote`.
pub fn bind(addr: &str, allow_remote: bool) -> Result<TcpListener, GdbError> {
    let addrs: Vec<SocketAddr> = addr
        .to_socket_addrs()
        .map_err(|e| GdbError::Address {
            addr: addr.into(),
            msg: e.to_string(),
        })?
        .collect();
    let first = *addrs.first().ok_or_else(|| GdbError::Address {
        addr: addr.into(),
        msg: "resolves to no address".into(),
    })?;
    if let Some(bad) = addrs.iter().find(|a| !a.ip().is_loopback()) {
        if !allow_remote {
            return Err(GdbError::NotLoopback(*bad));
        }
    }
    Ok(TcpListener::bind(first)?)
}

/// Binds a loopback `addr` and serves one GDB session (see [`serve_listener`]).
pub fn serve(
    m: &mut Machine,
    addr: &str,
    out: &mut dyn Write,
) -> Result<Option<Outcome>, GdbError> {
    let l = bind(addr, false)?;
    serve_listener(m, l, out)
}

/// Accepts one connection on `listener` and serves it. Returns the program's outcome
/// if it ran to its end (exit or crash) during the session.
pub fn serve_listener(
    m: &mut Machine,
    listener: TcpListener,
    out: &mut dyn Write,
) -> Result<Option<Outcome>, GdbError> {
    let (stream, _) = listener.accept()?;
    stream.set_nodelay(true)?;
    let mut target = DebugTarget::new(m, out);
    let stub = GdbStub::new(stream);
    match stub.run_blocking::<target::EventLoop<'_>>(&mut target) {
        Ok(DisconnectReason::Disconnect)
        | Ok(DisconnectReason::TargetExited(_))
        | Ok(DisconnectReason::TargetTerminated(_))
        | Ok(DisconnectReason::Kill) => Ok(target.outcome().cloned()),
        Err(e) => Err(GdbError::Session(e.to_string())),
    }
}
