"""Takes a picture of a studio page after "fit": the page at URL in headless Chromium at
1500×950 through ChromeDriver, its panels hidden and its tree fitted in VIEW (edit, watch
or replay) with the toolbar's buttons, as a person would.

Usage (from the repository root, the studio already serving):
    python3 crates/neurotree-studio/docs/fit_shot.py URL VIEW OUT.png [SECONDS]
SECONDS (default 6) is how long the page is given to draw before the clicks.
"""

import base64
import subprocess
import sys
import time

from rewind_shot import call, clicker, open_session

PORT = 9634


def main(url, view, out, wait=6.0):
    driver = subprocess.Popen(
        ["chromedriver", f"--port={PORT}"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    try:
        time.sleep(1)
        base = f"http://127.0.0.1:{PORT}"
        session = open_session(base)
        try:
            click = clicker(session, view)

            # The page 1500×950, the window that much larger than what the browser takes.
            inner = call("POST", session + "/execute/sync", {
                "script": "return [innerWidth, innerHeight];", "args": []})
            call("POST", session + "/window/rect",
                 {"width": 3000 - inner[0], "height": 1900 - inner[1]})
            call("POST", session + "/url", {"url": url})
            time.sleep(wait)
            click("panels")
            time.sleep(0.5)
            click("fit")
            time.sleep(1)
            with open(out, "wb") as f:
                f.write(base64.b64decode(call("GET", session + "/screenshot")))
        finally:
            call("DELETE", session)
    finally:
        driver.kill()


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4]) if len(sys.argv) > 4 else 6.0)
