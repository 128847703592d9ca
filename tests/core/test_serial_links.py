"""Lab links: the serial transports behind a network serial server. The URL schemes' limits,
a pseudo-terminal given as a device, reads that never renegotiate the port, BREAK over
RFC 2217, and the whole suite over rfc2217:// against the reference implementation on a
pty pair behind an RFC 2217 server built on pyserial's PortManager
(tests/fakes/port_server.py)."""

import os
import select
import shutil
import signal
import socket
import subprocess
import sys
import time
import tty
from contextlib import contextmanager
from pathlib import Path

import pytest
from no_false_alarm import judged
from ptpcert.procedures.p3964.description import reference_profile
from ptpcert.runner import Runner
from ptpcert.scenario import Step, Vector
from ptpcert.transport import BREAK, CHAR_ERROR, TransportError
from ptpcert.transport.base import NETWORK
from ptpcert.transport.serialport import NATIVE, SerialTransport, scheme_of

ROOT = Path(__file__).resolve().parents[2]
PY = sys.executable
SERVER = ROOT / "tests" / "fakes" / "port_server.py"
IUT_ON_PORT = f"{PY} -m ptpcert.cli iut --cdt-ms 20 --adt-ms 20 --parmrk --port {{port}}"
PARAMS = reference_profile().params


