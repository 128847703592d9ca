"""``exec:COMMAND`` and ``pty:COMMAND``: the IUT is a process the harness starts for each
case, in its own process group, and always stops (also on Ctrl-C, crash or timeout).

* ``exec:`` — the wire is the process's stdin/stdout.
* ``pty:`` — the harness opens a pseudo-terminal pair, replaces ``{port}`` in COMMAND by
  the device path and starts it; the wire is the pty. stdin and stdout of the process are
  not used for the line.

Line conditions towards the IUT are marked in-band as POSIX PARMRK marks them (``FF 00 00``
BREAK, ``FF 00 xx`` character xx with a parity/framing error, ``FF FF`` a data byte FF)
when the profile says the IUT reads that marking. The IUT's stderr is kept, and lines
``STATUS 16#XXXX`` on it are collected with their arrival times.
"""

from __future__ import annotations

import atexit
import errno
import fcntl
import os
import select
import signal
import subprocess
import time
import tty
import weakref

from .. import priority
from ..model import parmrk as marking
from .base import BREAK, CHAR_ERROR, RESTART, STATUS, CloseInfo, IUTDied, StatusParser, Transport, TransportError

_LIVE: "weakref.WeakSet[ProcessTransport]" = weakref.WeakSet()


@atexit.register
def _kill_leftovers() -> None:  # the last line of defence: no IUT outlives the harness
    for t in list(_LIVE):
        try:
            t.close()
        except Exception:
            pass
        proc = t.proc   # also one whose close() was cut short (e.g. by Ctrl-C)
        if proc is not None and proc.poll() is None:
            try:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait(timeout=2.0)
            except (OSError, subprocess.TimeoutExpired):
                pass


def _nonblocking(fd: int) -> None:
    fl = fcntl.fcntl(fd, fcntl.F_GETFL)
    fcntl.fcntl(fd, fcntl.F_SETFL, fl | os.O_NONBLOCK)


