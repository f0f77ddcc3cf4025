//! The explorer over real connections: the schema, the controls, the
//! scenes it may open, who may change anything, and the camera. Timeouts
//! only turn a hang into a failure; nothing is timed.

use std::io::BufRead;
use std::io::BufReader;
use std::net::SocketAddr;

use penumbra::sampling::Distribution;
use penumbra::scene::options::Value as OptionValue;
use penumbra::scene::{Choices, IntegratorChoice, LoadOptions};
use serde_json::{json, Value};

use super::controls::{value_json, CONTROLS};
use super::{Explorer, Setup};
use crate::preview::tests::{agent, next_event, raw};
use crate::preview::DEFAULT_BIND;

/// An explorer of `showcase`, small and quick: 40 x 30, 4 samples in 4
/// passes, one thread.
fn start() -> Explorer {
    let mut choices = Choices::default();
    let o = &mut choices.overrides;
    (o.width, o.height, o.spp, o.passes) = (Some(40), Some(30), Some(4), Some(4));
    choices.threads = Some(1);
    Explorer::start(Setup {
        bind: DEFAULT_BIND,
        port: 0,
        scenes: vec!["showcase".into()],
        load: LoadOptions::default(),
        choices,
    })
    .unwrap()
}

fn addr(e: &Explorer) -> SocketAddr {
    e.server().addr()
}

fn url(e: &Explorer, path: &str) -> String {
    format!("http://{}{path}?token={}", addr(e), e.server().token())
}

/// POSTs `body` as the page does (its own Origin) and returns the status
/// and the text.
fn post(e: &Explorer, path: &str, body: &Value) -> (u16, String) {
    let mut r = agent()
        .post(&url(e, path))
        .header("Origin", &format!("http://{}", addr(e)))
        .header("Content-Type", "application/json")
        .send(&body.to_string())
        .unwrap();
    (r.status().as_u16(), r.body_mut().read_to_string().unwrap())
}

fn post_ok(e: &Explorer, path: &str, body: &Value) -> Value {
    let (status, text) = post(e, path, body);
    assert_eq!(status, 200, "{path} {body}: {text}");
    serde_json::from_str(&text).unwrap()
}

fn events(e: &Explorer) -> impl BufRead {
    let r = agent().get(&url(e, "/events")).call().unwrap();
    assert_eq!(r.status(), 200);
    BufReader::new(r.into_body().into_reader())
}

/// A frame as (run, pass, passes, info, stats).
type Seen = (u64, u32, u32, Value, Value);

/// The frames up to the last pass of run `run`.
fn frames_until_done(reader: &mut impl BufRead, run: u64) -> Vec<Seen> {
    let mut seen = Vec::new();
    while let Some((name, data)) = next_event(reader) {
        if name != "frame" {
            continue;
        }
        let d: Value = serde_json::from_str(&data).unwrap();
        let at = |k: &str| d[k].as_u64().unwrap();
        let this = d["info"]["run"].as_u64().unwrap();
        let (pass, passes) = (at("pass") as u32, at("passes") as u32);
        seen.push((this, pass, passes, d["info"].clone(), d["stats"].clone()));
        if this == run && at("pass") == at("passes") {
            return seen;
        }
    }
    panic!("the stream ended before run {run} finished: {seen:?}");
}

fn image(e: &Explorer) -> Vec<u8> {
    let mut r = agent().get(&url(e, "/image")).call().unwrap();
    assert_eq!(r.status(), 200);
    r.body_mut().read_to_vec().unwrap()
}

#[test]
fn explore_page_is_whole_and_builds_its_controls_from_the_schema() {
    let e = start();
    let mut r = agent().get(&url(&e, "/")).call().unwrap();
    assert_eq!(r.status(), 200);
    let page = r.body_mut().read_to_string().unwrap();
    assert!(!page.contains("{{"), "a placeholder was left in the page");
    assert!(page.contains("<canvas id=\"image\""));
    assert!(page.contains("id=\"zoom-fit\"") && page.contains("id=\"p-rays\""));
    assert!(page.contains("fetch(\"/schema?\""));
    // No control is written into the page: each comes from /schema.
    assert!(!page.contains("shadow_distribution"));
}

