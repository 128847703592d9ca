"""The harness's scheduling class (ptpcert.priority): its timing threads take the real-time
class where the system permits it, for the time of the cases only; the IUT, the report
writing and everything the harness starts stay in the normal class."""

import json
import os
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from ptpcert import priority
from ptpcert.cli import main as cli_main

ROOT = Path(__file__).resolve().parents[2]
PROFILE = ROOT / "conformance" / "profiles" / "reference-20ms.toml"


def _permitted() -> bool:
    try:
        with priority.harness("realtime"):
            return True
    except priority.PriorityError:
        return False


needs_rt = pytest.mark.skipif(not _permitted(), reason="the real-time class is not permitted here")


def _child_policy() -> int:
    out = subprocess.run([sys.executable, "-c", "import os; print(os.sched_getscheduler(0))"],
                         capture_output=True, text=True, check=True).stdout
    return int(out)


@needs_rt
def test_the_harness_thread_is_real_time_for_the_body_only_and_what_it_starts_is_not():
    assert priority.current() == "normal"
    seen = {}
    with priority.harness("auto") as how:
        assert priority.current() == "realtime"
        assert how.startswith("real-time (SCHED_FIFO")
        assert _child_policy() == os.SCHED_OTHER          # SCHED_RESET_ON_FORK: the IUT stays normal

        def worker():
            seen["plain"] = priority.current()           # a new thread begins in the normal class
            with priority.thread():
                seen["timing"] = priority.current()
            seen["after"] = priority.current()
        t = threading.Thread(target=worker)
        t.start()
        t.join()
    assert seen == {"plain": "normal", "timing": "realtime", "after": "normal"}
    assert priority.current() == "normal"


@needs_rt
def test_a_long_lived_thread_follows_the_run_with_sync():
    steps = []
    go, turn, done = threading.Event(), threading.Event(), threading.Event()

    def reader():
        for _ in range(2):
            go.wait()
            go.clear()
            priority.sync()
            steps.append(priority.current())
            turn.set()
        done.set()
    t = threading.Thread(target=reader)
    t.start()
    with priority.harness("auto"):
        go.set()
        turn.wait(5)
        turn.clear()
    go.set()
    done.wait(5)
    t.join(5)
    assert steps == ["realtime", "normal"]


def test_normal_never_asks_and_the_other_thread_keeps_its_class():
    with priority.harness("normal") as how:
        assert priority.current() == "normal" and how == "normal (--priority normal)"
        with priority.thread():
            assert priority.current() == "normal"
    with pytest.raises(ValueError, match="allowed values: auto, realtime, normal"):
        with priority.harness("fast"):
            pass


def test_where_it_is_not_permitted_auto_runs_normal_and_realtime_is_refused(monkeypatch, tmp_path, capsys):
    def refuse(*_):
        raise PermissionError(1, "Operation not permitted")
    monkeypatch.setattr(os, "sched_setscheduler", refuse)
    with priority.harness("auto") as how:
        assert how.startswith("normal (the system does not permit the real-time class")
        with priority.thread():
            assert priority.current() == "normal"
    with pytest.raises(priority.PriorityError, match="--priority realtime"):
        with priority.harness("realtime"):
            pass
    rc = cli_main(["run", "--iut", "exec:ptpcert iut --cdt-ms 20 --adt-ms 20 --parmrk", "--profile", str(PROFILE),
                   "--priority", "realtime", "--json", str(tmp_path / "r.json"), "-q"])
    assert rc == 2
    assert "--priority realtime: the system does not permit" in capsys.readouterr().err
    assert not (tmp_path / "r.json").exists()          # refused before anything ran


@pytest.mark.realtime
@needs_rt
def test_a_run_over_exec_has_a_real_time_harness_and_a_normal_iut(tmp_path):
    """The IUT process writes its own scheduling policy where the test can read it, then
    becomes the reference IUT: the run passes, says it had the real-time class, and the IUT
    ran in the normal one."""
    mark = tmp_path / "policy"
    code = (f"import os, sys; open({str(mark)!r}, 'w').write(str(os.sched_getscheduler(0))); "
            "os.execvp(sys.executable, [sys.executable, '-m', 'ptpcert.cli', 'iut', '--cdt-ms', '20', "
            "'--adt-ms', '20', '--parmrk'])")
    iut = f"exec:{sys.executable} -c \"{code}\""
    p = subprocess.run([sys.executable, "-m", "ptpcert.cli", "run", "--iut", iut, "--profile", str(PROFILE),
                        "--select", "SUITE.SEND.ECHO-PLAIN", "--json", str(tmp_path / "r.json"),
                        "--html", str(tmp_path / "r.html")],
                       capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert p.returncode == 0, p.stdout + p.stderr
    res = json.loads((tmp_path / "r.json").read_text())
    assert res["harness_scheduling"].startswith("real-time (SCHED_FIFO")
    assert "harness scheduling: real-time" in p.stdout
    assert "harness scheduling" in (tmp_path / "r.html").read_text()
    assert int(mark.read_text()) == os.SCHED_OTHER


@needs_rt
def test_processes_started_ahead_wait_lowered_and_run_their_case_at_the_normal_level():
    """An IUT started ahead of its case (exec:, a fresh process per case) must not take a
    CPU from the IUT under test with its start-up: it waits at nice 10 and is back at 0 when
    its case takes it. Without the real-time class (no privilege to raise it again) nothing
    is lowered."""
    from ptpcert.transport import ProcessFactory
    from ptpcert.transport.process import ProcessTransport

    def nice(t):
        return os.getpriority(os.PRIO_PROCESS, t.proc.pid)

    f = ProcessFactory(ProcessTransport, "sleep 30", parmrk=False, status=False, prespawn=2)
    try:
        with priority.harness("auto"):
            first = f(None, None)                    # started for its case: never lowered
            ahead = [t for ready in f._ready.values() for _, t in ready]
            assert len(ahead) == 2 and all(nice(t) == priority.BACKGROUND_NICE for t in ahead)
            assert nice(first) == 0
            second = f(None, None)
            assert second in ahead and nice(second) == 0
            for t in (first, second):
                t.close()
        f.release()
        with priority.harness("normal"):
            third = f(None, None)
            ahead = [t for ready in f._ready.values() for _, t in ready]
            assert ahead and all(nice(t) == 0 for t in ahead)
            third.close()
    finally:
        f.shutdown()