class ProcessTransport(Transport):
    kind = "exec"

    def __init__(self, command: str, *, parmrk: bool, status: bool, startup_grace: float = 2.0):
        if not command.strip():
            raise TransportError(f"{self.kind}: needs a command, e.g. '{self.kind}:ptpcert iut --parmrk'")
        self.command = command
        self.url = f"{self.kind}:{command}"
        self.parmrk = parmrk
        caps = {RESTART}
        if parmrk:
            caps |= {BREAK, CHAR_ERROR}
        if status:
            caps.add(STATUS)
        self.capabilities = frozenset(caps)
        self.proc: subprocess.Popen | None = None
        self._no_schedstat = False
        self._sched: dict[tuple[int, str], int] = {}   # (pid, tid) -> open schedstat descriptor
        self._next_walk = 0.0
        self.parser = StatusParser()
        self._closed = False
        self._eof = False
        self.startup_grace = startup_grace

    # -- life cycle ---------------------------------------------------------------
    def _spawn(self, command: str, **kw) -> subprocess.Popen:
        try:
            # "exec" lets the shell turn into the IUT, so that the pid is the IUT's own
            proc = subprocess.Popen("exec " + command, shell=True, start_new_session=True,
                                    stderr=subprocess.PIPE, bufsize=0, **kw)
        except OSError as exc:
            raise TransportError(f"{self.url}: cannot start: {exc}") from None
        _LIVE.add(self)
        _nonblocking(proc.stderr.fileno())
        return proc

    def open(self) -> None:
        if self.proc is not None:
            return  # started ahead of time
        self.proc = self._spawn(self.command, stdin=subprocess.PIPE, stdout=subprocess.PIPE)
        self.fd_out = self.proc.stdin.fileno()
        self.fd_in = self.proc.stdout.fileno()
        _nonblocking(self.fd_in)

    def now(self) -> float:
        return time.monotonic()

    def _check_startup_failure(self) -> None:
        """A command that cannot even start (not found, bad options) is a configuration
        fault of the run, not a verdict on the IUT."""
        rc = self.proc.poll()
        if rc is not None and rc in (126, 127, 2) and self.now() - self._t_open < self.startup_grace:
            self._drain_stderr()
            tail = self.parser.tail(800).strip()
            raise TransportError(f"{self.url}: the command exited with status {rc} at start-up"
                                 + (f": {tail}" if tail else ""))

    # -- line -----------------------------------------------------------------------
    def _encode(self, data: bytes) -> bytes:
        return marking.encode(data) if self.parmrk else data

    def _write_raw(self, data: bytes) -> float:
        t = self.now()
        try:
            view = memoryview(data)
            while view:
                try:
                    n = os.write(self.fd_out, view)
                    view = view[n:]
                except BlockingIOError:
                    select.select([], [self.fd_out], [], 0.05)
        except (BrokenPipeError, OSError) as exc:
            if isinstance(exc, OSError) and exc.errno not in (errno.EPIPE, errno.EIO, errno.EBADF):
                raise
            self._died()
        return t

    def write(self, data: bytes) -> float:
        return self._write_raw(self._encode(data))

    def send_break(self, duration: float) -> float:
        if not self.parmrk:
            raise TransportError(f"{self.url}: BREAK needs an IUT that reads PARMRK marking")
        return self._write_raw(marking.BREAK_MARK)

    def send_char_error(self, byte: int) -> float:
        if not self.parmrk:
            raise TransportError(f"{self.url}: character errors need an IUT that reads PARMRK marking")
        return self._write_raw(marking.error_mark(byte))

    def read(self, deadline: float) -> list[tuple[float, int]]:
        if self._eof:
            self._died()
        fds = [self.fd_in, self.proc.stderr.fileno()]
        while True:
            timeout = max(0.0, deadline - self.now())
            try:
                r, _, _ = select.select(fds, [], [], timeout)
            except InterruptedError:
                continue
            t = self.now()
            out: list[tuple[float, int]] = []
            if self.proc.stderr.fileno() in r:
                self._drain_stderr(t)
            if self.fd_in in r:
                try:
                    data = os.read(self.fd_in, 65536)
                except BlockingIOError:
                    data = None
                except OSError as exc:
                    if exc.errno != errno.EIO:
                        raise
                    data = b""
                if data == b"":
                    self._eof = True
                    if out:
                        return out
                    self._died()
                if data:
                    out = [(t, b) for b in data]
            if out:
                return out
            if self.now() >= deadline:
                if self.proc.poll() is not None:
                    self._died()
                return []

    def _drain_stderr(self, t: float | None = None) -> None:
        t = self.now() if t is None else t
        while True:
            try:
                chunk = os.read(self.proc.stderr.fileno(), 65536)
            except (BlockingIOError, OSError):
                return
            if not chunk:
                return
            self.parser.feed(t, chunk)

    def _died(self) -> None:
        try:
            self.proc.wait(timeout=0.5)
        except subprocess.TimeoutExpired:
            pass
        self._drain_stderr()
        self._check_startup_failure()
        rc = self.proc.poll()
        if rc is None:
            raise IUTDied(None, self.parser.tail(), "the IUT closed its side of the line (end of file on its "
                          "output) but its process keeps running")
        raise IUTDied(rc, self.parser.tail())

    #: kernel wait channels of a task that waits for input (select/poll, a blocking read)
    _WAITS = ("poll", "select", "pipe_read", "wait_woken", "n_tty_read", "tty_read")

    def ready(self) -> bool | None:
        """Linux: the IUT is ready once one of its threads sleeps waiting for input (its
        /proc wait channel); elsewhere, or when /proc cannot be read, None."""
        if self.proc is None or self.proc.poll() is not None:
            return None
        base = f"/proc/{self.proc.pid}/task"
        try:
            tasks = os.listdir(base)
            for tid in tasks:
                with open(f"{base}/{tid}/stat", "rb") as f:
                    state = f.read().rsplit(b")", 1)[1].split()[0]
                with open(f"{base}/{tid}/wchan", "rb") as f:
                    wchan = f.read().decode("ascii", "replace")
                if state == b"S" and any(w in wchan for w in self._WAITS):
                    return True
        except (OSError, IndexError):
            return None
        return False

    #: how often cpu_wait walks the IUT's process tree again for new threads and children;
    #: between walks it only re-reads the descriptors it keeps open (a few microseconds each)
    TREE_WALK = 0.02

    def cpu_wait(self) -> float | None:
        """Linux: the run-queue wait of every thread of the IUT's process and its children
        (/proc/PID/task/TID/schedstat, second field, nanoseconds), read through descriptors
        kept open. A thread or child that ends is left out from then on (its wait with it);
        one that starts is found at the next walk of the tree; where /proc has no schedstat
        at all, None from then on."""
        if self.proc is None or self._closed or self._no_schedstat:
            return None
        now = self.now()
        if now >= self._next_walk:
            if not self._walk_tree():
                return None
            self._next_walk = now + self.TREE_WALK
        total = 0
        for key, fd in list(self._sched.items()):
            try:
                total += priority.run_queue_wait_ns(fd)
            except (OSError, ValueError, IndexError):
                os.close(fd)          # the thread ended
                del self._sched[key]
        return total / 1e9

    def _walk_tree(self) -> bool:
        """Open the schedstat of every thread of the IUT and its children not yet open;
        False where there is nothing to read (the IUT is gone, or /proc has no schedstat)."""
        todo = [self.proc.pid]
        seen = 0
        while todo and seen < 64:
            pid = todo.pop()
            seen += 1
            base = f"/proc/{pid}/task"
            try:
                tasks = os.listdir(base)
            except OSError:
                if pid == self.proc.pid:
                    if self.proc.poll() is None and not os.path.exists(f"/proc/{pid}"):
                        self._no_schedstat = True     # no /proc here
                    return False
                continue
            for tid in tasks:
                key = (pid, tid)
                if key not in self._sched:
                    try:
                        self._sched[key] = os.open(f"{base}/{tid}/schedstat", os.O_RDONLY | os.O_CLOEXEC)
                    except FileNotFoundError:
                        if not os.path.exists(f"/proc/{pid}") or not os.path.exists(f"{base}/{tid}"):
                            continue          # the thread or process ended meanwhile
                        self._no_schedstat = True     # a kernel without schedstats
                        self._drop_sched()
                        return False
                    except OSError:
                        continue
                try:
                    with open(f"{base}/{tid}/children", "rb") as f:
                        todo.extend(int(c) for c in f.read().split())
                except (OSError, ValueError):
                    pass
        return True

    def _drop_sched(self) -> None:
        for fd in self._sched.values():
            try:
                os.close(fd)
            except OSError:
                pass
        self._sched.clear()

    def status_reports(self) -> list[tuple[float, int]]:
        if self.proc is not None and not self._closed:
            self._drain_stderr()
        return self.parser.drain()

    def report_lines(self) -> list[tuple[float, str]]:
        if self.proc is not None and not self._closed:
            self._drain_stderr()
        return self.parser.drain_lines()

    def close(self) -> CloseInfo:
        info = CloseInfo()
        if self.proc is None or self._closed:
            return info
        self._closed = True
        self._drop_sched()
        proc = self.proc
        self._close_line()
        # Let the IUT see the end of its input and exit by itself (flushing its stderr),
        # briefly; then no member of its process group survives, whatever happened.
        deadline = self.now() + 0.15
        err = proc.stderr.fileno()
        while proc.poll() is None and self.now() < deadline:
            r, _, _ = select.select([err], [], [], max(0.0, min(0.01, deadline - self.now())))
            if r:
                self._drain_stderr()
                try:  # stderr at EOF: the process is ending
                    if not os.read(err, 1):
                        proc.wait(timeout=max(0.0, deadline - self.now()))
                        break
                except BlockingIOError:
                    pass
                except (OSError, subprocess.TimeoutExpired):
                    break
        if proc.poll() is None:
            info.killed = True
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
        try:
            proc.wait(timeout=2.0)
        except subprocess.TimeoutExpired:
            info.notes.append(f"the IUT process {proc.pid} did not end after SIGKILL")
        self._drain_stderr()
        try:
            proc.stderr.close()
        except OSError:
            pass
        info.returncode = proc.returncode
        info.stderr = self.parser.tail()
        if self.parser.dropped:
            info.notes.append(f"{self.parser.dropped} further STATUS line(s) on the IUT's stderr not kept "
                              f"(at most {self.parser.keep_lines} per case)")
        _LIVE.discard(self)
        return info

    def _close_line(self) -> None:
        for f in (self.proc.stdin, self.proc.stdout):
            try:
                f.close()
            except OSError:
                pass

    def describe(self) -> str:
        return self.url