#[test]
fn explore_schema_lists_the_controls_with_the_tables_defaults() {
    let e = start();
    let mut r = agent().get(&url(&e, "/schema")).call().unwrap();
    assert_eq!(r.status(), 200);
    let schema: Value = serde_json::from_str(&r.body_mut().read_to_string().unwrap()).unwrap();
    let controls = schema["controls"].as_array().unwrap();
    let names: Vec<&str> = controls
        .iter()
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, CONTROLS);
    for c in controls {
        let o = penumbra::scene::options::find(c["name"].as_str().unwrap()).unwrap();
        assert_eq!(c["doc"], o.doc);
        let expected = match o.default {
            penumbra::scene::options::DefaultValue::Fixed(v) => value_json(v),
            penumbra::scene::options::DefaultValue::Follows(n) => json!({ "follows": n }),
            penumbra::scene::options::DefaultValue::Computed(t) => json!({ "computed": t }),
        };
        assert_eq!(c["default"], expected, "{}", o.name);
    }
    let find = |n: &str| controls.iter().find(|c| c["name"] == n).unwrap();
    assert_eq!(find("spp")["kind"], "int");
    assert_eq!(find("metric")["default"], false);
    assert_eq!(
        find("shadow_distribution")["default"],
        json!({"follows": "distribution"})
    );
    let distributions: Vec<&str> = Distribution::SELECTABLE.iter().map(|d| d.name()).collect();
    assert_eq!(find("shadow_distribution")["choices"], json!(distributions));
    assert_eq!(
        find("integrator")["choices"],
        json!(IntegratorChoice::NAMES)
    );
    assert_eq!(
        find("integrator")["default"],
        value_json(OptionValue::Integrator(IntegratorChoice::Whitted))
    );
    let scenes = schema["scenes"].as_array().unwrap();
    assert!(scenes.iter().any(|s| s["name"] == "showcase"));
}

#[test]
fn explore_set_changes_the_next_run_and_refuses_bad_values() {
    let e = start();
    let mut stream = events(&e);
    frames_until_done(&mut stream, 1);
    let info = post_ok(
        &e,
        "/set",
        &json!({"name": "shadow_distribution", "value": "poisson"}),
    );
    assert_eq!(info["run"], 2);
    assert_eq!(info["settings"]["shadow"]["distribution"], "poisson");
    assert_eq!(info["chosen"]["shadow_distribution"], "poisson");
    let frames = frames_until_done(&mut stream, 2);
    let (_, _, _, last, _) = frames.last().unwrap();
    assert_eq!(last["settings"]["shadow"]["distribution"], "poisson");
    let info = post_ok(&e, "/set", &json!({"name": "shadow_rays", "value": 9}));
    assert_eq!(info["settings"]["shadow"]["rays"], 9);
    assert_eq!(
        info["settings"]["shadow"]["distribution"], "poisson",
        "kept"
    );

    let (status, text) = post(
        &e,
        "/set",
        &json!({"name": "shadow_distribution", "value": "sobel"}),
    );
    assert_eq!(status, 400);
    assert!(text.contains("unknown distribution `sobel`"), "{text}");
    for bad in [
        json!({"name": "spp", "value": 0}),
        json!({"name": "seed", "value": 1}),
        json!({"name": "metric", "value": "maybe"}),
        json!({"value": 1}),
        json!([1]),
    ] {
        let (status, text) = post(&e, "/set", &bad);
        assert_eq!(status, 400, "{bad}: {text}");
    }
    let (status, _) = raw(
        addr(&e),
        &format!(
            "POST /set?token={} HTTP/1.1\r\nHost: {}\r\nOrigin: http://{}\r\nContent-Length: 3\r\n\
             Connection: close\r\n\r\n{{x:",
            e.server().token(),
            addr(&e),
            addr(&e)
        ),
    );
    assert_eq!(status, 400, "not JSON");
}

