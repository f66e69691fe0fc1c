//! Work for the server, done on its blocking pool or, for large sparse
//! problems, in a worker process it can kill.
//!
//! A solve on the blocking pool is cancelled through the budget's flag
//! ([`fairsurf::budget`]) and stops at its next checkpoint — between dense
//! Cholesky panels, assembly loops and iterations. A sparse factorization
//! (faer's LLT, LDLᵀ, LU of a triangular surface's system) has no
//! checkpoint inside: it runs to its end. Requests whose surface may have
//! more unknowns than `--worker-unknowns` therefore run in a child process
//! (`fairsurf serve-worker`, the same binary) that the server kills when the
//! time is up or the client goes away, so the CPU is free at once. Small
//! requests — every drag of the editor — stay in-process, with the
//! factorizations kept between requests.
//!
//! The protocol: the job as one JSON object on the worker's standard input
//! (`{"job": "solve" | "analyse" | "compare" | "export", "scene": "…", "quick",
//! "mesh_encoding", "format", "max_unknowns", "max_bytes"}`); on its standard output one
//! line of JSON, `{"ok": {"json": …}}`, `{"ok": {"file": {"name", "kind"}}}`
//! followed by the file's bytes, or `{"error": …, "status": …, "path": …}`.

use super::{view, ApiError, ApiResult, Limits, Server};
use axum::http::StatusCode;
use serde_json::{json, Value};
use std::io::{Read, Write};
use std::sync::Arc;
use tokio::io::{AsyncReadExt, AsyncWriteExt};

/// One request's work.
#[derive(Clone, Debug)]
pub(crate) enum Job {
    /// Solve and describe for the page; `quick` skips the analysis and the
    /// check's polishing (see [`view::solve`]).
    Solve {
        scene: String,
        quick: bool,
        mesh: view::MeshEncoding,
    },
    /// Measure the surface as given.
    Analyse { scene: String },
    /// Monterde & Ugail's four surfaces.
    Compare { scene: String },
    /// The solved surface as a file of this format.
    Export { scene: String, format: String },
}

/// What a job gives back.
#[derive(Debug)]
pub(crate) enum Reply {
    Json(Value),
    /// A JSON document already written as text.
    Text(String),
    File {
        name: String,
        kind: String,
        bytes: Vec<u8>,
    },
}

impl Job {
    fn scene(&self) -> &str {
        match self {
            Job::Solve { scene, .. }
            | Job::Analyse { scene }
            | Job::Compare { scene }
            | Job::Export { scene, .. } => scene,
        }
    }

    /// Does the work here, on this thread.
    pub(crate) fn run(&self, limits: &Limits, factors: &fairsurf::FactorCache) -> ApiResult<Reply> {
        Ok(match self {
            Job::Solve { scene, quick, mesh } => {
                Reply::Text(view::solve(scene, *quick, *mesh, limits, factors)?)
            }
            Job::Analyse { scene } => Reply::Json(view::analyse(scene, limits)?),
            Job::Compare { scene } => Reply::Json(view::compare(scene, limits)?),
            Job::Export { scene, format } => {
                let (name, kind, bytes) = view::export(scene, format, limits)?;
                Reply::File {
                    name,
                    kind: kind.to_string(),
                    bytes,
                }
            }
        })
    }

    fn to_json(&self, limits: &Limits) -> Value {
        let mut v = json!({
            "scene": self.scene(),
            "max_unknowns": limits.max_unknowns,
            "max_bytes": limits.max_bytes,
        });
        match self {
            Job::Solve { quick, mesh, .. } => {
                v["job"] = json!("solve");
                v["quick"] = json!(quick);
                v["mesh_encoding"] = json!(mesh.name());
            }
            Job::Analyse { .. } => v["job"] = json!("analyse"),
            Job::Compare { .. } => v["job"] = json!("compare"),
            Job::Export { format, .. } => {
                v["job"] = json!("export");
                v["format"] = json!(format);
            }
        }
        v
    }

