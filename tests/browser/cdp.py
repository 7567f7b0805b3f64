"""A headless chromium driven over the DevTools protocol on a pipe (--remote-debugging-pipe):
no websocket library needed, Debian's python3 only.

Chromium reads commands from its fd 3 and writes answers and events to its fd 4, each message a
JSON object followed by a NUL byte.
"""

import base64
import fcntl
import json
import os
import select
import subprocess
import time

# The flags, and why:
# --headless: no display.
# --no-sandbox: chromium refuses to run as root (CI containers) with its sandbox.
# --use-angle=swiftshader --enable-unsafe-swiftshader: WebGL on the CPU through ANGLE's
#   SwiftShader (Vulkan) backend, no GPU needed; chromium 156 picks it without flags too, the
#   second flag keeps it where chromium stops falling back to SwiftShader for WebGL by itself.
#   (--use-gl=egl and --use-angle=gl, on Mesa, give no WebGL context.)
# --remote-debugging-pipe: the protocol on fds 3 and 4.
FLAGS = [
    "--headless",
    "--no-sandbox",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--remote-debugging-pipe",
    "--no-first-run",
    "--no-default-browser-check",
    "--disable-extensions",
    "--disable-background-networking",
    "--mute-audio",
    "--hide-scrollbars",
]


class Error(Exception):
    pass


class Browser:
    def __init__(self, binary, user_data_dir, log_path):
        to_child_r, self._to_child = os.pipe()
        self._from_child, from_child_w = os.pipe()
        # The child's fds 3 and 4, set in the child; the pipe ends are first moved above 10 so
        # that neither is overwritten by the other's dup2. Python's own fds are close-on-exec, so
        # close_fds=False leaks nothing else.
        def wire():
            command = fcntl.fcntl(to_child_r, fcntl.F_DUPFD, 10)
            answers = fcntl.fcntl(from_child_w, fcntl.F_DUPFD, 10)
            os.dup2(command, 3)
            os.dup2(answers, 4)
        self._log = open(log_path, "wb")
        self.process = subprocess.Popen(
            [binary] + FLAGS + ["--user-data-dir=" + user_data_dir, "about:blank"],
            stdin=subprocess.DEVNULL, stdout=self._log, stderr=self._log,
            preexec_fn=wire, close_fds=False)  # closing would come after wire()
        os.close(to_child_r)
        os.close(from_child_w)
        self._buffer = b""
        self._next_id = 0
        self.events = []

    def _send(self, message):
        data = json.dumps(message).encode() + b"\0"
        while data:
            written = os.write(self._to_child, data)
            data = data[written:]

    def _read(self, deadline):
        while b"\0" not in self._buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                raise Error("no answer from chromium in time")
            ready, _, _ = select.select([self._from_child], [], [], left)
            if ready:
                chunk = os.read(self._from_child, 1 << 20)
                if not chunk:
                    raise Error("chromium closed its pipe (exit code %s)" % self.process.poll())
                self._buffer += chunk
        message, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(message)

    def call(self, method, params=None, session=None, timeout=30):
        """Sends a command and returns its result; events met meanwhile go to self.events."""
        self._next_id += 1
        message = {"id": self._next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        self._send(message)
        deadline = time.monotonic() + timeout
        while True:
            answer = self._read(deadline)
            if answer.get("id") == self._next_id:
                if "error" in answer:
                    raise Error("%s: %s" % (method, answer["error"]))
                return answer.get("result", {})
            if "method" in answer:
                self.events.append(answer)

    def drain(self, seconds):
        """Collects the events arriving in the next `seconds`."""
        deadline = time.monotonic() + seconds
        try:
            while True:
                self.events.append(self._read(deadline))
        except Error as err:
            if "in time" not in str(err):
                raise

    def close(self):
        try:
            self.call("Browser.close", timeout=5)
        except (Error, OSError):
            pass
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        os.close(self._to_child)
        os.close(self._from_child)
        self._log.close()


class Page:
    """A tab of a given size, with the events of its runtime, log and network enabled."""

    def __init__(self, browser, width, height):
        self.browser = browser
        target = browser.call("Target.createTarget", {"url": "about:blank"})["targetId"]
        self.session = browser.call("Target.attachToTarget",
                                    {"targetId": target, "flatten": True})["sessionId"]
        for domain in ("Runtime", "Log", "Network", "Page"):
            self.call(domain + ".enable")
        # Every load asks the server again: its answers are what is tested (no 304, no cache).
        self.call("Network.setCacheDisabled", {"cacheDisabled": True})
        self.call("Emulation.setDeviceMetricsOverride",
                  {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False})

    def call(self, method, params=None, timeout=30):
        return self.browser.call(method, params, session=self.session, timeout=timeout)

    def navigate(self, url):
        self.browser.events = []
        result = self.call("Page.navigate", {"url": url})
        if result.get("errorText"):
            raise Error("cannot load %s: %s" % (url, result["errorText"]))

    def evaluate(self, expression):
        result = self.call("Runtime.evaluate", {"expression": expression, "returnByValue": True})
        if "exceptionDetails" in result:
            raise Error("%s: %s" % (expression, result["exceptionDetails"]))
        return result["result"].get("value")

    def screenshot(self):
        return base64.b64decode(self.call("Page.captureScreenshot", {"format": "png"})["data"])

    def events(self):
        return [e for e in self.browser.events if e.get("sessionId") == self.session]
