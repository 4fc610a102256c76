"""Takes the rewind picture: `neurotree demo --studio` watched in headless Chromium through
ChromeDriver, paused, taken eight ticks back, with the warehouse scene and the blackboards.

Usage (from the repository root): python3 crates/neurotree-studio/docs/rewind_shot.py NEUROTREE OUT.png
"""

import base64
import json
import re
import subprocess
import sys
import time
import urllib.request

PORT = 9633


def call(method, url, body=None):
    data = json.dumps(body).encode() if body is not None else None
    request = urllib.request.Request(
        url, data=data, method=method, headers={"Content-Type": "application/json"}
    )
    return json.loads(urllib.request.urlopen(request, timeout=60).read())["value"]


def open_session(base):
    """A session of headless Chromium at 1500×950 through the ChromeDriver at `base`."""
    options = ["--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
               "--window-size=1500,950"]
    caps = {"capabilities": {"alwaysMatch": {"goog:chromeOptions": {"args": options}}}}
    return base + "/session/" + call("POST", base + "/session", caps)["sessionId"]


def clicker(session, view):
    """Clicks the button `[data-action=ACTION]` of VIEW's toolbar, as a person would."""
    def click(action):
        call("POST", session + "/execute/sync", {
            "script": f"document.querySelector('#{view}-view [data-action={action}]').click()",
            "args": [],
        })
    return click


def main(neurotree, out):
    driver = subprocess.Popen(
        ["chromedriver", f"--port={PORT}"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    demo = subprocess.Popen(
        [neurotree, "demo", "--studio", "0", "--speed", "1", "--max-ticks", "100000"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        url = None
        while url is None:
            line = demo.stderr.readline()
            if not line:
                sys.exit("the demo ended before it printed the studio's address")
            found = re.match(r"studio: (http\S+)", line)
            url = found and found.group(1)
        time.sleep(1)
        base = f"http://127.0.0.1:{PORT}"
        session = open_session(base)
        try:
            click = clicker(session, "watch")

            call("POST", session + "/url", {"url": url + "#view=watch"})
            time.sleep(12)
            click("pause")
            time.sleep(1.5)
            for _ in range(8):
                click("back")
                time.sleep(0.4)
            time.sleep(1)
            with open(out, "wb") as f:
                f.write(base64.b64decode(call("GET", session + "/screenshot")))
        finally:
            call("DELETE", session)
    finally:
        demo.kill()
        driver.kill()


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