#[test]
fn explore_opens_listed_scenes_only() {
    let e = start();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("other.toml");
    std::fs::write(&path, "[render]\nwidth = 8\nheight = 8\n").unwrap();
    let count = {
        let mut r = agent().get(&url(&e, "/schema")).call().unwrap();
        let s: Value = serde_json::from_str(&r.body_mut().read_to_string().unwrap()).unwrap();
        s["scenes"].as_array().unwrap().len()
    };
    for bad in [
        json!({"scene": count}),
        json!({"scene": 1e9}),
        json!({"scene": -1}),
        json!({"scene": path.display().to_string()}),
        json!({"scene": "/etc/passwd"}),
        json!({"scene": "../Cargo.toml"}),
        json!({"path": "showcase"}),
    ] {
        let (status, text) = post(&e, "/scene", &bad);
        assert_eq!(status, 400, "{bad}: {text}");
        assert!(text.contains("no other scene is opened"), "{text}");
    }
    let index = penumbra::scene::builtin::SCENES
        .iter()
        .position(|b| b.name == "cornell-box")
        .unwrap();
    let info = post_ok(&e, "/scene", &json!({"scene": index}));
    assert_eq!(info["scene_name"], "cornell-box");
    assert_eq!(info["settings"]["width"], 40, "the chosen settings stay");
    let info = post_ok(&e, "/scene", &json!({"scene": "showcase"}));
    assert_eq!(info["scene_name"], "showcase");
}

#[test]
fn explore_changes_need_the_token_the_host_and_the_origin() {
    let e = start();
    let (a, t) = (addr(&e), e.server().token().to_string());
    let body = r#"{"name":"spp","value":2}"#;
    let request = |path: &str, host: &str, extra: &str| {
        format!(
            "POST {path} HTTP/1.1\r\nHost: {host}\r\n{extra}Content-Type: application/json\r\n\
             Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
            body.len()
        )
    };
    let own = format!("Origin: http://{a}\r\n");
    let cases = [
        (request("/set", &a.to_string(), &own), "no token"),
        (
            request(
                &format!("/set?token={t}"),
                &format!("evil.example:{}", a.port()),
                &own,
            ),
            "another host",
        ),
        (
            request(
                &format!("/set?token={t}"),
                &a.to_string(),
                "Origin: http://evil.example\r\n",
            ),
            "another origin",
        ),
        (
            request(&format!("/set?token={t}"), &a.to_string(), ""),
            "no origin, token in the query",
        ),
    ];
    for (req, why) in &cases {
        for path in ["/set", "/camera", "/scene"] {
            let req = req.replacen("/set", path, 1);
            let (status, _) = raw(a, &req);
            assert_eq!(status, 403, "{path}: {why}");
        }
    }
    let (status, _) = raw(
        a,
        &format!("GET /schema HTTP/1.1\r\nHost: {a}\r\nConnection: close\r\n\r\n"),
    );
    assert_eq!(status, 403);
    // The token in the header, without an Origin: a client, not a form.
    let header = format!("X-Penumbra-Token: {t}\r\n");
    let (status, text) = raw(a, &request("/set", &a.to_string(), &header));
    assert_eq!(status, 200, "{text}");
}

#[test]
fn explore_orbit_and_dolly_change_the_image_and_restart_the_passes() {
    let e = start();
    let mut stream = events(&e);
    let first = frames_until_done(&mut stream, 1);
    assert!(first.iter().all(|f| f.0 == 1 && f.2 == 4));
    let before = image(&e);
    let info = post_ok(&e, "/camera", &json!({"orbit": [25.0, 10.0]}));
    assert_eq!(info["run"], 2);
    assert_ne!(info["camera"]["position"], first[0].3["camera"]["position"]);
    let frames = frames_until_done(&mut stream, 2);
    let of_run: Vec<u32> = frames.iter().filter(|f| f.0 == 2).map(|f| f.1).collect();
    // Counted again from the first pass, each pass once.
    assert!(of_run.windows(2).all(|w| w[0] < w[1]), "{of_run:?}");
    assert!(of_run[0] <= 4 && *of_run.last().unwrap() == 4);
    let orbited = image(&e);
    assert_eq!(orbited.len(), before.len());
    assert_ne!(orbited[16..], before[16..], "an orbit moves the image");

    let info = post_ok(&e, "/camera", &json!({"dolly": 0.5}));
    assert_eq!(info["run"], 3);
    frames_until_done(&mut stream, 3);
    assert_ne!(image(&e)[16..], orbited[16..], "a dolly moves the image");

    for bad in [
        json!({"dolly": 0}),
        json!({"dolly": "near"}),
        json!({"orbit": [1]}),
        json!({"orbit": [1e9, 0]}),
    ] {
        let (status, text) = post(&e, "/camera", &bad);
        assert_eq!(status, 400, "{bad}: {text}");
    }
    // The same camera again renders the same pixels.
    post_ok(&e, "/camera", &json!({"dolly": 2.0}));
    frames_until_done(&mut stream, 4);
    assert_eq!(image(&e)[16..], orbited[16..]);
}
