"""Each transport on its own: exec:, pty:, loop://, socket:// (a TCP bridge to the reference
implementation, i.e. an IUT behind a network serial server), sim:; PARMRK marking; and the
IUT profile loader's errors."""

import os
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from ptpcert.model.parmrk import ParmrkDecoder
from ptpcert.profile import ProfileError, load_profile, profile_from_dict
from ptpcert.procedures.p3964.description import reference_profile
from ptpcert.transport import BREAK, CHAR_ERROR, RESTART, STATUS, TransportError, make_factory
from ptpcert.transport.base import IUTDied, StatusParser
from ptpcert.transport.process import ExecTransport, PtyTransport

ROOT = Path(__file__).resolve().parents[2]
PY = sys.executable
IUT = f"{PY} -m ptpcert.cli iut --cdt-ms 20 --adt-ms 20 --parmrk"


def read_until(tr, n, timeout=5.0):
    out = []
    end = tr.now() + timeout
    while len(out) < n and tr.now() < end:
        out += tr.read(end)
    return out


@pytest.mark.realtime
@pytest.mark.parametrize("cls,cmd", [(ExecTransport, IUT), (PtyTransport, IUT + " --port {port}")])
def test_process_transports_carry_a_block_and_status(cls, cmd):
    tr = cls(cmd, parmrk=True, status=True)
    assert {RESTART, STATUS, BREAK, CHAR_ERROR} <= tr.capabilities
    tr.open()
    try:
        (t0, nak), = read_until(tr, 1)
        assert nak == 0x15                              # start-up NAK
        tr.write(b"\x02")
        assert [b for _, b in read_until(tr, 1)] == [0x10]
        for b in bytes.fromhex("3110103215031003") + b"\x07":  # wrong BCC
            tr.write(bytes([b]))
        (t1, nak2), = read_until(tr, 1)
        assert nak2 == 0x15 and t1 > t0
        time.sleep(0.1)
        codes = [c for _, c in tr.status_reports()]
        assert 0x0808 in codes and 0x0801 in codes
    finally:
        info = tr.close()
    assert info.returncode is not None


@pytest.mark.realtime
def test_exec_marks_line_conditions_in_band():
    tr = ExecTransport(IUT, parmrk=True, status=True)
    tr.open()
    try:
        read_until(tr, 1)
        tr.send_break(0.01)            # FF 00 00 in idle: 16#080D, no NAK
        tr.send_char_error(0x41)       # FF 00 41: 16#080C at once, NAK after CDT (A13)
        got = read_until(tr, 1, timeout=1.0)
        assert [b for _, b in got] == [0x15]
        time.sleep(0.05)
        codes = [c for _, c in tr.status_reports()]
        assert codes[:2] == [0x080D, 0x080C]
        tr.write(b"\xff")              # a data FF is doubled on the wire: a stray byte, NAK after CDT
        assert [b for _, b in read_until(tr, 1, timeout=1.0)] == [0x15]
    finally:
        tr.close()


@pytest.mark.realtime
def test_exec_without_parmrk_cannot_carry_line_conditions():
    tr = ExecTransport(IUT, parmrk=False, status=False)
    assert BREAK not in tr.capabilities and STATUS not in tr.capabilities
    with pytest.raises(TransportError):
        tr.send_break(0.01)


@pytest.mark.realtime
def test_exec_reports_a_dead_iut():
    tr = ExecTransport(f"{PY} -c 'import os; os.write(1, bytes([21]))'", parmrk=False, status=True)
    tr.open()
    with pytest.raises(IUTDied):
        for _ in range(20):
            tr.read(tr.now() + 0.2)
    tr.close()


def test_parmrk_decoder_handles_split_marks():
    d = ParmrkDecoder(True)
    items = d.feed(1.0, b"\x02\xff") + d.feed(2.0, b"\xff\x41\xff\x00") + d.feed(3.0, b"\x00\xff\x00\x32")
    assert [(k, v) for _, k, v in items] == [("byte", 2), ("byte", 0xFF), ("byte", 0x41), ("break", 0),
                                             ("invalid", 0x32)]
    assert ParmrkDecoder(False).feed(0, b"\xff\x00\x00")[1][1:] == ("byte", 0)


