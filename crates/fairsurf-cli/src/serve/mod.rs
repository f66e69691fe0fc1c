//! `fairsurf serve`: the browser editor. A local HTTP server (axum on
//! tokio) serving the page (`editor/dist`, embedded at build time) and a
//! JSON API: solve, compare, export, and the bundled examples. The contract
//! is `editor/API.md`. The only state kept between requests is a few
//! factorizations ([`fairsurf::FactorCache`]), so that a drag re-solves
//! without assembling or factoring; answers never depend on it.
//!
//! Requests not addressed to this server or not from its page are refused
//! (`guard.rs`: Host, Origin, Content-Type). A connection must send its
//! headers within `--header-timeout` (10 s) and its body within 30 s (408);
//! at most 256 are open at once. Limits, each a clear JSON error: the
//! request body (`--max-body-mb`, 413), the problem's size
//! (`--max-unknowns`, 413), its estimated memory (`--max-memory-gb`, 413),
//! the solve time (`--timeout`, 503; the solve is cancelled, or its worker
//! process killed: `worker.rs`), and at most as many solves at once as
//! there are cores (the others wait their turn).

mod guard;
mod view;
mod worker;

pub use worker::run_worker;
use worker::{dispatch, Job, Reply};

use crate::Failure;
use axum::body::{to_bytes, Body, Bytes};
use axum::extract::{Path as UrlPath, Query, State};
use axum::http::{header, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use include_dir::{include_dir, Dir};
use serde_json::{json, Value};
use std::collections::HashMap;
use std::net::{IpAddr, SocketAddr};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;
use tokio::sync::Semaphore;

/// The editor page and its assets (built by `editor/build.sh`).
static DIST: Dir<'_> = include_dir!("$CARGO_MANIFEST_DIR/../../editor/dist");
/// The bundled example scenes.
static EXAMPLES: Dir<'_> = include_dir!("$CARGO_MANIFEST_DIR/../../examples");

#[derive(clap::Args)]
pub struct Args {
    /// A scene to open first (listed before the bundled examples).
    scene: Option<PathBuf>,
    /// The port (0: any free port; the address is printed).
    #[arg(long, default_value_t = 8765)]
    port: u16,
    /// The address to listen on: 127.0.0.1 (this machine only) unless told.
    #[arg(long, default_value = "127.0.0.1")]
    host: IpAddr,
    /// Longest solve, in seconds, before the request fails with 503.
    #[arg(long, default_value_t = 30.0)]
    timeout: f64,
    /// Largest request body, in MB.
    #[arg(long, default_value_t = 16)]
    max_body_mb: usize,
    /// Largest problem: scalar unknowns (3 per control point).
    #[arg(long, default_value_t = 300_000)]
    max_unknowns: usize,
    /// Another host name the server answers to (besides 127.0.0.1,
    /// localhost and `[::1]` at its port), e.g. a name for this machine;
    /// repeatable. Requests naming any other Host are refused (403).
    #[arg(long = "allow-host", value_name = "NAME[:PORT]")]
    allow_host: Vec<String>,
    /// Seconds a client has to send a request's headers (a connection that
    /// trickles them or sends nothing is closed).
    #[arg(long, default_value_t = 10.0)]
    header_timeout: f64,
    /// Requests whose surface may have more scalar unknowns than this run in
    /// a worker process, killed at the timeout or when the client goes away
    /// (a sparse factorization cannot be stopped inside the server); smaller
    /// ones, such as every drag, run in the server itself.
    #[arg(long, default_value_t = 30_000)]
    worker_unknowns: usize,
}

/// At most this many factorizations are kept between requests…
const FACTOR_ENTRIES: usize = 8;
/// …together at most this large (a degree-30 problem with a normal field
/// holds about 250 MB and is not kept).
const FACTOR_BYTES: usize = 256 << 20;

/// What the handlers share.
pub(crate) struct Server {
    /// (file name, scene text) of the examples, the opened scene first.
    examples: Vec<(String, String)>,
    limits: Limits,
    solves: Semaphore,
    /// Factorizations kept between requests: a drag that moves only known
    /// points, the guide surface or attractor targets re-solves with one.
    factors: Arc<fairsurf::FactorCache>,
}

/// The request limits.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Limits {
    pub timeout: Duration,
    pub max_body: usize,
    pub max_unknowns: usize,
    /// Largest estimated memory of one solve (`--max-memory-gb`).
    pub max_bytes: usize,
    /// Larger problems run in a worker process (`--worker-unknowns`).
    pub worker_unknowns: usize,
}

