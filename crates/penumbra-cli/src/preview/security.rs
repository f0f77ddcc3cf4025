//! Who may talk to the preview server.
//!
//! The server listens on the loopback address, but any web page the user has
//! open can make the browser send requests there. Three checks keep those
//! out:
//! - a per-run token of 128 random bits, which only the URL printed on the
//!   terminal carries (query `token=` or header `X-Penumbra-Token`);
//! - the Host header must name the server itself (an IP address or
//!   `localhost`, with its port), so that a DNS name rebound to 127.0.0.1
//!   gets nothing;
//! - a request that changes anything (the preview's POST /stop, the
//!   explorer's controls) must come from the page's own origin, or carry the
//!   token in a header (which a cross-site form cannot add).

use std::net::IpAddr;

use axum::extract::Query;
use axum::http::{header, HeaderMap, Uri};

/// The header that may carry the token instead of the query.
pub const TOKEN_HEADER: &str = "x-penumbra-token";

/// The largest request body accepted, in bytes: a few words of JSON.
pub const BODY_LIMIT: u64 = 1024;

/// 128 bits from the operating system's generator, as 32 hex digits.
pub fn random_token() -> Result<String, getrandom::Error> {
    let mut bytes = [0u8; 16];
    getrandom::fill(&mut bytes)?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

/// The facts the checks compare requests with.
pub struct Access {
    pub token: String,
    /// The address the server was bound to.
    pub bound: IpAddr,
    pub port: u16,
}

impl Access {
    /// Whether the Host header names this server: `localhost`, a loopback
    /// address when bound to one, or the bound address, with the bound port.
    /// Any address literal is accepted on an unspecified bind (0.0.0.0).
    pub fn host_allowed(&self, headers: &HeaderMap) -> bool {
        let Some(host) = single(headers, header::HOST) else {
            return false;
        };
        let Some((name, port)) = split_host(host) else {
            return false;
        };
        if port != self.port {
            return false;
        }
        if name.eq_ignore_ascii_case("localhost") {
            return true;
        }
        let Ok(ip) = name.parse::<IpAddr>() else {
            return false;
        };
        ip == self.bound
            || self.bound.is_unspecified()
            || (ip.is_loopback() && self.bound.is_loopback())
    }

    /// Whether the request carries the token, in the query or the header.
    pub fn token_given(&self, headers: &HeaderMap, uri: &Uri) -> bool {
        if self.token_in_header(headers) {
            return true;
        }
        let Ok(Query(pairs)) = Query::<Vec<(String, String)>>::try_from_uri(uri) else {
            return false;
        };
        pairs
            .iter()
            .any(|(k, v)| k == "token" && same_secret(v.as_bytes(), self.token.as_bytes()))
    }

    /// Whether a state-changing request (POST /stop, /set, ...) may proceed: its Origin
    /// is the server's own (`http://` and the Host it was sent to, which
    /// `host_allowed` has passed), or it has no Origin and the token comes in
    /// the header.
    pub fn change_allowed(&self, headers: &HeaderMap) -> bool {
        if headers.get_all(header::ORIGIN).iter().count() == 0 {
            return self.token_in_header(headers);
        }
        match (
            single(headers, header::ORIGIN),
            single(headers, header::HOST),
        ) {
            (Some(origin), Some(host)) => origin
                .strip_prefix("http://")
                .is_some_and(|rest| rest.eq_ignore_ascii_case(host)),
            _ => false,
        }
    }

    fn token_in_header(&self, headers: &HeaderMap) -> bool {
        single(headers, TOKEN_HEADER)
            .is_some_and(|v| same_secret(v.as_bytes(), self.token.as_bytes()))
    }
}

/// The value of a header present exactly once, as text.
fn single(headers: &HeaderMap, name: impl header::AsHeaderName + Clone) -> Option<&str> {
    let mut values = headers.get_all(name.clone()).iter();
    let first = values.next()?;
    if values.next().is_some() {
        return None;
    }
    first.to_str().ok()
}

/// `name:port`, `[v6]:port`, or a name alone (port 80).
fn split_host(host: &str) -> Option<(&str, u16)> {
    let (name, port) = if let Some(rest) = host.strip_prefix('[') {
        let (inside, after) = rest.split_once(']')?;
        match after {
            "" => (inside, None),
            _ => (inside, Some(after.strip_prefix(':')?)),
        }
    } else {
        match host.split_once(':') {
            Some((name, port)) => (name, Some(port)),
            None => (host, None),
        }
    };
    let port = match port {
        None => 80,
        Some(p) if !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit()) => p.parse().ok()?,
        Some(_) => return None,
    };
    Some((name, port))
}

