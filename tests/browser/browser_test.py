#!/usr/bin/python3
"""The viewer in a real browser: Debian's headless chromium loads the page of a running
`pyramid serve` (or of one this script starts) and waits for its tiles.

  browser_test.py URL [--out DIR]
  browser_test.py --serve 'pyramid serve cone.dat --port 0' [--out DIR]

With --serve the command's first line on stdout must be `pyramid serve: http://HOST:PORT/`;
the server is stopped at the end. The pyramid must be a cone (a single peak in the middle of
the root quad) without ortho, for the hillshade checks (--no-hillshade skips them), such as
  make_cone.py cone.tif && preprocessDem cone.tif -o cone/DEM.dat --scale 0.05

Checks, for each page load (the start view, with orbit then fly controls, then `?view=top`
lit from the north-west, then from the south-east), once the status element says data-idle="true":
  * (start view) the F key switches to the fly controls and back;
  * data-errors, data-failed are 0 and data-loaded > 0; every tile the page requested is
    answered 200 (404 with --allow-absent), as seen by the browser's network events, and as many
    as the page counted; no console error, no uncaught exception;
  * top views: most of the screenshot differs from the page's background; the cone's flanks
    toward the light are brighter than the opposite flanks (west vs east, north vs south, in
    the sectors of a ring around the peak).
Screenshots go to --out (default ./browser-test-out). Exit status 0 when everything passes.
"""

import argparse
import math
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cdp  # noqa: E402
import png  # noqa: E402

BACKGROUND = (0x10, 0x18, 0x20)  # web/viewer.js's BACKGROUND
STATUS = "JSON.stringify(Object.assign({text: document.getElementById('status').textContent}, " \
         "document.getElementById('status').dataset))"


class Failure(Exception):
    pass


def start_server(command, timeout=30):
    process = subprocess.Popen(command, shell=True, stdout=subprocess.PIPE,
                               start_new_session=True, text=True)
    lines = []
    reader = threading.Thread(target=lambda: [lines.append(l) for l in process.stdout], daemon=True)
    reader.start()
    deadline = time.monotonic() + timeout
    while not lines and time.monotonic() < deadline and process.poll() is None:
        time.sleep(0.05)
    match = re.match(r"pyramid serve: (https?://\S+)", lines[0]) if lines else None
    if not match:
        stop_server(process)
        raise Failure("the server's first line is not 'pyramid serve: URL': %r" % lines[:1])
    return process, match.group(1)


def wait_answering(base, timeout=15):
    """Waits until the server answers its pyramid.json (200), so that the page's load is not
    the first request of a server still starting."""
    import urllib.request
    deadline = time.monotonic() + timeout
    while True:
        try:
            with urllib.request.urlopen(base + "api/pyramid.json", timeout=5) as answer:
                if answer.status == 200:
                    return
        except OSError as err:
            if time.monotonic() > deadline:
                raise Failure("%sapi/pyramid.json: %s" % (base, err))
        time.sleep(0.1)


def stop_server(process):
    if process.poll() is None:
        os.killpg(process.pid, signal.SIGTERM)
        try:
            process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()


def wait_idle(page, timeout):
    """Polls the status element until it has said idle twice in a row; returns its data."""
    import json
    deadline = time.monotonic() + timeout
    idle_before, status = False, None
    while time.monotonic() < deadline:
        try:
            value = page.evaluate(STATUS)
        except cdp.Error:
            value = None  # the page is still loading
        status = json.loads(value) if value else None
        idle = bool(status) and status.get("idle") == "true"
        if idle and idle_before:
            return status
        idle_before = idle
        page.browser.drain(0.25)
    raise Failure("not idle after %g s: %s" % (timeout, status))


