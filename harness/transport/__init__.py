"""Transports: how the runner reaches an IUT. :func:`make_factory` turns an ``--iut`` URL
into a factory that gives the runner a transport for each case."""

from __future__ import annotations

import re
import shutil
import sys
import tempfile
import threading
import time
from typing import Any, Callable

from .. import priority
from .base import (BREAK, CHAR_ERROR, RESTART, SETUPS, STATUS, CloseInfo, IUTDied, Transport,
                   TransportError)

SCHEMES = ("exec:COMMAND, pty:COMMAND (with {port}), sim:[?options], a pyserial URL (rfc2217://HOST:PORT, "
           "socket://HOST:PORT, ...) or a device path (/dev/ttyUSB0)")


class Factory:
    """Gives the runner a transport for each case. ``capabilities`` and ``virtual`` are
    known without creating one; ``shutdown()`` releases what persists across cases."""

    capabilities: frozenset[str] = frozenset()
    virtual = False
    #: how many cases can run at the same time on what this factory reaches: 1 for one line
    #: (a device, a port server); any number where each case gets an IUT of its own
    concurrency = 1
    #: the ``--iut`` URL it was made from (names the device in a pool's reports)
    url = ""

    def __init__(self, make, capabilities: frozenset[str], virtual: bool = False, shutdown=None,
                 concurrency: int = 1):
        self._make = make
        self.capabilities = capabilities
        self.virtual = virtual
        self._shutdown = shutdown
        self.concurrency = concurrency

    def __call__(self, vector, params: Any) -> Transport:
        return self._make(vector, params)

    def shutdown(self) -> None:
        if self._shutdown is not None:
            self._shutdown()


