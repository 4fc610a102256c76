//! A headless Chromium driven through chromedriver (WebDriver, with `fantoccini`), for the
//! browser tests (`browser.rs`, `browser_rewind.rs`).
//!
//! Without a browser (no `chromium` and `chromedriver` on `PATH`, or at the paths in
//! `NEUROTREE_CHROMIUM` and `NEUROTREE_CHROMEDRIVER`) [`Browser::start`] prints a note and
//! gives `None`; with `NEUROTREE_REQUIRE_BROWSER=1` (as `.ci/run` sets) it fails instead.
//!
//! A browser takes a second to start, as long as many tests take to run: a test that passes
//! gives its browser back ([`Browser::close`]) on a blank page, with the window as it started
//! and no storage or cookies left, and the next test takes it. A test that fails ends its
//! browser; the browsers left when the tests end are ended as the process exits.

#![allow(dead_code)]

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{LazyLock, Mutex, Once};
use std::time::{Duration, Instant};

use fantoccini::{Client, ClientBuilder, Locator};
use hyper_util::client::legacy::connect::HttpConnector;
use serde_json::{json, Value};

pub struct Browser {
    pub client: Client,
    /// `None` once given back or ended.
    session: Option<Session>,
}

/// What a browser is beside its client: the chromedriver that started it, its profile
/// folder, and its window as it started.
struct Session {
    client: Client,
    driver: Child,
    /// chromedriver's port, and the session's id there.
    port: u16,
    id: String,
    _profile: tempfile::TempDir,
    /// x, y, width and height.
    window: (u64, u64, u64, u64),
}

impl Session {
    /// Ends the session, which closes its browser (killing chromedriver alone would leave
    /// the browser running), then chromedriver. Blocking: this runs in `Drop` and at exit.
    fn end(mut self) {
        if let Ok(mut http) = TcpStream::connect(("127.0.0.1", self.port)) {
            let _ = http.set_read_timeout(Some(Duration::from_secs(5)));
            let _ = write!(
                http,
                "DELETE /session/{} HTTP/1.1\r\nHost: 127.0.0.1:{}\r\nConnection: close\r\n\r\n",
                self.id, self.port
            );
            let _ = http.read_to_end(&mut Vec::new());
        }
        let _ = self.driver.kill();
        let _ = self.driver.wait();
    }
}

/// Browsers given back by passing tests, for the next tests.
static IDLE: Mutex<Vec<Session>> = Mutex::new(Vec::new());

/// Where the browsers' WebDriver connections run: a runtime kept for the whole process,
/// since each test's own runtime ends with the test, and a browser outlives it.
static CONNECTIONS: LazyLock<tokio::runtime::Runtime> = LazyLock::new(|| {
    tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .expect("a runtime for the WebDriver connections")
});

extern "C" {
    fn atexit(callback: extern "C" fn()) -> std::ffi::c_int;
}

/// Ends the idle browsers as the process exits (the test harness exits without dropping
/// statics).
extern "C" fn end_idle_browsers() {
    if let Ok(mut idle) = IDLE.lock() {
        idle.drain(..).for_each(Session::end);
    }
}

