//! Running a child process with a timeout, capturing the tail of its output.

use super::command::Invocation;
use std::io::Read;
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Bytes of each output stream kept (the end of it; CuraEngine prints ~20 kB per run).
pub const OUTPUT_KEEP_BYTES: usize = 256 * 1024;
/// How often the child is polled while waiting for it.
const POLL_INTERVAL: Duration = Duration::from_millis(10);
/// Extra attempts to start an executable that is busy being written (ETXTBSY).
const SPAWN_RETRIES: u32 = 5;

/// A finished run.
#[derive(Debug)]
pub struct Outcome {
    /// The exit status.
    pub status: ExitStatus,
    /// The end of standard output.
    pub stdout: Vec<u8>,
    /// The end of standard error.
    pub stderr: Vec<u8>,
}

impl Outcome {
    /// Standard output then standard error, lossily decoded.
    pub fn combined_text(&self) -> String {
        let mut s = String::from_utf8_lossy(&self.stdout).into_owned();
        if !s.is_empty() && !s.ends_with('\n') {
            s.push('\n');
        }
        s.push_str(&String::from_utf8_lossy(&self.stderr));
        s
    }
}

/// Why no [`Outcome`].
#[derive(Debug)]
pub enum RunError {
    /// The process could not be started.
    Spawn(std::io::Error),
    /// It ran longer than the timeout and was killed.
    TimedOut(Duration),
}

fn drain<R: Read + Send + 'static>(stream: Option<R>) -> Option<JoinHandle<Vec<u8>>> {
    let mut stream = stream?;
    Some(std::thread::spawn(move || {
        let mut kept = Vec::new();
        let mut buf = [0u8; 8192];
        loop {
            match stream.read(&mut buf) {
                Ok(0) | Err(_) => break,
                Ok(n) => {
                    kept.extend_from_slice(&buf[..n]);
                    if kept.len() > 2 * OUTPUT_KEEP_BYTES {
                        kept.drain(..kept.len() - OUTPUT_KEEP_BYTES);
                    }
                }
            }
        }
        kept
    }))
}

fn join(h: Option<JoinHandle<Vec<u8>>>) -> Vec<u8> {
    h.and_then(|h| h.join().ok()).unwrap_or_default()
}

fn wait(child: &mut Child, timeout: Option<Duration>) -> Result<ExitStatus, RunError> {
    let started = Instant::now();
    loop {
        match child.try_wait() {
            Ok(Some(status)) => return Ok(status),
            Ok(None) => {}
            Err(e) => return Err(RunError::Spawn(e)),
        }
        if let Some(limit) = timeout {
            if started.elapsed() >= limit {
                // Kill can only fail if the child already exited; wait reaps it either way.
                let _ = child.kill();
                let _ = child.wait();
                return Err(RunError::TimedOut(limit));
            }
        }
        std::thread::sleep(POLL_INTERVAL);
    }
}

/// Spawns, retrying a few times on ETXTBSY: a freshly written executable can be briefly
/// "busy" while another thread of this process forks.
fn spawn(cmd: &mut Command) -> Result<Child, RunError> {
    const TEXT_FILE_BUSY: i32 = 26;
    let mut attempt = 0;
    loop {
        match cmd.spawn() {
            Ok(child) => return Ok(child),
            Err(e) if e.raw_os_error() == Some(TEXT_FILE_BUSY) && attempt < SPAWN_RETRIES => {
                attempt += 1;
                std::thread::sleep(POLL_INTERVAL * 5);
            }
            Err(e) => return Err(RunError::Spawn(e)),
        }
    }
}

/// Runs `exe` with `inv`, stdin closed, both output streams captured.
pub fn run(exe: &Path, inv: &Invocation, timeout: Option<Duration>) -> Result<Outcome, RunError> {
    let mut cmd = Command::new(exe);
    cmd.args(&inv.args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    for (k, v) in &inv.env {
        cmd.env(k, v);
    }
    let mut child = spawn(&mut cmd)?;
    let out = drain(child.stdout.take());
    let err = drain(child.stderr.take());
    // On a timeout the reader threads are left to finish on their own: a grandchild may still
    // hold the pipes open.
    let status = wait(&mut child, timeout)?;
    Ok(Outcome {
        status,
        stdout: join(out),
        stderr: join(err),
    })
}