class ProcessFactory(Factory):
    """Starts a fresh IUT process per case. Processes are started ahead: ``prespawn`` of the
    plain command while the current case runs, so their start-up overlaps its waits, and
    the next case's own when the runner announces it (:meth:`prepare`) and it needs a
    command of its own (a setup, a request script). A process handed out is the caller's
    to close; one started ahead and not used within ``max_idle`` seconds is stopped and
    replaced (30 s: longer than a case at the manual's default timers takes, so a run never
    throws a process away, and a bound on how long one can wait for nothing), and
    :meth:`release` stops every one started ahead (a caller that pauses, such as the fuzzer
    between rounds), so that none outlives its use. Its methods may be called from several
    threads at once (``ptpcert run --jobs``): each case gets a process of its own."""

    def __init__(self, cls, command: str, parmrk: bool, status: bool, prespawn: int = 2,
                 command_for: Callable[[Any, str], str | None] | None = None,
                 start_ahead: Callable[[Any], bool] | None = None, max_idle: float = 30.0):
        self.cls, self.command, self.parmrk, self.status = cls, command, parmrk, status
        probe = cls(command, parmrk=parmrk, status=status)
        super().__init__(None, probe.capabilities | ({SETUPS} if command_for else frozenset()),
                         concurrency=sys.maxsize)
        self.prespawn = int(prespawn)
        self.max_idle = max_idle
        self._command_for = command_for
        self._start_ahead = start_ahead
        self._ready: dict[str, list[tuple[float, Transport]]] = {}
        self._workdir: str | None = None
        self._plain: str | None = None
        self._lock = threading.RLock()
        self._starting = 0   # processes being started ahead by some thread

    @property
    def plain(self) -> str:
        """The command as a case without needs of its own runs it: the template as the
        procedure completes it (e.g. with an empty RK 512 request script)."""
        with self._lock:
            if self._plain is None:
                plain = self.command
                if self._command_for is not None:
                    plain = self._command_for(None, self.workdir) or self.command
                self._plain = plain
            return self._plain

    @property
    def workdir(self) -> str:
        """A private directory for the files per-case commands need (request scripts)."""
        with self._lock:
            if self._workdir is None:
                self._workdir = tempfile.mkdtemp(prefix="ptpcert-iut-")
            return self._workdir

    def command_for(self, vector) -> str:
        if vector is None or self._command_for is None:
            return self.plain
        with self._lock:   # a request script is written once, whole, before any process reads it
            cmd = self._command_for(vector, self.workdir)
        if cmd is None:
            what = f"setup {vector.setup[0]!r}" if vector.setup else "what the case needs"
            raise TransportError(f"case {vector.id}: the profile has no {what}")
        return cmd

    def _started(self, command: str) -> Transport:
        t = self.cls(command, parmrk=self.parmrk, status=self.status)
        t.open()
        return t

    def _ahead(self, command: str) -> None:
        t = self._started(command)   # outside the lock: other threads take theirs meanwhile
        # its start-up must not take a CPU from the IUT under test: lowered while it waits
        proc = getattr(t, "proc", None)
        t.backgrounded = proc is not None and priority.background(proc.pid)
        with self._lock:
            self._ready.setdefault(command, []).append((time.monotonic(), t))

    def _take(self, command: str) -> Transport | None:
        stale = []
        try:
            with self._lock:
                ready = self._ready.get(command)
                while ready:
                    since, t = ready.pop(0)
                    if time.monotonic() - since <= self.max_idle:
                        return t
                    stale.append(t)   # waited too long: stopped, not kept for a case that may never come
            return None
        finally:
            for t in stale:
                t.close()

    def __call__(self, vector, params: Any) -> Transport:
        cmd = self.command_for(vector)
        t = self._take(cmd)
        if t is None:
            t = self._started(cmd)
        elif getattr(t, "backgrounded", False):
            priority.foreground(t.proc.pid)     # its case begins: the normal level again
            t.backgrounded = False
        self.reap()
        plain = self.plain
        while True:
            with self._lock:
                if len(self._ready.get(plain, ())) + self._starting >= self.prespawn:
                    break
                self._starting += 1
            try:
                self._ahead(plain)
            except TransportError:
                break
            finally:
                with self._lock:
                    self._starting -= 1
        return t

    def prepare(self, vector, params: Any) -> None:
        """The runner's next case: start its IUT now if it needs a command of its own (and
        may be started ahead: the procedure says)."""
        if self._start_ahead is not None and not self._start_ahead(vector):
            return
        try:
            cmd = self.command_for(vector)
        except TransportError:
            return
        with self._lock:
            if cmd == self.plain or self._ready.get(cmd):
                return
        try:
            self._ahead(cmd)
        except TransportError:
            pass

    def reap(self) -> None:
        """Stop the processes started ahead that have waited longer than ``max_idle``."""
        now = time.monotonic()
        stale = []
        with self._lock:
            for ready in self._ready.values():
                for item in [x for x in ready if now - x[0] > self.max_idle]:
                    ready.remove(item)
                    stale.append(item[1])
        for t in stale:
            t.close()

    def release(self) -> None:
        """Stop every process started ahead (the caller will not start a case soon)."""
        with self._lock:
            stale = [item[1] for ready in self._ready.values() for item in ready]
            for ready in self._ready.values():
                ready.clear()
        for t in stale:
            t.close()

    def alive(self) -> int:
        """How many processes started ahead are waiting."""
        with self._lock:
            return sum(len(r) for r in self._ready.values())

    def shutdown(self) -> None:
        self.release()
        self._ready.clear()
        if self._workdir is not None:
            shutil.rmtree(self._workdir, ignore_errors=True)
            self._workdir = None


def sim_factory(procedure, options: dict[str, str] | None = None, *, readings=None,
                url: str = "sim:") -> Factory:
    """The one builder of ``sim:`` transports: the procedure's model plays the IUT in
    virtual time, set up by ``options`` (the sim: URL's query: app, mutant, and the
    procedure's own, e.g. 3964's priority and buffer) and, where given, other ``readings``
    of the manual's open points."""
    from .sim import SimTransport

    options = dict(options or {})
    caps, _ = procedure.sim_options(options)

    def make(vector, params):
        params = procedure.sim_params(params, options)
        if vector is not None:
            options_ = dict(options)
            host_factory = lambda p: procedure.sim_host(p, vector, options_, readings)  # noqa: E731
            tester = procedure.tester_params(params, vector.tester_params)
        else:
            host_factory = lambda p: procedure.sim_host(p, None, options, readings)  # noqa: E731
            tester = params
        return SimTransport(params, host_factory, url=url, char_time=procedure.char_time(params),
                            tester_char=procedure.char_time(tester))
    f = Factory(make, SimTransport.capabilities | caps, virtual=True, concurrency=sys.maxsize)
    f.url = url
    return f