/// Equality whose time does not depend on where the first difference is.
fn same_secret(a: &[u8], b: &[u8]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

#[cfg(test)]
mod tests {
    use super::*;
    use axum::http::HeaderValue;
    use std::net::{Ipv4Addr, Ipv6Addr};

    fn access(bound: IpAddr) -> Access {
        Access {
            token: "00ff".into(),
            bound,
            port: 8123,
        }
    }

    fn headers(pairs: &[(&'static str, &str)]) -> HeaderMap {
        let mut h = HeaderMap::new();
        for (k, v) in pairs {
            h.append(*k, HeaderValue::from_str(v).unwrap());
        }
        h
    }

    #[test]
    fn preview_host_names_the_server_itself() {
        let a = access(IpAddr::V4(Ipv4Addr::LOCALHOST));
        for ok in [
            "127.0.0.1:8123",
            "localhost:8123",
            "LOCALHOST:8123",
            "[::1]:8123",
        ] {
            assert!(a.host_allowed(&headers(&[("host", ok)])), "{ok}");
        }
        for bad in [
            "evil.example:8123",
            "127.0.0.1:8124",
            "127.0.0.1",
            "127.0.0.1:",
            "127.0.0.1:+8123",
            "localhost.:8123",
            "10.0.0.1:8123",
            "[::1]8123",
            "",
        ] {
            assert!(!a.host_allowed(&headers(&[("host", bad)])), "{bad}");
        }
        assert!(!a.host_allowed(&HeaderMap::new()));
        let two = headers(&[("host", "127.0.0.1:8123"), ("host", "evil:8123")]);
        assert!(!a.host_allowed(&two));
    }

    #[test]
    fn preview_host_on_another_bind_is_that_address() {
        let a = access(IpAddr::V6(Ipv6Addr::LOCALHOST));
        assert!(a.host_allowed(&headers(&[("host", "[::1]:8123")])));
        let lan = access("192.168.1.5".parse().unwrap());
        assert!(lan.host_allowed(&headers(&[("host", "192.168.1.5:8123")])));
        assert!(!lan.host_allowed(&headers(&[("host", "127.0.0.1:8123")])));
    }

    #[test]
    fn preview_token_from_query_or_header() {
        let a = access(IpAddr::V4(Ipv4Addr::LOCALHOST));
        let uri = |s: &str| s.parse::<Uri>().unwrap();
        let none = HeaderMap::new();
        assert!(a.token_given(&none, &uri("/?token=00ff")));
        assert!(a.token_given(&none, &uri("/?x=1&token=00ff")));
        assert!(a.token_given(&headers(&[(TOKEN_HEADER, "00ff")]), &uri("/")));
        assert!(!a.token_given(&none, &uri("/")));
        assert!(!a.token_given(&none, &uri("/?token=00fe")));
        assert!(!a.token_given(&none, &uri("/?token=00ff0")));
        assert!(!a.token_given(&headers(&[(TOKEN_HEADER, "00FF")]), &uri("/")));
    }

    #[test]
    fn preview_change_needs_own_origin_or_token_header() {
        let a = access(IpAddr::V4(Ipv4Addr::LOCALHOST));
        let host = ("host", "127.0.0.1:8123");
        assert!(a.change_allowed(&headers(&[host, ("origin", "http://127.0.0.1:8123")])));
        assert!(!a.change_allowed(&headers(&[host, ("origin", "http://evil.example")])));
        assert!(!a.change_allowed(&headers(&[host, ("origin", "null")])));
        assert!(!a.change_allowed(&headers(&[host, ("origin", "https://127.0.0.1:8123")])));
        assert!(!a.change_allowed(&headers(&[
            host,
            ("origin", "http://evil.example"),
            (TOKEN_HEADER, "00ff")
        ])));
        assert!(a.change_allowed(&headers(&[host, (TOKEN_HEADER, "00ff")])));
        assert!(!a.change_allowed(&headers(&[host])));
    }

    #[test]
    fn preview_tokens_are_128_bit_and_differ() {
        let (a, b) = (random_token().unwrap(), random_token().unwrap());
        assert_eq!(a.len(), 32);
        assert!(a.bytes().all(|c| c.is_ascii_hexdigit()));
        assert_ne!(a, b);
    }
}