@contextmanager
def port_server(mode: str, command: str, tmp_path: Path, parmrk: bool = True):
    """Start tests/fakes/port_server.py; yield (tcp port, path of its event log)."""
    log = tmp_path / f"server-{mode}.log"
    with open(log, "wb") as err:
        proc = subprocess.Popen([PY, str(SERVER), mode] + (["--parmrk"] if parmrk else []) + [command],
                                stdout=subprocess.PIPE, stderr=err, cwd=ROOT)
    try:
        r, _, _ = select.select([proc.stdout], [], [], 20)
        line = proc.stdout.readline().decode() if r else ""
        assert line.startswith("PORT "), f"the port server did not start: {line!r} {log.read_text()}"
        yield int(line.split()[1]), log
    finally:
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def wait_for(predicate, timeout=5.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return True
        time.sleep(0.02)
    return predicate()


# -- each scheme's limits ---------------------------------------------------------------
@pytest.mark.parametrize("url,scheme", [
    ("/dev/ttyUSB0", "device"), ("rfc2217://10.0.0.7:4001", "rfc2217"),
    ("RFC2217://lab:2217?ign_set_control", "rfc2217"), ("socket://127.0.0.1:7000", "socket"),
    ("loop://", "loop"),
])
def test_schemes_are_recognised(url, scheme):
    assert scheme_of(url).name == scheme


@pytest.mark.parametrize("url,fragment", [
    ("spy:///dev/ttyUSB0", "spy:// is not a supported serial URL"),
    ("hwgrep://FTDI", "rfc2217://host:port"),
    ("rfc2217://lab", "give the server's host and TCP port"),
    ("socket://:4001", "give the server's host and TCP port"),
    ("rfc2217://lab:port", "give the server's host and TCP port"),
])
def test_unsupported_urls_are_clean_errors(url, fragment):
    with pytest.raises(TransportError, match=fragment):
        SerialTransport(url, PARAMS)


def test_each_scheme_declares_what_it_carries():
    caps = {u: SerialTransport(u, PARAMS).capabilities
            for u in ("/dev/ttyS0", "rfc2217://h:1", "socket://h:1", "loop://")}
    assert caps["/dev/ttyS0"] == {BREAK, CHAR_ERROR, NATIVE}
    assert caps["rfc2217://h:1"] == {BREAK, NATIVE, NETWORK}   # no character errors over the network
    assert caps["socket://h:1"] == {NETWORK} and caps["loop://"] == frozenset()
    assert SerialTransport("/dev/ttyS0", PARAMS.with_(parity="none")).capabilities == {BREAK, NATIVE}


def test_a_scheme_says_what_it_cannot_do():
    tr = SerialTransport("loop://", PARAMS)
    tr.open()
    try:
        with pytest.raises(TransportError, match="cannot send BREAK"):
            tr.send_break(0.01)
        with pytest.raises(TransportError, match="parity error"):
            tr.send_char_error(0x41)
    finally:
        tr.shutdown()


def test_native_line_conditions_need_no_marking_by_the_iut():
    """A profile with line_conditions = "none" runs BREAK cases over a transport that carries
    a real BREAK; character errors still need a transport that can send them."""
    profile = reference_profile(line_conditions="none", status_from_stderr=False)
    runner = Runner(None, profile)

    def vector(kind):
        step = Step("break") if kind == "break" else Step("send_error", b"\x41")
        return Vector(procedure="p3964", id="X", title="x", reference="-", rule="-", group="break", iut_role="idle",
                      params=profile.params, steps=(step,))
    rfc2217 = frozenset({BREAK, NATIVE})
    assert runner.unsupported_reason(vector("break"), rfc2217) is None
    assert "parity" in runner.unsupported_reason(vector("send_error"), rfc2217)
    assert "reads no line conditions" in runner.unsupported_reason(vector("break"), frozenset({BREAK}))


def test_a_failure_over_a_network_link_must_reproduce():
    """A port server stalled longer than CDT puts a gap on the line the harness never sent:
    over rfc2217:// and socket:// a failed case runs once more before its failure stands."""
    class F:
        capabilities = frozenset({BREAK, NATIVE, NETWORK})
    v = Vector(procedure="p3964", id="X", title="x", reference="-", rule="-", group="receive", iut_role="receiver",
               params=PARAMS, steps=(Step("send", b"\x02"),))
    assert Runner(F(), reference_profile())._rerun_budget(v, "ok", realtime=True) == 1
    F.capabilities = frozenset({BREAK, NATIVE})
    assert Runner(F(), reference_profile())._rerun_budget(v, "ok", realtime=True) == 0


def test_a_pty_as_device_carries_bytes_but_no_line_conditions():
    master, slave = os.openpty()
    tty.setraw(slave)
    tr = SerialTransport(os.ttyname(slave), PARAMS)
    try:
        tr.open()
        assert BREAK not in tr.capabilities and CHAR_ERROR not in tr.capabilities
        with pytest.raises(TransportError, match="pseudo-terminal has no BREAK"):
            tr.send_break(0.01)
        tr.write(b"\x02")
        assert os.read(master, 16) == b"\x02"
        before = tr.now()
        os.write(master, b"\x10\x15")
        got = []
        while len(got) < 2:
            got += tr.read(tr.now() + 1.0)
        assert [b for _, b in got] == [0x10, 0x15]
        assert all(before <= t <= tr.now() for t, _ in got)
    finally:
        tr.shutdown()
        os.close(master)
        os.close(slave)


def test_iut_on_a_port_that_cannot_be_opened_exits_2_with_one_line():
    for port in ("/dev/ttyNOPE", "rfc2217://127.0.0.1:1", "spy:///dev/ttyNOPE"):
        p = subprocess.run([PY, "-m", "ptpcert.cli", "iut", "--port", port], cwd=ROOT,
                           capture_output=True, text=True, timeout=60)
        assert p.returncode == 2, (port, p.stderr)
        assert len(p.stderr.strip().splitlines()) == 1 and "Traceback" not in p.stderr
        assert p.stderr.startswith("ptpcert iut: ") and port in p.stderr


# -- RFC 2217 against the reference implementation ------------------------------------------
@pytest.mark.realtime
@pytest.mark.filterwarnings("ignore:set.*deprecated:DeprecationWarning")  # pyserial's own thread setup
def test_rfc2217_reads_cost_nothing_and_break_reaches_the_iut(tmp_path, monkeypatch):
    import serial.rfc2217

    calls = []
    reconfigure = serial.rfc2217.Serial._reconfigure_port
    monkeypatch.setattr(serial.rfc2217.Serial, "_reconfigure_port",
                        lambda self, *a, **k: (calls.append(time.monotonic()), reconfigure(self, *a, **k))[1])
    with port_server("rfc2217", IUT_ON_PORT, tmp_path) as (port, log):
        tr = SerialTransport(f"rfc2217://127.0.0.1:{port}", PARAMS)
        tr.open()                                   # pyserial 3.5 rejects a write timeout here
        try:
            assert tr.capabilities == {BREAK, NATIVE, NETWORK}
            opened = len(calls)
            assert opened == 1
            for _ in range(20):                    # until the IUT is up: it answers STX with DLE
                tr.write(b"\x02")
                if any(b == 0x10 for _, b in tr.read(tr.now() + 0.5)):
                    break
            while tr.read(tr.now() + 0.3):         # its NAK (CDT expired), then the line is quiet
                pass
            t0 = tr.now()
            for _ in range(40):                    # 40 empty reads of 5 ms: about 0.2 s, not 40 x 50 ms
                assert tr.read(tr.now() + 0.005) == []
            assert tr.now() - t0 < 0.6 and len(calls) == opened
            sent = tr.write(b"\x02")               # STX: the reference IUT answers DLE
            (t, b), = tr.read(sent + 1.0)
            assert b == 0x10 and sent < t <= tr.now()
            assert t - sent < PARAMS.adt + 0.05
            tr.read(tr.now() + 0.1)                # the IUT now times out (CDT) and says NAK
            started = tr.now()
            t_break = tr.send_break(0.02)
            held = tr.now() - started
            assert started <= t_break and 0.02 <= held < 0.045   # no waiting for the server's acks
            assert len(calls) == opened
            assert wait_for(lambda: "BREAK off" in log.read_text())
            assert wait_for(lambda: log.read_text().count("STATUS 16#080D") == 1)  # the IUT saw it
        finally:
            tr.shutdown()


@pytest.mark.realtime
def test_the_suite_runs_over_rfc2217_with_break_cases(tmp_path):
    """The whole suite over rfc2217:// against the reference implementation at 20 ms timers
    on a pty behind an RFC 2217 server: nothing fails (see judged()), the BREAK cases pass,
    and only cases the link cannot serve (start-up, character errors, a full buffer) or the
    profile excludes are unsupported."""
    prof = tmp_path / "p.toml"
    prof.write_text((ROOT / "conformance/profiles/reference-20ms.toml").read_text()
                    .replace('line_conditions = "parmrk"', 'line_conditions = "none"')
                    .replace("status_from_stderr = true", "status_from_stderr = false"))
    out = tmp_path / "r.json"
    with port_server("rfc2217", IUT_ON_PORT, tmp_path) as (port, log):
        p = subprocess.run([PY, "-m", "ptpcert.cli", "run", "--iut", f"rfc2217://127.0.0.1:{port}",
                            "--profile", str(prof), "--json", str(out), "--junit", str(tmp_path / "j.xml")],
                           cwd=ROOT, capture_output=True, text=True, timeout=900)
        events = log.read_text()
    cases = judged(p, out)
    by = {c["id"]: c for c in cases}
    breaks = [c for c in cases if any(s["kind"] == "break" for s in c["steps"])
              and not any(s["kind"] == "send_error" for s in c["steps"])]
    # a case that needs the IUT started with a setup is unsupported where the transport does
    # not start the IUT (a port server); every other BREAK case passes
    assert len(breaks) >= 6 and all(c["verdict"] == "pass" or (c["verdict"] == "unsupported" and "setup" in c["message"])
                                    for c in breaks), \
        [(c["id"], c["verdict"], c["message"]) for c in breaks if c["verdict"] != "pass"]
    assert by["3964R.D21.BREAK-DURING-RECEPTION"]["verdict"] == "pass"
    allowed = ("character errors", "parity/framing errors", "see the IUT start up",
               "this transport does not start the IUT", "the vector is for")
    for c in cases:
        if c["verdict"] == "unsupported":
            assert any(a in c["message"] for a in allowed), (c["id"], c["message"])
    assert sum(c["verdict"] == "pass" for c in cases) >= 88
    # each BREAK went through the server as a line condition and the IUT reported it
    attempts = sum(c["attempts"] for c in breaks if c["verdict"] == "pass")   # an unsupported case sent none
    assert events.count("BREAK on") >= attempts and events.count("STATUS 16#080D") >= attempts


# -- the documentation's ser2net recipe (docs/lab-links.md), where ser2net and socat are installed --
def _docs_ser2net_yaml() -> str:
    text = (ROOT / "docs" / "lab-links.md").read_text()
    section = text[text.index("## ser2net"):]
    return section.split("```yaml\n", 1)[1].split("```", 1)[0]


def test_the_docs_have_a_ser2net_recipe():
    yaml = _docs_ser2net_yaml()
    assert "telnet(rfc2217),tcp(nodelay)," in yaml and "chardelay: false" in yaml
    assert "serialdev,/dev/ttyUSB0," in yaml


@pytest.mark.realtime
@pytest.mark.skipif(not (shutil.which("ser2net") and shutil.which("socat")),
                    reason="needs Debian's ser2net and socat (apt-get install ser2net socat)")
def test_the_docs_ser2net_recipe_works(tmp_path):
    """The documentation's ser2net.yaml, bound to 127.0.0.1, serving one end of a socat pty pair with
    the reference implementation on the other: the cases pass over rfc2217:// (BREAK cases
    are left out: a pty has no BREAK)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    lab, dev = tmp_path / "ttyLAB", tmp_path / "ttyIUT"
    conf = tmp_path / "ser2net.yaml"
    conf.write_text(_docs_ser2net_yaml().replace("/dev/ttyUSB0", str(lab))
                    .replace("tcp(nodelay),4001", f"tcp(nodelay),127.0.0.1,{port}"))
    prof = tmp_path / "p.toml"
    prof.write_text((ROOT / "conformance/profiles/reference-20ms.toml").read_text()
                    .replace('line_conditions = "parmrk"', 'line_conditions = "none"')
                    .replace("status_from_stderr = true", "status_from_stderr = false"))
    procs = []

    def start(cmd, **kw):
        procs.append(subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                      start_new_session=True, **kw))
    try:
        start(["socat", f"pty,raw,echo=0,link={dev}", f"pty,raw,echo=0,link={lab}"])
        assert wait_for(lambda: dev.exists() and lab.exists())
        start([PY, "-m", "ptpcert.cli", "iut", "--cdt-ms", "20", "--adt-ms", "20", "--port", str(dev)])
        start(["ser2net", "-n", "-c", str(conf)])

        def listening():
            with socket.socket() as c:
                return c.connect_ex(("127.0.0.1", port)) == 0
        assert wait_for(listening, 10)
        time.sleep(0.5)   # ser2net drops the probe connection
        p = subprocess.run([PY, "-m", "ptpcert.cli", "run", "--iut", f"rfc2217://127.0.0.1:{port}?ign_set_control",
                            "--profile", str(prof), "--json", str(tmp_path / "r.json"),
                            "--select", "3964R.FIG2-6.*", "--select", "SUITE.RECEIVE.*",
                            "--select", "SUITE.TIMING.*", "--select", "SUITE.SEND.ECHO-*"],
                           cwd=ROOT, capture_output=True, text=True, timeout=600)
    finally:
        for proc in reversed(procs):
            try:
                os.killpg(proc.pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
            try:
                proc.wait(5)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()
    cases = judged(p, tmp_path / "r.json")
    assert sum(c["verdict"] == "pass" for c in cases) >= 30