_SCHEME = re.compile(r"^([A-Za-z][A-Za-z0-9+.-]*):")


def check_scheme(url: str) -> None:
    """A URL that is none of ours and no pyserial URL (``NAME://`` with a pyserial URL
    handler) is a typo (``exce:``), not a device: say which schemes there are."""
    m = _SCHEME.match(url)
    if not m:
        return   # a device path (/dev/ttyUSB0, COM3)
    scheme = m.group(1)
    if url.startswith(scheme + "://"):
        import importlib.util
        try:
            if importlib.util.find_spec(f"serial.urlhandler.protocol_{scheme.lower()}") is not None:
                return
        except (ImportError, ValueError):
            pass
    import difflib
    near = difflib.get_close_matches(scheme, ["exec", "pty", "sim", "rfc2217", "socket", "loop"], n=1)
    hint = f"did you mean {near[0]}:? " if near else ""
    raise TransportError(f"--iut {url}: unknown scheme {scheme + ':'!r}; {hint}valid: {SCHEMES}")


def make_factory(url: str, profile, *, prespawn: int = 2) -> Factory:
    """Turn an ``--iut`` URL into a :class:`Factory` for the IUT ``profile`` describes."""
    f = _make_factory(url.strip(), profile, prespawn=prespawn)
    f.url = url.strip()
    return f


def _make_factory(url: str, profile, *, prespawn: int = 2) -> Factory:
    url = url.strip()
    if not url:
        raise TransportError(f"--iut is empty; use {SCHEMES}")
    proc = profile.procedure
    parmrk = profile.line_conditions == "parmrk"
    status = profile.status_from_stderr
    if url.startswith("exec:") or url.startswith("pty:"):
        from .process import ExecTransport, PtyTransport
        scheme, cmd = url.split(":", 1)
        if scheme == "pty" and "{port}" not in cmd:
            raise TransportError(f"{url}: the command must contain {{port}}, replaced by the pty device path")

        def command_for(vector, workdir: str) -> str | None:
            return proc.command(cmd, vector, profile.setups, workdir)
        cls = ExecTransport if scheme == "exec" else PtyTransport
        return ProcessFactory(cls, cmd, parmrk, status, prespawn, command_for, proc.start_ahead)
    if url.startswith("sim:"):
        from .sim import parse_sim_url
        # the IUT the profile declares, unless the URL's options say otherwise
        opts = {"app": proc.profile_app(profile), **parse_sim_url(url)}
        try:
            proc.sim_options(dict(opts))
        except ValueError as exc:
            raise TransportError(f"{url}: {exc}") from None
        return sim_factory(proc, opts, url=url)
    check_scheme(url)
    from .serialport import SerialTransport
    shared = SerialTransport(url, profile.line)
    shared.open()
    return Factory(lambda v, p: shared, shared.capabilities, shutdown=shared.shutdown)


__all__ = ["BREAK", "CHAR_ERROR", "RESTART", "SETUPS", "STATUS", "CloseInfo", "IUTDied", "Transport",
           "TransportError", "make_factory", "preflight", "sim_factory", "SCHEMES", "Factory", "ProcessFactory"]


def preflight(url: str, factory, params) -> None:
    """Start the IUT once before a run: a command that cannot start, or a port that cannot
    be opened, is found before the first case (a :class:`TransportError` naming ``url`` and
    what the IUT said), not as 50 failed cases. Nothing to do where the transport does not
    start the IUT, or in virtual time."""
    if RESTART not in factory.capabilities or factory.virtual:
        return
    tr = factory(None, params)
    try:
        tr.open()
        tr.read(tr.now() + 1.0)
    except IUTDied as exc:
        what = (f"the IUT ended at start-up (exit status {exc.returncode})" if exc.returncode is not None
                else f"at start-up, {exc}")
        raise TransportError(f"{url}: {what}"
                             + (f": {exc.stderr_tail.strip()[-600:]}" if exc.stderr_tail.strip() else "")) from None
    finally:
        tr.close()