/// An API error: a 4xx status and `{"error", "path"}`.
#[derive(Debug)]
pub(crate) struct ApiError {
    pub status: StatusCode,
    pub message: String,
    pub path: Option<String>,
}

impl ApiError {
    pub fn new(status: StatusCode, message: impl Into<String>) -> Self {
        ApiError {
            status,
            message: message.into(),
            path: None,
        }
    }
}

impl From<fairsurf_io::Error> for ApiError {
    fn from(e: fairsurf_io::Error) -> Self {
        let message = e.to_string();
        match e {
            fairsurf_io::Error::Scene { path, .. } => ApiError {
                status: StatusCode::BAD_REQUEST,
                message,
                path: (!path.is_empty()).then_some(path),
            },
            fairsurf_io::Error::Solve(fairsurf::Error::TooLarge { .. }) => {
                ApiError::new(StatusCode::PAYLOAD_TOO_LARGE, message)
            }
            fairsurf_io::Error::Solve(fairsurf::Error::Cancelled) => {
                ApiError::new(StatusCode::SERVICE_UNAVAILABLE, message)
            }
            _ => ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, message),
        }
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        (
            self.status,
            Json(json!({"error": self.message, "path": self.path})),
        )
            .into_response()
    }
}

type ApiResult<T> = Result<T, ApiError>;

pub fn run(a: Args, max_bytes: usize) -> Result<(), Failure> {
    if !(a.header_timeout > 0.0 && a.header_timeout <= 3600.0) {
        return Err(Failure::input(format!(
            "--header-timeout {}: expected seconds in (0, 3600]",
            a.header_timeout
        )));
    }
    if !(a.timeout > 0.0 && a.timeout.is_finite()) {
        return Err(Failure::input(format!(
            "--timeout {}: expected a positive number of seconds",
            a.timeout
        )));
    }
    let mut examples = Vec::new();
    if let Some(p) = &a.scene {
        let text = crate::input::read(p)?;
        serde_json::from_str::<Value>(&text)
            .map_err(|e| Failure::input(format!("{}: {e}", p.display())))?;
        let name = p
            .file_name()
            .map_or("scene.json".into(), |n| n.to_string_lossy().into_owned());
        examples.push((name, text));
    }
    examples.extend(bundled_examples());
    let server = Arc::new(Server {
        examples,
        limits: Limits {
            timeout: Duration::from_secs_f64(a.timeout),
            max_body: a.max_body_mb.saturating_mul(1 << 20),
            max_unknowns: a.max_unknowns,
            max_bytes,
            worker_unknowns: a.worker_unknowns,
        },
        solves: Semaphore::new(std::thread::available_parallelism().map_or(2, |n| n.get())),
        factors: Arc::new(fairsurf::FactorCache::new(FACTOR_ENTRIES, FACTOR_BYTES)),
    });
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .map_err(|e| Failure::input(format!("cannot start the server: {e}")))?;
    runtime.block_on(async move {
        let addr = SocketAddr::new(a.host, a.port);
        let listener = tokio::net::TcpListener::bind(addr)
            .await
            .map_err(|e| Failure::input(format!("cannot listen on {addr}: {e}")))?;
        let local = listener
            .local_addr()
            .map_err(|e| Failure::input(format!("{e}")))?;
        println!("fairsurf editor: http://{local}/");
        use std::io::Write;
        let _ = std::io::stdout().flush();
        let hosts = Arc::new(guard::Hosts::new(local, &a.allow_host));
        let headers = Duration::from_secs_f64(a.header_timeout);
        serve_connections(listener, router(server, hosts), headers).await;
        Ok(())
    })
}

/// At most this many connections at once; more are closed on arrival.
const MAX_CONNECTIONS: usize = 256;
/// A client must send a request's body within this time (408).
const BODY_TIMEOUT: Duration = Duration::from_secs(30);

