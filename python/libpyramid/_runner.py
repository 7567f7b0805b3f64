"""Running an encoding so that Ctrl-C stops it cleanly.

A C encode call runs in a worker thread while the calling thread waits in short waits. A
KeyboardInterrupt in the caller sets a flag that the C API's cancel callback reads (it is called
after every tile), the C call returns PYRAMID_ERROR_CANCELLED having left no file behind, and the
KeyboardInterrupt is raised again. An installed program (encoding from input files) is stopped the
same way, with SIGINT, which makes it remove its outputs and exit 130.
"""

import json
import signal
import subprocess
import threading

from . import _capi
from ._errors import CancelledError, Error, from_status


class Call:
    """One C encode call: its progress and cancel callbacks, and the caller's callables."""

    def __init__(self, lib, progress=None, cancel=None):
        self.lib = lib
        self.interrupted = False    # set on KeyboardInterrupt
        self.user_cancelled = False
        self.errors = []            # exceptions raised by the caller's callables, first first
        self._progress = progress
        self._cancel = cancel
        # The ctypes callbacks; kept alive as attributes for as long as the call runs.
        self.c_progress = _capi.PROGRESS_FN(self._on_progress)
        self.c_cancel = _capi.CANCEL_FN(self._on_cancel)

    def fail(self, exc):
        """Records an exception of a caller's callable; the call stops at the next tile."""
        self.errors.append(exc)

    def _on_progress(self, user, done, total):
        if self._progress is not None and not self.errors:
            try:
                self._progress(done, total)
            except BaseException as e:  # noqa: B902 - carried to the caller's thread
                self.fail(e)

    def _on_cancel(self, user):
        if self.interrupted or self.errors:
            return 1
        if self._cancel is not None:
            try:
                if self._cancel():
                    self.user_cancelled = True
                    return 1
            except BaseException as e:  # noqa: B902
                self.fail(e)
                return 1
        return 0

    def run(self, fn, *args):
        """Runs fn(*args) (a C call returning a status) in a worker thread; raises what it
        should: KeyboardInterrupt, a callable's exception, CancelledError or Error."""
        result = {}
        done = threading.Event()

        def target():
            try:
                status = fn(*args)
                result["status"] = status
                if status != _capi.OK:  # the message is thread-local: read it here
                    result["message"] = self.lib.pyramid_last_error().decode("utf-8", "replace")
            except BaseException as e:  # noqa: B902
                result["exception"] = e
            finally:
                done.set()

        worker = threading.Thread(target=target, name="libpyramid-encode", daemon=True)
        worker.start()
        interrupt = None
        while not done.is_set():
            try:
                done.wait(0.05)
            except KeyboardInterrupt as e:
                interrupt = interrupt or e
                self.interrupted = True
        worker.join()
        if interrupt is not None:
            raise interrupt
        if "exception" in result:
            raise result["exception"]
        if self.errors:
            raise self.errors[0]
        status = result["status"]
        if status != _capi.OK:
            raise from_status(status, self.lib, result.get("message"))


def run_program(args, progress=None, cancel=None):
    """Runs an installed program with ``--report -``; returns its report (a dict).

    Its JSON progress lines (``--progress json``) go to `progress`; `cancel` is polled. On
    KeyboardInterrupt or cancel the program gets SIGINT (it removes what it wrote) and the
    interrupt (or CancelledError) is raised once it has exited.
    """
    args = list(args) + ["--report", "-"] + (["--progress", "json"] if progress else ["--quiet"])
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    lines = []
    errors = []

    def read_stderr():
        for line in proc.stderr:
            if progress and line.startswith('{"progress"'):
                try:
                    p = json.loads(line)
                    progress(p["done"], p["total"])
                except BaseException as e:  # noqa: B902
                    errors.append(e)
                continue
            lines.append(line.rstrip("\n"))

    reader = threading.Thread(target=read_stderr, daemon=True)
    reader.start()
    out = []
    stdout_reader = threading.Thread(target=lambda: out.append(proc.stdout.read()), daemon=True)
    stdout_reader.start()
    interrupt = None
    cancelled = False
    while True:
        try:
            if proc.poll() is not None:
                break
            if not cancelled and (errors or (cancel is not None and cancel())):
                cancelled = True
                proc.send_signal(signal.SIGINT)
            proc.wait(0.05)
        except subprocess.TimeoutExpired:
            continue
        except KeyboardInterrupt as e:
            interrupt = interrupt or e
            if proc.poll() is None:
                proc.send_signal(signal.SIGINT)
    reader.join()
    stdout_reader.join()
    if interrupt is not None:
        raise interrupt
    if errors:
        raise errors[0]
    if cancelled:
        raise CancelledError(f"{args[0]}: cancelled", _capi.ERROR_CANCELLED, "cancelled")
    if proc.returncode != 0:
        message = lines[-1] if lines else f"{args[0]} exited with {proc.returncode}"
        status = _capi.ERROR_ARGUMENT if proc.returncode == 2 else _capi.ERROR_FILE
        raise from_status(status, message=message)
    try:
        return json.loads(out[0])
    except (ValueError, IndexError):
        raise Error(f"{args[0]}: unreadable report") from None