def check_load(page, url, status, allow_absent):
    problems = []
    if status["errors"] != "0":
        problems.append("data-errors=%s: %s" % (status["errors"], status["text"]))
    if status["failed"] != "0":
        problems.append("data-failed=%s" % status["failed"])
    if int(status["loaded"]) <= 0:
        problems.append("no tile loaded")
    tiles = 0
    for event in page.events():
        method, params = event["method"], event.get("params", {})
        if method == "Network.responseReceived":
            response = params["response"]
            is_tile = "/tiles/" in response["url"]
            tiles += is_tile
            if response["status"] != 200 and not (allow_absent and is_tile and response["status"] == 404):
                problems.append("HTTP %d for %s" % (response["status"], response["url"]))
        elif method == "Runtime.exceptionThrown":
            problems.append("exception: %s" % params["exceptionDetails"].get("text"))
        elif method == "Runtime.consoleAPICalled" and params["type"] in ("error", "assert"):
            problems.append("console.%s: %s" % (params["type"], [a.get("value") for a in params["args"]]))
        elif method == "Log.entryAdded" and params["entry"]["level"] == "error":
            entry = params["entry"]
            if not (allow_absent and "404" in entry.get("text", "") and "/tiles/" in entry.get("url", "")):
                problems.append("log: %s %s" % (entry.get("text"), entry.get("url", "")))
    if tiles != int(status["requested"]):
        problems.append("the page counted %s tile requests, the browser saw %d answers"
                        % (status["requested"], tiles))
    if problems:
        raise Failure("%s:\n  %s" % (url, "\n  ".join(problems)))
    return tiles


def check_toggle(page):
    """The F key switches to the fly controls and back (the status text names them)."""
    modes = []
    for expected in ("fly", "orbit"):
        for kind in ("keyDown", "keyUp"):
            page.call("Input.dispatchKeyEvent", {"type": kind, "key": "f", "code": "KeyF",
                                                 "windowsVirtualKeyCode": 70})
        deadline = time.monotonic() + 10  # the status shows it after the next frame is drawn
        while True:
            text = page.evaluate("document.getElementById('status').textContent")
            mode = "fly" if ", fly," in text else "orbit" if ", orbit," in text else text
            if mode == expected or time.monotonic() > deadline:
                break
            page.browser.drain(0.1)
        modes.append(mode)
    if modes != ["fly", "orbit"]:
        raise Failure("the F key gave the controls %s, not fly then orbit" % modes)
    errors = page.evaluate("document.getElementById('status').dataset.errors")
    if errors != "0":
        raise Failure("data-errors=%s after switching the controls" % errors)
    return "F: fly, orbit"