    fn from_json(v: &Value) -> Option<(Job, usize, usize)> {
        let scene = v["scene"].as_str()?.to_string();
        let job = match v["job"].as_str()? {
            "solve" => Job::Solve {
                scene,
                quick: v["quick"].as_bool()?,
                mesh: view::MeshEncoding::from_name(v["mesh_encoding"].as_str()?)?,
            },
            "analyse" => Job::Analyse { scene },
            "compare" => Job::Compare { scene },
            "export" => Job::Export {
                scene,
                format: v["format"].as_str()?.to_string(),
            },
            _ => return None,
        };
        let max_unknowns = usize::try_from(v["max_unknowns"].as_u64()?).ok()?;
        let max_bytes = usize::try_from(v["max_bytes"].as_u64()?).ok()?;
        Some((job, max_unknowns, max_bytes))
    }
}

/// An upper bound on the scalar unknowns of the request's scene, from its
/// JSON alone (no surface is built): 3 per control point, a triangular
/// surface's patches counted as if they shared none. 0 when the scene
/// does not say (the solve itself then reports what is wrong).
pub(crate) fn unknowns_bound(scene: &Value) -> usize {
    let s = &scene["surface"];
    let degree = |v: &Value| v.as_u64().map_or(0, |d| d.min(1 << 20) as usize);
    match s["type"].as_str() {
        Some("triangular") => {
            let d = degree(&s["degree"]);
            let patches = s["triangles"].as_array().map_or(0, Vec::len);
            3usize
                .saturating_mul(patches)
                .saturating_mul((d + 1) * (d + 2) / 2)
        }
        _ => match s["degree"].as_array().map(|d| d.as_slice()) {
            Some([n, m]) => 3usize.saturating_mul((degree(n) + 1) * (degree(m) + 1)),
            _ => 0,
        },
    }
}

/// Runs the job within the server's limits: in a worker process when its
/// scene may have more than `limits.worker_unknowns` unknowns, else on the
/// blocking pool; one per core at a time either way.
pub(crate) async fn dispatch(s: &Server, job: Job, unknowns: usize) -> ApiResult<Reply> {
    let _permit =
        s.solves.acquire().await.map_err(|_| {
            ApiError::new(StatusCode::SERVICE_UNAVAILABLE, "the server is stopping")
        })?;
    if unknowns > s.limits.worker_unknowns {
        in_worker(s, &job).await
    } else {
        in_process(s, job).await
    }
}

fn timed_out(limits: &Limits) -> ApiError {
    ApiError::new(
        StatusCode::SERVICE_UNAVAILABLE,
        format!(
            "the solve took longer than {} s (--timeout); lower the degree or the sampling",
            limits.timeout.as_secs_f64()
        ),
    )
}

/// On the blocking pool, cancelled (at the next checkpoint) when the time
/// is up or the client goes away (this future is dropped).
async fn in_process(s: &Server, job: Job) -> ApiResult<Reply> {
    struct CancelOnDrop(Arc<std::sync::atomic::AtomicBool>);
    impl Drop for CancelOnDrop {
        fn drop(&mut self) {
            self.0.store(true, std::sync::atomic::Ordering::Relaxed);
        }
    }
    let flag = Arc::new(std::sync::atomic::AtomicBool::new(false));
    let _cancel = CancelOnDrop(flag.clone());
    let budget = fairsurf::budget::Budget {
        max_bytes: s.limits.max_bytes,
        cancel: Some(flag),
    };
    let (limits, factors) = (s.limits, s.factors.clone());
    let work = move || fairsurf::budget::with_budget(budget, || job.run(&limits, &factors));
    match tokio::time::timeout(s.limits.timeout, tokio::task::spawn_blocking(work)).await {
        Ok(Ok(r)) => r,
        Ok(Err(e)) => Err(ApiError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            format!("the solve failed: {e}"),
        )),
        Err(_) => Err(timed_out(&s.limits)),
    }
}