class ExecTransport(ProcessTransport):
    kind = "exec"

    def open(self) -> None:
        if self.proc is None:
            self._t_open = self.now()
        super().open()


class PtyTransport(ProcessTransport):
    kind = "pty"

    def open(self) -> None:
        if self.proc is not None:
            return  # started ahead of time
        self._t_open = self.now()
        master, slave = os.openpty()
        tty.setraw(slave)
        self.master, self.slave = master, slave
        self.device = os.ttyname(slave)
        if "{port}" not in self.command:
            os.close(master)
            os.close(slave)
            raise TransportError(f"{self.url}: the command must contain {{port}}, replaced by the pty device")
        self.proc = self._spawn(self.command.replace("{port}", self.device),
                                stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL)
        _nonblocking(master)
        self.fd_in = self.fd_out = master

    def read(self, deadline: float) -> list[tuple[float, int]]:
        # the pty stays open while the harness holds the slave, so also watch the process
        out = super().read(min(deadline, self.now() + 0.25))
        while not out and self.now() < deadline:
            if self.proc.poll() is not None:
                self._died()
            out = super().read(min(deadline, self.now() + 0.25))
        return out

    def line_settings(self) -> dict | None:
        """The character frame the IUT set on the pseudo-terminal, in the profile's terms
        (baud_rate, data_bits, parity, stop_bits), with only the fields this system's ptys
        keep (:mod:`ptpcert.transport.line_frame`); for a case that compares it with the profile."""
        from ptpcert.transport.line_frame import pty_keeps, read_frame
        try:
            frame = read_frame(self.slave)
        except (OSError, AttributeError):
            return None
        return {k: v for k, v in frame.items() if k in pty_keeps()}

    def _close_line(self) -> None:
        for fd in (self.master, self.slave):
            try:
                os.close(fd)
            except OSError:
                pass
