"""Transports: how the runner reaches an IUT. :func:`make_factory` turns an ``--iut`` URL
into a factory that gives the runner a transport for each case."""

from __future__ import annotations

from ..model import Params3964
from .base import BREAK, CHAR_ERROR, RESTART, STATUS, CloseInfo, IUTDied, Transport, TransportError

SCHEMES = "exec:COMMAND, pty:COMMAND (with {port}), sim:[?options], or a pyserial URL / device path"


def make_factory(url: str, profile=None):
    """Return (factory, shutdown). ``factory(vector, params)`` gives a transport for one
    case; ``shutdown()`` releases what persists across cases."""
    url = url.strip()
    if not url:
        raise TransportError(f"--iut is empty; use {SCHEMES}")
    parmrk = profile is not None and profile.line_conditions == "parmrk"
    status = profile is None or profile.status_from_stderr
    if url.startswith("exec:"):
        from .process import ExecTransport
        cmd = url[5:]
        ExecTransport(cmd, parmrk=parmrk, status=status)  # validate now
        return (lambda v, p: ExecTransport(cmd, parmrk=parmrk, status=status)), (lambda: None)
    if url.startswith("pty:"):
        from .process import PtyTransport
        cmd = url[4:]
        if "{port}" not in cmd:
            raise TransportError(f"{url}: the command must contain {{port}}, replaced by the pty device path")
        return (lambda v, p: PtyTransport(cmd, parmrk=parmrk, status=status)), (lambda: None)
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
        return make_sim, (lambda: None)
    from .serialport import SerialTransport
    if profile is None:
        raise TransportError(f"{url}: a serial port needs an IUT profile (--profile) for its baud rate and frame")
    shared = SerialTransport(url, profile.params)
    shared.open()
    return (lambda v, p: shared), shared.shutdown


__all__ = ["BREAK", "CHAR_ERROR", "RESTART", "STATUS", "CloseInfo", "IUTDied", "Transport",
           "TransportError", "make_factory", "SCHEMES"]