/// Accepts connections and serves each with HTTP/1.1 (hyper), with a
/// header read timeout and a cap on open connections: what `axum::serve`
/// does not offer.
async fn serve_connections(listener: tokio::net::TcpListener, app: Router, headers: Duration) {
    let open = Arc::new(Semaphore::new(MAX_CONNECTIONS));
    loop {
        let Ok((stream, _)) = listener.accept().await else {
            // Out of file descriptors or similar: wait, try again.
            tokio::time::sleep(Duration::from_millis(50)).await;
            continue;
        };
        let Ok(permit) = open.clone().try_acquire_owned() else {
            drop(stream);
            continue;
        };
        let service = hyper_util::service::TowerToHyperService::new(app.clone());
        tokio::spawn(async move {
            let io = hyper_util::rt::TokioIo::new(stream);
            let _ = hyper::server::conn::http1::Builder::new()
                .timer(hyper_util::rt::TokioTimer::new())
                .header_read_timeout(headers)
                .serve_connection(io, service)
                .await;
            drop(permit);
        });
    }
}

/// The bundled examples the editor opens (scenes: files with a
/// `"surface"`; fill scenes are for `fairsurf fill`), sorted by file name.
fn bundled_examples() -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = EXAMPLES
        .files()
        .filter(|f| f.path().extension().is_some_and(|e| e == "json"))
        .filter_map(|f| {
            Some((
                f.path().file_name()?.to_string_lossy().into_owned(),
                f.contents_utf8()?.to_string(),
            ))
        })
        .filter(|(_, text)| {
            serde_json::from_str::<Value>(text).is_ok_and(|v| v.get("surface").is_some())
        })
        .collect();
    out.sort();
    out
}

pub(crate) fn router(server: Arc<Server>, hosts: Arc<guard::Hosts>) -> Router {
    Router::new()
        .route("/api/examples", get(list_examples))
        .route("/api/examples/{file}", get(get_example))
        .route("/api/solve", post(solve))
        .route("/api/compare", post(compare))
        .route("/api/analyse", post(analyse))
        .route("/api/export", post(export))
        .route("/api/{*rest}", get(api_not_found).post(api_not_found))
        .fallback(get(asset))
        .with_state(server)
        .layer(axum::middleware::from_fn_with_state(hosts, guard::guard))
}

async fn api_not_found() -> ApiError {
    ApiError::new(StatusCode::NOT_FOUND, "no such API endpoint")
}

/// A file of the page.
async fn asset(uri: axum::http::Uri) -> Response {
    let path = uri.path().trim_start_matches('/');
    let path = if path.is_empty() { "index.html" } else { path };
    let Some(file) = DIST.get_file(path) else {
        return (StatusCode::NOT_FOUND, "not found").into_response();
    };
    let kind = match path.rsplit('.').next() {
        Some("html") => "text/html; charset=utf-8",
        Some("js" | "mjs") => "text/javascript; charset=utf-8",
        Some("css") => "text/css; charset=utf-8",
        Some("json") => "application/json",
        Some("png") => "image/png",
        Some("svg") => "image/svg+xml",
        _ => "application/octet-stream",
    };
    (
        [(header::CONTENT_TYPE, HeaderValue::from_static(kind))],
        file.contents(),
    )
        .into_response()
}

async fn list_examples(State(s): State<Arc<Server>>) -> Json<Value> {
    use fairsurf_io::SurfaceType;
    let list: Vec<Value> = s
        .examples
        .iter()
        .map(|(file, text)| {
            let kind = SurfaceType::of_json(text).unwrap_or(SurfaceType::Tensor);
            let v: Value = serde_json::from_str(text).unwrap_or(Value::Null);
            let name = v["name"].as_str().unwrap_or(file);
            json!({"file": file, "name": name, "kind": kind.name()})
        })
        .collect();
    Json(json!({ "examples": list }))
}

async fn get_example(
    State(s): State<Arc<Server>>,
    UrlPath(file): UrlPath<String>,
) -> ApiResult<Response> {
    let (_, text) = s
        .examples
        .iter()
        .find(|(f, _)| *f == file)
        .ok_or_else(|| ApiError::new(StatusCode::NOT_FOUND, format!("no example {file:?}")))?;
    Ok((
        [(
            header::CONTENT_TYPE,
            HeaderValue::from_static("application/json"),
        )],
        text.clone(),
    )
        .into_response())
}

/// A request body: the scene as text for the scene parsers (which name the
/// JSON path of every error), whether it asks for a quick answer
/// (`"quick": true`, while the user drags), and a bound on its unknowns.
struct Request {
    scene: String,
    quick: bool,
    /// How the answer writes its mesh (`"mesh_encoding"`).
    mesh: view::MeshEncoding,
    unknowns: usize,
}

