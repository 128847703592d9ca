"""Concurrent cases at the manual's default timers. Prints figures; exits 1 when a
done-when figure is missed.

    python benchmarks/bench_jobs.py [--jobs 8] [--repeat 5] [--select GLOB ...] [--no-serial] [--no-plugin]

1. The full 3964R suite against the bundled reference implementation over exec: at
   CDT 220 ms / ADT 2000 ms (Table 2-4's defaults), serially and with ``--jobs 8``: wall
   times, the bound 1.3 x (the longest chain of forced waits of one case + the sum of forced
   waits / jobs), and whether both runs gave the same verdicts. The forced waits are the
   protocol's own (each result's ``forced_wait``), so the bound is what perfect overlap
   would reach plus 30 %. A serial run takes minutes (the sum of the forced waits).
   ``--repeat N`` runs the ``--jobs`` run N times in a row: each must meet the bound and give
   the serial run's verdicts.
2. The pytest plugin against the reference at 20 ms timers: its outcome counts equal
   ``ptpcert run``'s, also with pytest-xdist's ``-n 2``.

The machine's load average is printed before and after: on a shared machine the figures
mean little without it.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PY = sys.executable
REFERENCE_20 = ROOT / "conformance" / "profiles" / "reference-20ms.toml"
IUT_DEFAULT = f"exec:{PY} -m ptpcert.cli iut --cdt-ms 220 --adt-ms 2000 --parmrk"
IUT_20 = f"exec:{PY} -m ptpcert.cli iut --cdt-ms 20 --adt-ms 20 --parmrk"
#: pytest outcome for each verdict of `ptpcert run`
OUTCOME_OF = {"pass": "passed", "non-strict": "passed", "informational": "passed", "fail": "failed",
              "xpass": "failed", "unsupported": "skipped", "xfail": "skipped", "error": "error"}


def load() -> str:
    one, five, fifteen = os.getloadavg()
    return f"load average {one:.2f} {five:.2f} {fifteen:.2f} on {os.cpu_count()} cores"


def default_timers_profile(tmp: Path) -> Path:
    """The bundled reference profile at the manual's default timers."""
    text = REFERENCE_20.read_text()
    for old, new in (("character_delay_ms = 20\n", "character_delay_ms = 220\n"),
                     ("acknowledgement_delay_ms = 20\n", "acknowledgement_delay_ms = 2000\n")):
        if old not in text:
            raise SystemExit(f"bench_jobs: {REFERENCE_20} has no line {old.strip()!r}")
        text = text.replace(old, new)
    path = tmp / "reference-default-timers.toml"
    path.write_text(text)
    return path


def suite_run(profile: Path, jobs: int, select: list[str], out: Path) -> tuple[float, dict]:
    args = [PY, "-m", "ptpcert.cli", "run", "--iut", IUT_DEFAULT, "--profile", str(profile),
            "--json", str(out), "-q", "--jobs", str(jobs)]
    for s in select:
        args += ["--select", s]
    t = time.monotonic()
    subprocess.run(args, cwd=ROOT, stdout=subprocess.DEVNULL)
    return time.monotonic() - t, json.loads(out.read_text())


def bound(cases: list[dict], jobs: int) -> tuple[float, float, float]:
    forced = [c["forced_wait"] for c in cases]
    chain, total = max(forced, default=0.0), sum(forced)
    return chain, total, 1.3 * (chain + total / jobs)


def plugin_counts(tmp: Path, extra: list[str]) -> Counter:
    xml = tmp / "plugin.xml"
    subprocess.run([PY, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--ptpcert-iut", IUT_20,
                    "--ptpcert-profile", str(REFERENCE_20), f"--junitxml={xml}", *extra],
                   cwd=tmp, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    out = Counter()
    for tc in ET.parse(xml).getroot().iter("testcase"):
        kinds = {child.tag for child in tc}
        out["failed" if "failure" in kinds else "error" if "error" in kinds
            else "skipped" if "skipped" in kinds else "passed"] += 1
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--jobs", type=int, default=8)
    ap.add_argument("--select", action="append", default=[], help="only these cases (a quicker look)")
    ap.add_argument("--no-serial", action="store_true", help="skip the serial run (no verdict comparison)")
    ap.add_argument("--no-plugin", action="store_true")
    ap.add_argument("--repeat", type=int, default=1, help="how many --jobs runs in a row (default 1)")
    args = ap.parse_args()
    ok = True
    tmp = Path(tempfile.mkdtemp(prefix="bench-jobs-"))
    profile = default_timers_profile(tmp)
    print(f"before: {load()}")
    runs: dict[int, dict] = {}
    parallel: list[dict] = []
    for i, jobs in enumerate(([] if args.no_serial else [1]) + [args.jobs] * max(1, args.repeat)):
        wall, d = suite_run(profile, jobs, args.select, tmp / f"r{jobs}-{i}.json")
        runs.setdefault(jobs, d)
        if jobs == args.jobs:
            parallel.append(d)
        cases = d["cases"]
        chain, total, limit = bound(cases, args.jobs)
        counts = Counter(c["verdict"] for c in cases)
        print(f"3964R suite over exec: at CDT 220 ms / ADT 2000 ms, --jobs {jobs}: {len(cases)} cases, "
              f"wall {wall:.1f} s (runner {d['wall_time']:.1f} s); verdicts {dict(sorted(counts.items()))}; "
              f"{load()}")
        if jobs == args.jobs:
            met = d["wall_time"] <= limit
            ok &= met
            print(f"  forced waits: longest case {chain:.1f} s, sum {total:.1f} s; bound 1.3 x ({chain:.1f} + "
                  f"{total:.1f} / {args.jobs}) = {limit:.1f} s: {'met' if met else 'MISSED'}")
        else:
            print(f"  forced waits: sum {total:.1f} s; wall / forced {d['wall_time'] / max(total, 1e-9):.2f}")
    if 1 in runs and args.jobs != 1:
        a = runs[1]["cases"]
        for n, d in enumerate(parallel, 1):
            b = d["cases"]
            same_order = [c["id"] for c in a] == [c["id"] for c in b]
            diff = [(x["id"], x["verdict"], y["verdict"]) for x, y in zip(a, b) if x["verdict"] != y["verdict"]]
            ok &= same_order and not diff
            print(f"  --jobs {args.jobs} run {n} against the serial run: same cases in the same order: {same_order}; "
                  f"verdicts differing: {diff or 'none'}")
    if not args.no_plugin:
        subprocess.run([PY, "-m", "ptpcert.cli", "run", "--iut", IUT_20, "--profile", str(REFERENCE_20),
                        "--json", str(tmp / "r20.json"), "-q", "--jobs", "2"], cwd=ROOT, stdout=subprocess.DEVNULL)
        want = Counter(OUTCOME_OF[c["verdict"]] for c in json.loads((tmp / "r20.json").read_text())["cases"])
        for extra in ([], ["-n", "2"]):
            have = plugin_counts(tmp, extra)
            same = have == want
            ok &= same
            print(f"pytest plugin{' ' + ' '.join(extra) if extra else ''} at 20 ms timers: {dict(sorted(have.items()))}; "
                  f"ptpcert run: {dict(sorted(want.items()))}: {'equal' if same else 'DIFFERENT'}")
    print(f"after: {load()}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