def sectors(path):
    """Mean brightness of the terrain's four sectors (east, north, west, south) in a ring around
    the centre of the terrain's pixels, and the terrain's share of the image."""
    width, height, channels, rows = png.decode(open(path, "rb").read())
    mask = []
    for y in range(0, height, 2):
        row = rows[y]
        for x in range(0, width, 2):
            p = row[x * channels:x * channels + 3]
            if max(abs(p[c] - BACKGROUND[c]) for c in range(3)) > 12:
                mask.append((x, y, (p[0] + p[1] + p[2]) / 3))
    share = len(mask) / ((width // 2) * (height // 2))
    if not mask:
        return share, None
    xs = [m[0] for m in mask]
    ys = [m[1] for m in mask]
    cx, cy = (min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2
    half = max(max(xs) - min(xs), max(ys) - min(ys)) / 2
    sums, counts = [0.0] * 4, [0] * 4
    for x, y, lum in mask:
        r = math.hypot(x - cx, y - cy)
        if 0.1 * half <= r <= 0.45 * half:
            angle = math.degrees(math.atan2(cy - y, x - cx))  # screen north up
            sector = int(((angle + 45) % 360) // 90)          # 0 east, 1 north, 2 west, 3 south
            sums[sector] += lum
            counts[sector] += 1
    if min(counts) == 0:
        return share, None
    return share, [s / c for s, c in zip(sums, counts)]


def check_hillshade(path, lit):
    """lit: 'north-west' or 'south-east', where the light comes from."""
    share, means = sectors(path)
    if share < 0.1:
        raise Failure("%s: only %.1f %% of the pixels differ from the background" % (path, 100 * share))
    if means is None:
        raise Failure("%s: the terrain does not surround its centre" % path)
    east, north, west, south = means
    margin = 8
    bright = (west, north) if lit == "north-west" else (east, south)
    dark = (east, south) if lit == "north-west" else (west, north)
    if not (bright[0] > dark[0] + margin and bright[1] > dark[1] + margin):
        raise Failure("%s: lit from the %s, yet brightness E %.0f N %.0f W %.0f S %.0f"
                      % (path, lit, east, north, west, south))
    return "%.0f %% terrain; E %.0f N %.0f W %.0f S %.0f" % (100 * share, east, north, west, south)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("url", nargs="?", help="the server's URL, e.g. http://127.0.0.1:8080/")
    parser.add_argument("--serve", help="a command starting the server (first stdout line: its URL)")
    parser.add_argument("--out", default="browser-test-out", help="where the screenshots go")
    parser.add_argument("--chromium", default=os.environ.get("CHROMIUM", "chromium"))
    parser.add_argument("--timeout", type=float, default=40, help="seconds per page to become idle")
    parser.add_argument("--size", default="800x600", help="the window, WIDTHxHEIGHT")
    parser.add_argument("--allow-absent", action="store_true", help="404 tiles are fine (sparse)")
    parser.add_argument("--no-hillshade", action="store_true", help="skip the cone's checks")
    parser.add_argument("--extra", action="append", default=[], metavar="QUERY",
                        help="one more load, e.g. 'view=top&exaggeration=3' (status checks only)")
    args = parser.parse_args()
    if bool(args.url) == bool(args.serve):
        parser.error("give either URL or --serve CMD")
    binary = shutil.which(args.chromium)
    if not binary:
        print("browser_test: no %s (apt-get install chromium)" % args.chromium, file=sys.stderr)
        return 77  # ctest's SKIP_RETURN_CODE convention
    width, height = (int(v) for v in args.size.split("x"))
    os.makedirs(args.out, exist_ok=True)
    started = time.monotonic()
    server, url = (None, args.url)
    profile = tempfile.mkdtemp(prefix="browser-test-profile-")
    browser = None
    try:
        if args.serve:
            server, url = start_server(args.serve)
        base = url.rstrip("/") + "/"
        wait_answering(base)
        browser = cdp.Browser(binary, profile, os.path.join(args.out, "chromium.log"))
        page = cdp.Page(browser, width, height)
        loads = [("start", "", None), ("fly", "?controls=fly", None)]
        if not args.no_hillshade:
            loads += [("top", "?view=top&status=hidden", "north-west"),
                      ("top-light-se", "?view=top&status=hidden&light=135,45", "south-east")]
        loads += [("extra-%d" % i, "?" + q, None) for i, q in enumerate(args.extra, 1)]
        for name, query, lit in loads:
            page.navigate(base + query)
            status = wait_idle(page, args.timeout)
            tiles = check_load(page, base + query, status, args.allow_absent)
            shot = os.path.join(args.out, name + ".png")
            with open(shot, "wb") as f:
                f.write(page.screenshot())
            note = check_hillshade(shot, lit) if lit else ""
            if name == "start":
                note = check_toggle(page)
            print("ok %s: %d tiles, idle, no errors; %s %s" % (name, tiles, shot, note))
    except (Failure, cdp.Error) as err:
        print("FAIL %s" % err, file=sys.stderr)
        return 1
    finally:
        if browser:
            browser.close()
        if server:
            stop_server(server)
        shutil.rmtree(profile, ignore_errors=True)
    print("browser test passed in %.1f s" % (time.monotonic() - started))
    return 0


if __name__ == "__main__":
    sys.exit(main())