def test_status_parser():
    p = StatusParser()
    p.feed(1.0, b"hello\nSTATUS 16#08")
    p.feed(2.0, b"08\nSTATUS 16#0801\nnoise STATUS 16#0a05 x\n")
    assert p.drain() == [(2.0, 0x0808), (2.0, 0x0801), (2.0, 0x0A05)]
    assert "hello" in p.tail()


@pytest.mark.realtime
def test_loop_url_transport():
    f = make_factory("loop://", reference_profile())
    assert BREAK not in f.capabilities and RESTART not in f.capabilities
    tr = f(None, None)
    tr.write(b"\x02\x10")
    got = read_until(tr, 2, timeout=1.0)
    assert [b for _, b in got] == [0x02, 0x10]
    assert all(t <= tr.now() for t, _ in got)
    f.shutdown()


class Bridge:
    """A TCP server that puts a freshly started reference implementation behind each
    connection: what a network serial server (socket://, rfc2217://) looks like."""

    def __init__(self, cmd):
        self.srv = socket.socket()
        self.srv.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        self.srv.bind(("127.0.0.1", 0))
        self.srv.listen(1)
        self.port = self.srv.getsockname()[1]
        self.cmd = cmd
        self.procs = []
        threading.Thread(target=self._serve, daemon=True).start()

    def _serve(self):
        conn, _ = self.srv.accept()
        conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        proc = subprocess.Popen(self.cmd, shell=True, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                stderr=subprocess.DEVNULL, bufsize=0, cwd=ROOT)
        self.procs.append(proc)

        def up():
            try:
                while True:
                    data = conn.recv(4096)
                    if not data:
                        break
                    proc.stdin.write(data)
            except OSError:
                pass

        def down():
            try:
                while True:
                    data = os.read(proc.stdout.fileno(), 4096)
                    if not data:
                        break
                    conn.sendall(data)
            except OSError:
                pass
        threading.Thread(target=up, daemon=True).start()
        threading.Thread(target=down, daemon=True).start()

    def close(self):
        for p in self.procs:
            p.kill()
        self.srv.close()


@pytest.mark.realtime
def test_socket_url_runs_cases_against_a_persistent_iut(tmp_path):
    bridge = Bridge(f"exec {PY} -m ptpcert.cli iut --cdt-ms 20 --adt-ms 20")
    prof = tmp_path / "p.toml"
    prof.write_text((ROOT / "conformance/profiles/reference-20ms.toml").read_text()
                    .replace('line_conditions = "parmrk"', 'line_conditions = "none"')
                    .replace("status_from_stderr = true", "status_from_stderr = false"))
    try:
        p = subprocess.run([PY, "-m", "ptpcert.cli", "run", "--iut", f"socket://127.0.0.1:{bridge.port}",
                            "--profile", str(prof), "--vectors-only", "--select", "3964R.FIG2-6.*",
                            "--select", "3964R.D03.*", "--select", "3964R.D01.*", "--select", "3964R.D21.*",
                            "--select", "3964R.FIG2-7.REPETITION"],
                           cwd=ROOT, capture_output=True, text=True, timeout=120)
    finally:
        bridge.close()
    out = p.stdout
    assert p.returncode == 0, out + p.stderr
    assert "3964R.FIG2-6.RECEIVE" in out and "unsupported   3964R.D01" in out  # no restart on a socket
    assert "unsupported   3964R.D21" in out  # socket:// drops BREAK


# -- the IUT profile ------------------------------------------------------------------
GOOD = dict(procedure="3964R", priority="low", character_delay_ms=20, acknowledgement_delay_ms=20,
            setup_attempts=6, transmission_attempts=6, send_trigger="echo", line_conditions="parmrk",
            status_from_stderr=True)