impl Browser {
    /// A headless chromium through a chromedriver of its own (an idle one if there is one),
    /// or `None` (with a note) when there is none and none is required.
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
        let idle = IDLE.lock().unwrap().pop();
        let session = match idle {
            Some(session) => session,
            None => Self::launch(chromium, driver).await,
        };
        Some(Browser {
            client: session.client.clone(),
            session: Some(session),
        })
    }

    async fn launch(chromium: PathBuf, driver: PathBuf) -> Session {
        static AT_EXIT: Once = Once::new();
        // SAFETY: `atexit` is given a function with the C ABI that takes and returns nothing.
        AT_EXIT.call_once(|| assert_eq!(unsafe { atexit(end_idle_browsers) }, 0));
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
        let connect = async move {
            let deadline = Instant::now() + Duration::from_secs(20);
            loop {
                match ClientBuilder::new(HttpConnector::new())
                    .capabilities(caps.clone())
                    .connect(&url)
                    .await
                {
                    Ok(client) => break client,
                    Err(e) if Instant::now() > deadline => panic!("chromedriver answers: {e}"),
                    Err(_) => tokio::time::sleep(Duration::from_millis(100)).await,
                }
            }
        };
        let client = match CONNECTIONS.spawn(connect).await {
            Ok(client) => client,
            Err(e) => std::panic::resume_unwind(e.into_panic()),
        };
        let window = client.get_window_rect().await.expect("the window's size");
        let id = client
            .session_id()
            .await
            .expect("a session id")
            .expect("a session");
        Session {
            client,
            driver,
            port,
            id,
            _profile: profile,
            window,
        }
    }

    /// Gives the browser back for the next test, as it started; ends it if that fails.
    pub async fn close(mut self) {
        let Some(session) = self.session.take() else {
            return;
        };
        let c = &session.client;
        let (x, y, width, height) = session.window;
        let reset = async {
            c.execute("localStorage.clear(); sessionStorage.clear();", vec![])
                .await?;
            c.delete_all_cookies().await?;
            c.goto("about:blank").await?;
            let size = |n: u64| u32::try_from(n).unwrap_or(u32::MAX);
            c.set_window_rect(size(x), size(y), size(width), size(height))
                .await?;
            Ok::<_, fantoccini::error::CmdError>(())
        };
        match reset.await {
            Ok(()) => IDLE.lock().unwrap().push(session),
            Err(_) => session.end(),
        }
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

    /// Clicks the element, brought into view first. A panel that is still filling in can
    /// move it between the two, so that the click lands on what took its place: the element
    /// is then brought into view and clicked again, as a person would, a few times.
    pub async fn click(&self, css: &str) {
        let mut tries = 0;
        loop {
            let element = self.element(css).await;
            self.bring_into_view(css).await;
            match element.click().await {
                Ok(()) => return,
                Err(e) if tries < 5 && moved(&e) => {
                    tries += 1;
                    tokio::time::sleep(Duration::from_millis(100)).await;
                }
                Err(e) => {
                    let seen = self.describe(css).await;
                    panic!("click {css}: {e}; the element: {seen}")
                }
            }
        }
    }

    /// Where the element is and what hides it, for a click that failed.
    async fn describe(&self, css: &str) -> Value {
        self.client
            .execute(
                "const el = document.querySelector(arguments[0]);
                 if (!el) return 'gone';
                 const r = el.getBoundingClientRect(), s = getComputedStyle(el);
                 const hidden = [];
                 for (let p = el; p; p = p.parentElement) {
                   const ps = getComputedStyle(p);
                   if (ps.display === 'none' || ps.visibility === 'hidden' || p.hidden || (p.tagName === 'DETAILS' && !p.open))
                     hidden.push(p.tagName + '.' + p.className + '#' + p.id);
                 }
                 const at = document.elementFromPoint(r.left + r.width / 2, r.top + r.height / 2);
                 return {rect: [r.left, r.top, r.width, r.height], display: s.display, visibility: s.visibility,
                         disabled: el.disabled, hidden, at: at && (at.tagName + '.' + at.className),
                         view: [innerWidth, innerHeight]};",
                vec![json!(css)],
            )
            .await
            .unwrap_or(Value::Null)
    }

    /// A node of a tree drawing outside its view is brought into it, as a person pans to
    /// a node before clicking it (a drawing at a legible zoom is larger than its view); any
    /// other element is scrolled into its panel's view, as a person scrolls to it.
    pub async fn bring_into_view(&self, css: &str) {
        self.client
            .execute(
                "const el = document.querySelector(arguments[0]);
                 const g = el?.closest('g.node');
                 const box = g?.closest('.tree-drawing');
                 if (!g || !box) return el?.scrollIntoView({block: 'center', inline: 'nearest'});
                 const r = g.getBoundingClientRect(), v = box.getBoundingClientRect();
                 const inside = r.left >= v.left && r.top >= v.top && r.right <= v.right && r.bottom <= v.bottom;
                 if (!inside) return box.treeDrawing.reveal(Number(g.dataset.index));",
                vec![json!(css)],
            )
            .await
            .unwrap_or_else(|e| panic!("bring {css} into view: {e}"));
    }

    /// Clicks the field `css` and types `keys` into it, as a person does. A page that
    /// redraws the field between the click and the keys (a live view refreshing) leaves the
    /// typing nowhere; the person then clicks the new field and types again, and so does
    /// this, a few times at most.
    pub async fn type_into(&self, css: &str, keys: &str) {
        let mut last = None;
        for _ in 0..5 {
            self.until(
                &format!("{css} shown"),
                &format!(
                    "(f => !!f && f.getClientRects().length > 0 && !f.disabled)(document.querySelector({}))",
                    json!(css)
                ),
            )
            .await;
            self.click(css).await;
            match self.element(css).await.send_keys(keys).await {
                Ok(()) => return,
                Err(e) => last = Some(e),
            }
        }
        panic!("typing into {css}: {last:?}");
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
    // A browser not given back (its test failed) is ended: its page may be in any state.
    fn drop(&mut self) {
        if let Some(session) = self.session.take() {
            session.end();
        }
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

/// The click landed elsewhere, or found no element to land on, because the element moved
/// or was drawn anew in between.
fn moved(e: &fantoccini::error::CmdError) -> bool {
    let text = e.to_string();
    text.contains("click intercepted")
        || text.contains("stale element")
        || text.contains("not interactable")
}
