//! What a web page elsewhere must not make the local server do. A page on
//! any site the user visits can send requests to 127.0.0.1; the server
//! answers only requests that are addressed to it and come from its own page:
//! - `Host` must name the server (`127.0.0.1:PORT`, `localhost:PORT`,
//!   `[::1]:PORT`, the address it listens on, or a name given with
//!   `--allow-host`): a DNS-rebinding page sends its own host name (403);
//! - an `Origin`, when sent, must be `http://` + one of those hosts (403);
//! - a POST must say `Content-Type: application/json`: the "simple" requests
//!   a cross-site page can send without a CORS preflight (text/plain, form
//!   bodies) are refused (415).

use super::ApiError;
use axum::extract::{Request, State};
use axum::http::{header, Method, StatusCode};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use std::net::SocketAddr;
use std::sync::Arc;

/// The host names (with port) the server answers to.
#[derive(Clone, Debug)]
pub(crate) struct Hosts(Vec<String>);

impl Hosts {
    /// The loopback names and `local` itself, at `local`'s port, plus
    /// `extra` names (with or without a port; without, the server's port).
    pub fn new(local: SocketAddr, extra: &[String]) -> Self {
        let port = local.port();
        let mut names = vec![
            format!("127.0.0.1:{port}"),
            format!("localhost:{port}"),
            format!("[::1]:{port}"),
            local.to_string(),
        ];
        for e in extra {
            let e = e.to_ascii_lowercase();
            // "name:port" or "[v6]:port" as given; otherwise at our port.
            let has_port = e.rsplit_once(':').is_some_and(|(h, p)| {
                !p.is_empty()
                    && p.bytes().all(|b| b.is_ascii_digit())
                    && (!h.contains(':') || h.ends_with(']'))
            });
            names.push(if has_port { e } else { format!("{e}:{port}") });
        }
        Self(names)
    }

    fn allows(&self, host: &str) -> bool {
        let host = host.to_ascii_lowercase();
        self.0.contains(&host)
    }
}

fn refuse(status: StatusCode, message: String) -> Response {
    ApiError::new(status, message).into_response()
}

/// The middleware: Host, Origin and Content-Type checks before any handler.
pub(crate) async fn guard(State(hosts): State<Arc<Hosts>>, req: Request, next: Next) -> Response {
    let headers = req.headers();
    let host = headers
        .get(header::HOST)
        .and_then(|h| h.to_str().ok())
        .unwrap_or("");
    if !hosts.allows(host) {
        return refuse(
            StatusCode::FORBIDDEN,
            format!(
                "Host {host:?} is not this server's address; use http://127.0.0.1:PORT/ \
                 (or name the host with --allow-host)"
            ),
        );
    }
    if let Some(origin) = headers.get(header::ORIGIN) {
        let origin = origin.to_str().unwrap_or("");
        let own = origin
            .strip_prefix("http://")
            .is_some_and(|o| hosts.allows(o));
        if !own {
            return refuse(
                StatusCode::FORBIDDEN,
                format!("requests from the page at {origin:?} are refused: only the editor's own page may call the API"),
            );
        }
    }
    if req.method() == Method::POST {
        let kind = headers
            .get(header::CONTENT_TYPE)
            .and_then(|h| h.to_str().ok())
            .unwrap_or("");
        let essence = kind.split(';').next().unwrap_or("").trim();
        if !essence.eq_ignore_ascii_case("application/json") {
            return refuse(
                StatusCode::UNSUPPORTED_MEDIA_TYPE,
                format!("Content-Type {kind:?}: the API takes application/json"),
            );
        }
    }
    next.run(req).await
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loopback_names_and_given_names_at_the_port() {
        let h = Hosts::new(
            "127.0.0.1:8765".parse().unwrap(),
            &["MyBox".into(), "other:9000".into()],
        );
        for ok in [
            "127.0.0.1:8765",
            "localhost:8765",
            "LOCALHOST:8765",
            "[::1]:8765",
            "mybox:8765",
            "other:9000",
        ] {
            assert!(h.allows(ok), "{ok}");
        }
        for bad in [
            "",
            "127.0.0.1",
            "127.0.0.1:8766",
            "evil.example:8765",
            "localhost.evil:8765",
            "mybox:1",
        ] {
            assert!(!h.allows(bad), "{bad}");
        }
    }
}