async fn request(s: &Server, body: Body) -> ApiResult<Request> {
    let read = tokio::time::timeout(BODY_TIMEOUT, to_bytes(body, s.limits.max_body))
        .await
        .map_err(|_| {
            ApiError::new(
                StatusCode::REQUEST_TIMEOUT,
                format!(
                    "the request body did not arrive within {} s",
                    BODY_TIMEOUT.as_secs()
                ),
            )
        })?;
    let bytes: Bytes = read.map_err(|_| {
        ApiError::new(
            StatusCode::PAYLOAD_TOO_LARGE,
            format!(
                "the request is larger than {} MB (--max-body-mb)",
                s.limits.max_body >> 20
            ),
        )
    })?;
    let mut v: Value = serde_json::from_slice(&bytes).map_err(|e| ApiError {
        status: StatusCode::BAD_REQUEST,
        message: format!("the request is not JSON: {e}"),
        path: None,
    })?;
    let scene = v
        .get_mut("scene")
        .map(Value::take)
        .filter(Value::is_object)
        .ok_or_else(|| ApiError {
            status: StatusCode::BAD_REQUEST,
            message: "scene: expected the request {\"scene\": {…}}".into(),
            path: Some("scene".into()),
        })?;
    let quick = match v.get("quick") {
        None | Some(Value::Null) => false,
        Some(Value::Bool(b)) => *b,
        Some(other) => {
            return Err(ApiError {
                status: StatusCode::BAD_REQUEST,
                message: format!("quick: expected true or false, got {other}"),
                path: Some("quick".into()),
            })
        }
    };
    let mesh = match v.get("mesh_encoding") {
        None | Some(Value::Null) => view::MeshEncoding::default(),
        Some(other) => other
            .as_str()
            .and_then(view::MeshEncoding::from_name)
            .ok_or_else(|| ApiError {
                status: StatusCode::BAD_REQUEST,
                message: format!("mesh_encoding: expected \"json\" or \"base64\", got {other}"),
                path: Some("mesh_encoding".into()),
            })?,
    };
    Ok(Request {
        unknowns: worker::unknowns_bound(&scene),
        scene: scene.to_string(),
        quick,
        mesh,
    })
}

async fn solve(State(s): State<Arc<Server>>, body: Body) -> ApiResult<Response> {
    let r = request(&s, body).await?;
    let job = Job::Solve {
        scene: r.scene,
        quick: r.quick,
        mesh: r.mesh,
    };
    json_reply(dispatch(&s, job, r.unknowns).await?)
}

async fn analyse(State(s): State<Arc<Server>>, body: Body) -> ApiResult<Response> {
    let r = request(&s, body).await?;
    let job = Job::Analyse { scene: r.scene };
    json_reply(dispatch(&s, job, r.unknowns).await?)
}

async fn compare(State(s): State<Arc<Server>>, body: Body) -> ApiResult<Response> {
    let r = request(&s, body).await?;
    let job = Job::Compare { scene: r.scene };
    json_reply(dispatch(&s, job, r.unknowns).await?)
}

fn json_reply(reply: Reply) -> ApiResult<Response> {
    match reply {
        Reply::Json(v) => Ok(Json(v).into_response()),
        Reply::Text(t) => {
            Ok(([(axum::http::header::CONTENT_TYPE, "application/json")], t).into_response())
        }
        Reply::File { .. } => Err(ApiError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            "expected a JSON answer, got a file",
        )),
    }
}

async fn export(
    State(s): State<Arc<Server>>,
    Query(q): Query<HashMap<String, String>>,
    body: Body,
) -> ApiResult<Response> {
    let format = q.get("format").cloned().unwrap_or_default();
    let r = request(&s, body).await?;
    let job = Job::Export {
        scene: r.scene,
        format,
    };
    let Reply::File { name, kind, bytes } = dispatch(&s, job, r.unknowns).await? else {
        return Err(ApiError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            "expected a file, got a JSON answer",
        ));
    };
    let disposition = HeaderValue::from_str(&format!("attachment; filename=\"{name}\""))
        .unwrap_or_else(|_| HeaderValue::from_static("attachment"));
    let kind = HeaderValue::from_str(&kind)
        .unwrap_or_else(|_| HeaderValue::from_static("application/octet-stream"));
    Ok((
        [
            (header::CONTENT_TYPE, kind),
            (header::CONTENT_DISPOSITION, disposition),
        ],
        bytes,
    )
        .into_response())
}
