"""The RK 512 suite split over the configurations an IUT is tested in (link, priority,
transport), so that every case runs once against a real-time IUT in about the time of one
suite run, and every configuration runs cases of both roles."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import ptpcert.conformance as conformance

from rk512_profiles import PY, ROOT, rk_profile, rk_profile_dict, write_profile

#: timers for real processes on a loaded machine: where the IUT sends first (its requests,
#: its responses) the tester must answer its STX within the IUT's ADT
REALTIME = dict(cdt=100, adt=100, t_res=1000)

#: (link, priority, transport): both links, both priorities, exec: and pty:
CONFIGS = [("3964R", "low", "exec"), ("3964R", "high", "pty"), ("3964", "high", "exec"), ("3964", "low", "pty")]

OK = ("pass", "non_strict", "informational")


def suite_ids(link: str, prio: str) -> list[str]:
    return [v.id for v in conformance.cases(rk_profile(link, prio, **REALTIME))]


def shares(configs=CONFIGS) -> list[list[str]]:
    """Every case id of every configuration's suite in exactly one share: the ids in sorted
    order go round the configurations, each to the next one whose suite has it (cases that
    exist only for one link or priority, e.g. the conflict cases, go to a configuration with
    that link or priority)."""
    suites = [set(suite_ids(link, prio)) for link, prio, _ in configs]
    out: list[list[str]] = [[] for _ in configs]
    n = len(configs)
    for i, cid in enumerate(sorted(set().union(*suites))):
        k = next((i + o) % n for o in range(n) if cid in suites[(i + o) % n])
        out[k].append(cid)
    return out


def run_shares(tmp_path: Path, command, configs=CONFIGS, extra=(), parallel: int = 2
               ) -> list[tuple[tuple, subprocess.CompletedProcess, dict]]:
    """``ptpcert run`` of each configuration's share against ``command(raw, scheme)`` (an
    exec:/pty: URL), ``parallel`` configurations at a time; (config, process, JSON report) for
    each. A freshly started IUT may take 5 s for its start-up NAK: a loaded machine is slow to
    start a Python process, and that is no verdict on the IUT."""
    jobs = []
    for k, ((link, prio, scheme), ids) in enumerate(zip(configs, shares(configs))):
        raw = rk_profile_dict(link, prio, **REALTIME)
        d = tmp_path / f"share-{k}"
        d.mkdir()
        prof = write_profile(d / "p.toml", raw)
        j = d / "r.json"
        args = [a for cid in ids for a in ("--select", cid)]
        cmd = [PY, "-m", "ptpcert.cli", "run", "--iut", command(raw, scheme), "--profile", str(prof),
               "--json", str(j), "-q", "--startup-timeout", "5", *args, *extra]
        jobs.append(((link, prio, scheme), cmd, j))
    out = []
    for i in range(0, len(jobs), parallel):
        batch = [(cfg, subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True), j)
                 for cfg, cmd, j in jobs[i:i + parallel]]
        for cfg, p, j in batch:
            stdout, stderr = p.communicate(timeout=900)
            done = subprocess.CompletedProcess(p.args, p.returncode, stdout, stderr)
            assert j.exists(), (cfg, stderr[-2000:])
            out.append((cfg, done, json.loads(j.read_text())))
    return out
