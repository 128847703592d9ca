"""Transports: how the runner reaches an IUT. :func:`make_factory` turns an ``--iut`` URL
into a factory that gives the runner a transport for each case."""

from __future__ import annotations

from ..model import Params3964
from .base import BREAK, CHAR_ERROR, RESTART, STATUS, CloseInfo, IUTDied, Transport, TransportError

SCHEMES = "exec:COMMAND, pty:COMMAND (with {port}), sim:[?options], or a pyserial URL / device path"


class Factory:
    """Gives the runner a transport for each case. ``capabilities`` and ``virtual`` are
    known without creating one; ``shutdown()`` releases what persists across cases."""

    capabilities: frozenset[str] = frozenset()
    virtual = False

    def __init__(self, make, capabilities: frozenset[str], virtual: bool = False, shutdown=None):
        self._make = make
        self.capabilities = capabilities
        self.virtual = virtual
        self._shutdown = shutdown

    def __call__(self, vector, params: Params3964) -> Transport:
        return self._make(vector, params)

    def shutdown(self) -> None:
        if self._shutdown is not None:
            self._shutdown()


class ProcessFactory(Factory):
    """Starts a fresh IUT process per case. With ``prespawn`` the next case's process is
    started while the current case runs, so its start-up overlaps the current case's waits."""

    def __init__(self, cls, command: str, parmrk: bool, status: bool, prespawn: int = 2):
        self.cls, self.command, self.parmrk, self.status = cls, command, parmrk, status
        probe = cls(command, parmrk=parmrk, status=status)
        super().__init__(None, probe.capabilities)
        self.prespawn = int(prespawn)
        self._ready: list[Transport] = []

    def _started(self) -> Transport:
        t = self.cls(self.command, parmrk=self.parmrk, status=self.status)
        t.open()
        return t

    def __call__(self, vector, params: Params3964) -> Transport:
        t = self._ready.pop(0) if self._ready else self._started()
        while len(self._ready) < self.prespawn:
            try:
                self._ready.append(self._started())
            except TransportError:
                break
        return t

    def shutdown(self) -> None:
        while self._ready:
            self._ready.pop().close()


def make_factory(url: str, profile=None, *, prespawn: int = 2) -> Factory:
    """Turn an ``--iut`` URL into a :class:`Factory`."""
    url = url.strip()
    if not url:
        raise TransportError(f"--iut is empty; use {SCHEMES}")
    parmrk = profile is not None and profile.line_conditions == "parmrk"
    status = profile is None or profile.status_from_stderr
    if url.startswith("exec:"):
        from .process import ExecTransport
        return ProcessFactory(ExecTransport, url[5:], parmrk, status, prespawn)
    if url.startswith("pty:"):
        from .process import PtyTransport
        cmd = url[4:]
        if "{port}" not in cmd:
            raise TransportError(f"{url}: the command must contain {{port}}, replaced by the pty device path")
        return ProcessFactory(PtyTransport, cmd, parmrk, status, prespawn)
    if url.startswith("sim:"):
        from .sim import SimTransport, parse_sim_url
        opts = parse_sim_url(url)

        def make_sim(v, p: Params3964):
            if "priority" in opts:
                p = p.with_(priority=opts["priority"])
            factory = None
            if opts.get("mutant"):
                from ..mutants import make_mutant
                factory = lambda params: make_mutant(opts["mutant"], params)  # noqa: E731
            return SimTransport(p, app=opts.get("app", "echo"), buffer_free=opts.get("buffer", "free") == "free",
                                station_factory=factory, url=url,
                                tester_char=(v.tester_params or p).char_time)
        caps = SimTransport.capabilities
        if opts.get("buffer", "free") != "full":
            caps = caps - {"buffer_control"}  # the model's receive buffer is always free then
        return Factory(make_sim, caps, virtual=True)
    from .serialport import SerialTransport
    if profile is None:
        raise TransportError(f"{url}: a serial port needs an IUT profile (--profile) for its baud rate and frame")
    shared = SerialTransport(url, profile.params)
    shared.open()
    return Factory(lambda v, p: shared, shared.capabilities, shutdown=shared.shutdown)


__all__ = ["BREAK", "CHAR_ERROR", "RESTART", "STATUS", "CloseInfo", "IUTDied", "Transport",
           "TransportError", "make_factory", "SCHEMES", "Factory", "ProcessFactory"]