/// In a child process, killed when the time is up or the client goes away
/// (`kill_on_drop`).
async fn in_worker(s: &Server, job: &Job) -> ApiResult<Reply> {
    let internal = |what: String| ApiError::new(StatusCode::INTERNAL_SERVER_ERROR, what);
    let exe = std::env::current_exe().map_err(|e| {
        internal(format!(
            "cannot find the fairsurf program for a worker: {e}"
        ))
    })?;
    let mut child = tokio::process::Command::new(exe)
        .arg("serve-worker")
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .kill_on_drop(true)
        .spawn()
        .map_err(|e| internal(format!("cannot start a worker process: {e}")))?;
    let input = serde_json::to_vec(&job.to_json(&s.limits)).unwrap_or_default();
    let (mut stdin, mut stdout) = match (child.stdin.take(), child.stdout.take()) {
        (Some(i), Some(o)) => (i, o),
        _ => return Err(internal("the worker process has no pipes".into())),
    };
    let talk = async {
        stdin.write_all(&input).await?;
        drop(stdin);
        let mut out = Vec::new();
        stdout.read_to_end(&mut out).await?;
        Ok::<_, std::io::Error>(out)
    };
    let out = match tokio::time::timeout(s.limits.timeout, talk).await {
        Ok(Ok(out)) => out,
        Ok(Err(e)) => {
            let _ = child.kill().await;
            return Err(internal(format!("the worker process failed: {e}")));
        }
        Err(_) => {
            let _ = child.kill().await;
            return Err(timed_out(&s.limits));
        }
    };
    let status = child.wait().await;
    parse_reply(&out).ok_or_else(|| {
        internal(match status {
            Ok(st) => format!("the worker process ended without an answer ({st})"),
            Err(e) => format!("the worker process ended without an answer: {e}"),
        })
    })?
}

/// The worker's answer: a header line, then a file's bytes if any.
fn parse_reply(out: &[u8]) -> Option<ApiResult<Reply>> {
    let end = out.iter().position(|&b| b == b'\n')?;
    let head: Value = serde_json::from_slice(&out[..end]).ok()?;
    let rest = &out[end + 1..];
    if let Some(ok) = head.get("ok") {
        if let Some(v) = ok.get("json") {
            return Some(Ok(Reply::Json(v.clone())));
        }
        let f = ok.get("file")?;
        return Some(Ok(Reply::File {
            name: f["name"].as_str()?.to_string(),
            kind: f["kind"].as_str()?.to_string(),
            bytes: rest.to_vec(),
        }));
    }
    let status = StatusCode::from_u16(u16::try_from(head["status"].as_u64()?).ok()?).ok()?;
    Some(Err(ApiError {
        status,
        message: head["error"].as_str()?.to_string(),
        path: head["path"].as_str().map(str::to_string),
    }))
}

/// Largest job a worker reads: the server's body limit is at most this.
const MAX_JOB_BYTES: u64 = 1 << 32;

/// `fairsurf serve-worker`: one job from standard input, its reply on
/// standard output (the server starts it; not for people).
pub fn run_worker() -> Result<(), crate::Failure> {
    let mut input = Vec::new();
    std::io::stdin()
        .take(MAX_JOB_BYTES)
        .read_to_end(&mut input)
        .map_err(|e| crate::Failure::input(format!("serve-worker: cannot read the job: {e}")))?;
    let (job, max_unknowns, max_bytes) = serde_json::from_slice::<Value>(&input)
        .ok()
        .as_ref()
        .and_then(Job::from_json)
        .ok_or_else(|| crate::Failure::input("serve-worker: expected a job from fairsurf serve"))?;
    let limits = Limits {
        // The server keeps the time.
        timeout: std::time::Duration::MAX,
        max_body: 0,
        max_unknowns,
        max_bytes,
        worker_unknowns: usize::MAX,
    };
    let budget = fairsurf::budget::Budget {
        max_bytes,
        cancel: None,
    };
    let factors = fairsurf::FactorCache::new(0, 0);
    let reply = fairsurf::budget::with_budget(budget, || job.run(&limits, &factors));
    let mut out = std::io::stdout().lock();
    let written = match reply {
        Ok(Reply::Json(v)) => writeln!(out, "{}", json!({"ok": {"json": v}})),
        Ok(Reply::Text(t)) => writeln!(out, "{{\"ok\":{{\"json\":{t}}}}}"),
        Ok(Reply::File { name, kind, bytes }) => writeln!(
            out,
            "{}",
            json!({"ok": {"file": {"name": name, "kind": kind}}})
        )
        .and_then(|_| out.write_all(&bytes)),
        Err(e) => writeln!(
            out,
            "{}",
            json!({"error": e.message, "status": e.status.as_u16(), "path": e.path})
        ),
    };
    written
        .and_then(|_| out.flush())
        .map_err(|e| crate::Failure::input(format!("serve-worker: cannot answer: {e}")))
}