def test_profile_defaults_and_roundtrip():
    prof = profile_from_dict({"iut": GOOD})
    assert (prof.params.baud_rate, prof.params.data_bits, prof.params.parity, prof.params.stop_bits) == (9600, 8, "even", 1)
    assert prof.params.cdt_ms == 20 and prof.echo and prof.status_from_stderr
    assert profile_from_dict({"iut": {k: v for k, v in prof.to_dict().items() if k != "expected_failures"}}) == prof


@pytest.mark.parametrize("change,key,fragment", [
    ({"priority": None}, "iut.priority", "missing (one of low, high)"),
    ({"send_trigger": "control"}, "iut.send_trigger", '"echo", "none"'),
    ({"line_conditions": "termios"}, "iut.line_conditions", '"parmrk", "none"'),
    ({"character_delay_ms": 15}, "iut.character_delay_ms", "steps of 10"),
    ({"acknowledgement_delay_ms": 10}, "iut.acknowledgement_delay_ms", "20..655350"),
    ({"baud_rate": 115200}, "iut.baud_rate", "76800"),
    ({"status_from_stderr": "yes"}, "iut.status_from_stderr", "true or false"),
    ({"colour": "blue"}, "iut.colour", "unknown key"),
    ({"setup_attempts": 0}, "iut.setup_attempts", "1..255"),
])
def test_profile_errors_name_file_key_and_allowed_values(change, key, fragment):
    d = dict(GOOD)
    for k, v in change.items():
        if v is None:
            d.pop(k)
        else:
            d[k] = v
    with pytest.raises(ProfileError) as e:
        profile_from_dict({"iut": d}, "my.toml")
    assert e.value.key == key and str(e.value).startswith(f"my.toml: {key}:") and fragment in str(e.value)


def test_profile_file_errors(tmp_path):
    with pytest.raises(ProfileError, match="no such file"):
        load_profile(tmp_path / "missing.toml")
    f = tmp_path / "bad.toml"
    f.write_text("[iut\n")
    with pytest.raises(ProfileError, match="bad.toml: not valid TOML"):
        load_profile(f)
    f.write_text("[device]\nx=1\n")
    with pytest.raises(ProfileError, match="device"):
        load_profile(f)
    with pytest.raises(ProfileError, match="a reason"):
        profile_from_dict({"iut": GOOD, "expected_failures": {"X": ""}})


# An IUT that only waits while two children of its own compete for one CPU: the run-queue
# wait that exec: reports must be theirs (children included), and it keeps growing.
_CROWDED = (f"{PY} -c \"import os, time\n"
            "for _ in range(2):\n"
            "    if os.fork() == 0:\n"
            "        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})\n"
            "        end = time.monotonic() + 20\n"
            "        while time.monotonic() < end: pass\n"
            "        os._exit(0)\n"
            "time.sleep(20)\"")


def _open_fds() -> int:
    return len(os.listdir("/proc/self/fd"))


@pytest.mark.realtime
@pytest.mark.skipif(not os.path.exists("/proc/self/task/%d/schedstat" % threading.get_native_id()),
                    reason="no /proc schedstat here")
def test_exec_reports_the_run_queue_wait_of_the_iut_and_its_children():
    before = _open_fds()
    tr = ExecTransport(_CROWDED, parmrk=False, status=False)
    tr.open()
    try:
        first = None
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:   # the children appear after their fork
            w = tr.cpu_wait()
            assert w is not None
            first = w if first is None else first
            if w - first >= 0.2:
                break
            time.sleep(0.01)
        # two busy processes on one CPU: each waits about half the time; the parent sleeps
        assert w - first >= 0.2, f"only {w - first:.3f} s of run-queue wait in 10 s"
        later = [tr.cpu_wait() for _ in range(3)]
        assert later == sorted(later) and later[0] >= w
    finally:
        tr.close()
    assert tr.cpu_wait() is None
    assert _open_fds() <= before, "cpu_wait's descriptors are closed with the transport"
