//! A headless Chromium driven through chromedriver (WebDriver, with `fantoccini`), for the
//! browser tests (`browser.rs`, `browser_rewind.rs`).
//!
//! Without a browser (no `chromium` and `chromedriver` on `PATH`, or at the paths in
//! `NEUROTREE_CHROMIUM` and `NEUROTREE_CHROMEDRIVER`) [`Browser::start`] prints a note and
//! gives `None`; with `NEUROTREE_REQUIRE_BROWSER=1` (as `.ci/run` sets) it fails instead.

#![allow(dead_code)]

use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use fantoccini::{Client, ClientBuilder, Locator};
use hyper_util::client::legacy::connect::HttpConnector;
use serde_json::{json, Value};

pub struct Browser {
    pub client: Client,
    driver: Child,
    _profile: tempfile::TempDir,
}

impl Browser {
    /// A headless chromium through a chromedriver of its own, or `None` (with a note) when
    /// there is none and none is required.
    pub async fn start() -> Option<Browser> {
        let chromium = tool("NEUROTREE_CHROMIUM", "chromium");
        let driver = tool("NEUROTREE_CHROMEDRIVER", "chromedriver");
        if !chromium.exists() || !driver.exists() {
            let missing = format!(
                "{} or {} is missing (Debian: apt-get install chromium chromium-driver)",
                chromium.display(),
                driver.display()
            );
            if std::env::var("NEUROTREE_REQUIRE_BROWSER").as_deref() == Ok("1") {
                panic!("no browser, which NEUROTREE_REQUIRE_BROWSER=1 requires: {missing}");
            }
            eprintln!("browser test skipped: {missing}");
            return None;
        }
        let port = free_port();
        let driver = Command::new(&driver)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("chromedriver starts");
        let profile = tempfile::tempdir().expect("a profile folder");
        let caps = json!({
            "browserName": "chrome",
            "goog:chromeOptions": {
                "binary": chromium,
                "args": [
                    "--headless=new", "--no-sandbox", "--disable-gpu",
                    "--disable-background-networking", "--disable-component-update",
                    "--disable-sync", "--no-first-run", "--disable-dev-shm-usage",
                    "--window-size=1600,1000",
                    format!("--user-data-dir={}", profile.path().display()),
                ],
            },
        });
        let caps = match caps {
            Value::Object(map) => map,
            _ => unreachable!("the capabilities are an object"),
        };
        let url = format!("http://127.0.0.1:{port}");
        let deadline = Instant::now() + Duration::from_secs(20);
        let client = loop {
            match ClientBuilder::new(HttpConnector::new())
                .capabilities(caps.clone())
                .connect(&url)
                .await
            {
                Ok(client) => break client,
                Err(e) if Instant::now() > deadline => panic!("chromedriver answers: {e}"),
                Err(_) => tokio::time::sleep(Duration::from_millis(100)).await,
            }
        };
        Some(Browser {
            client,
            driver,
            _profile: profile,
        })
    }

    pub async fn close(self) {
        let _ = self.client.clone().close().await;
    }

    pub async fn goto(&self, url: &str) {
        self.client.goto(url).await.expect("the page opens");
    }

    pub async fn js(&self, script: &str) -> Value {
        self.client
            .execute(script, vec![])
            .await
            .unwrap_or_else(|e| panic!("script `{script}`: {e}"))
    }

    pub async fn click(&self, css: &str) {
        let element = self.element(css).await;
        self.bring_into_view(css).await;
        element
            .click()
            .await
            .unwrap_or_else(|e| panic!("click {css}: {e}"));
    }

    /// A node of a tree drawing outside its view is brought into it, as a person pans to
    /// a node before clicking it (a drawing at a legible zoom is larger than its view).
    pub async fn bring_into_view(&self, css: &str) {
        self.client
            .execute(
                "const g = document.querySelector(arguments[0])?.closest('g.node');
                 const box = g?.closest('.tree-drawing');
                 if (!g || !box) return;
                 const r = g.getBoundingClientRect(), v = box.getBoundingClientRect();
                 const inside = r.left >= v.left && r.top >= v.top && r.right <= v.right && r.bottom <= v.bottom;
                 if (!inside) box.treeDrawing.reveal(Number(g.dataset.index));",
                vec![json!(css)],
            )
            .await
            .unwrap_or_else(|e| panic!("bring {css} into view: {e}"));
    }

    pub async fn element(&self, css: &str) -> fantoccini::elements::Element {
        self.client
            .wait()
            .at_most(Duration::from_secs(10))
            .for_element(Locator::Css(css))
            .await
            .unwrap_or_else(|e| panic!("no element {css}: {e}"))
    }

    pub async fn count(&self, css: &str) -> usize {
        self.client
            .find_all(Locator::Css(css))
            .await
            .map(|v| v.len())
            .unwrap_or(0)
    }

    pub async fn attr(&self, css: &str, name: &str) -> Option<String> {
        self.element(css)
            .await
            .attr(name)
            .await
            .expect("an attribute read")
    }

    /// Waits until `script` (an expression) is truthy; returns its value.
    pub async fn until(&self, what: &str, script: &str) -> Value {
        let deadline = Instant::now() + Duration::from_secs(10);
        loop {
            let v = self.js(&format!("return {script};")).await;
            if !matches!(v, Value::Null | Value::Bool(false)) && v != json!("") && v != json!(0) {
                return v;
            }
            if Instant::now() > deadline {
                panic!("timed out waiting for {what} ({script})");
            }
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
    }

    pub async fn shown_tick(&self) -> u64 {
        self.js("return Number(document.querySelector('[data-tick]').dataset.tick);")
            .await
            .as_u64()
            .expect("the tick shown is a number")
    }
}

/// Moves the replay's timeline to step `p` as a dragged slider does; returns each node's
impl Drop for Browser {
    // Also when a test fails: chromedriver ends the browser it started when it ends.
    fn drop(&mut self) {
        let _ = self.driver.kill();
        let _ = self.driver.wait();
    }
}

/// The program named by the variable `var`, else `name` as found on `PATH` (Debian puts
/// both in /usr/bin), else /usr/bin/`name` (missing: the tests skip).
fn tool(var: &str, name: &str) -> PathBuf {
    if let Some(path) = std::env::var_os(var) {
        return PathBuf::from(path);
    }
    std::env::var_os("PATH")
        .iter()
        .flat_map(std::env::split_paths)
        .map(|dir| dir.join(name))
        .find(|p| p.is_file())
        .unwrap_or_else(|| Path::new("/usr/bin").join(name))
}

fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("a free port")
}
