"""The shared fuzz database on a real Redis server (``ptpcert fuzz --database redis://...``):
two fuzz processes write into it at the same time, and a later campaign starts from what
they stored; the property the directory database has (test_fuzz_workers.py), over the
network. The server is Debian's redis-server (.ci/run installs it), started here on a free
loopback port with nothing written to disk, and stopped at the end."""

from __future__ import annotations

import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest
from test_fuzz_workers import MUTANT, PROFILE, a_later_campaign_resumes

from ptpcert.scenario import load_dir

ROOT = Path(__file__).resolve().parents[2]
PY = sys.executable
SERVER = shutil.which("redis-server")
START_S = 15.0      # how long the server may take to answer its first PING
PREFIX = b"hypothesis-example:"   # where hypothesis's RedisExampleDatabase keeps its examples


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def redis_url(tmp_path):
    """A redis-server of its own on 127.0.0.1 (no snapshot, no append-only file, its
    directory a temporary one): its URL, database 0. Killed at the end."""
    if SERVER is None:
        pytest.skip("redis-server is not installed (Debian package 'redis-server'; .ci/run installs it)")
    redis = pytest.importorskip("redis", reason="the Redis client (hypothesis[redis], in the test extra)")
    for _ in range(3):   # another process may take the free port between the probe and the bind
        port = _free_port()
        proc = subprocess.Popen([SERVER, "--port", str(port), "--bind", "127.0.0.1", "--save", "", "--appendonly",
                                 "no", "--dir", str(tmp_path), "--daemonize", "no", "--logfile", ""],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)
        client = redis.Redis(host="127.0.0.1", port=port, socket_timeout=2)
        deadline = time.monotonic() + START_S
        while proc.poll() is None and time.monotonic() < deadline:
            try:
                if client.ping():
                    break
            except redis.exceptions.ConnectionError:
                time.sleep(0.05)
        else:
            if proc.poll() is None:
                proc.kill()
            out = proc.communicate(timeout=10)[0]
            if b"Address already in use" in out:
                continue
            pytest.fail(f"redis-server did not answer within {START_S:g} s: {out.decode(errors='replace')[-800:]}")
        try:
            yield f"redis://127.0.0.1:{port}/0", client
        finally:
            client.close()
            proc.kill()
            proc.communicate(timeout=10)
        return
    pytest.fail("redis-server found no free port in 3 tries")


def fuzz(log: Path, *args):
    """A ``ptpcert fuzz`` process, its output into ``log`` (two at once: no pipe to fill)."""
    with open(log, "w") as f:
        return subprocess.Popen([PY, "-m", "ptpcert.cli", "fuzz", *args], cwd=ROOT, stdout=f,
                                stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)


@pytest.mark.realtime
def test_two_processes_share_a_redis_database_and_a_later_campaign_resumes_from_it(redis_url, tmp_path):
    """Two fuzz processes (seeds apart) fuzz the broken variant at the same time with one
    Redis database: each finds the defect and the server holds their failing examples. A
    later campaign with another seed then starts from a stored example: the first example
    it runs is a shrunk finding (fails the variant, passes the reference): the test of the
    directory database (test_fuzz_workers.py), with the Redis server as the database."""
    url, client = redis_url
    procs = {seed: fuzz(tmp_path / f"log{seed}", "--iut", MUTANT, "--profile", str(PROFILE), "--budget", "8",
                        "--seed", str(seed), "--database", url, "--export", str(tmp_path / f"out{seed}"))
             for seed in (11, 12)}
    for seed, p in procs.items():
        p.wait(timeout=300)
        out = (tmp_path / f"log{seed}").read_text()
        assert p.returncode == 1, out[-3000:]
        assert f"database {url}" in out
    found = [load_dir(tmp_path / f"out{seed}") for seed in (11, 12)]
    assert [len(f) for f in found] == [1, 1], [[v.id for v in f] for f in found]
    stored = client.keys(PREFIX + b"*")
    assert stored and sum(client.scard(k) for k in stored if client.type(k) == b"set") > 0

    a_later_campaign_resumes(url, [f[0] for f in found])


def test_an_unreachable_redis_server_is_one_line_and_exit_2(tmp_path):
    """A redis:// database nobody answers on: the campaign does not start (exit 2, one line
    naming the database), rather than fuzzing without the shared database it was asked for."""
    pytest.importorskip("redis")
    url = f"redis://127.0.0.1:{_free_port()}/0"
    p = subprocess.run([PY, "-m", "ptpcert.cli", "fuzz", "--iut", MUTANT, "--profile", str(PROFILE), "--budget", "2",
                        "--database", url, "--export", str(tmp_path / "out")], cwd=ROOT, capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == 2, p.stdout[-2000:] + p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and url in lines[0] and "Traceback" not in p.stderr, p.stderr
