"""Reports of a flooding IUT: their size and how long writing them takes. Prints figures;
asserts nothing (tests/core/test_robust.py holds the goal: results.json < 5 MB, all reports in
< 10 s).

    python benchmarks/bench_reports.py [--bytes 10000000] [--select GLOB ...]

The whole suite runs over exec: against tests/fakes/flood.py, which sends --bytes random
bytes after its start-up NAK each time it is started; then the JUnit, JSON and HTML reports
are written (as ``ptpcert run`` writes them) and timed one by one, and the JSON is read back
and rendered again (as ``ptpcert report`` does).
"""

from __future__ import annotations

import argparse
import resource
import sys
import tempfile
import time
from pathlib import Path

from ptpcert import __version__
from ptpcert import results as R
from ptpcert.profile import load_profile
from ptpcert.report import write_junit
from ptpcert.report.html import write_html
from ptpcert.runner import Runner, RunOptions
from ptpcert.scenario import load_vector_sets
from ptpcert.suite import load_suite
from ptpcert.transport import make_factory

ROOT = Path(__file__).resolve().parent.parent
PROFILE = ROOT / "conformance" / "profiles" / "reference-20ms.toml"
FLOOD = ROOT / "tests" / "fakes" / "flood.py"


def flood_run(nbytes: int, select: list[str] | None) -> R.RunResult:
    profile = load_profile(PROFILE)
    cases = load_suite(profile, load_vector_sets(), select=select)
    url = f"exec:{sys.executable} {FLOOD} --bytes {nbytes} --random"
    factory = make_factory(url, profile)
    result = R.RunResult(tool_version=__version__, started="bench", iut=url, procedure=profile.procedure.title,
                         profile=profile.to_dict(), profile_path=str(PROFILE))
    try:
        Runner(factory, profile, RunOptions(echo=profile.echo, check_status=profile.status_from_stderr)).run(cases, result)
    finally:
        factory.shutdown()
    return result


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bytes", type=int, default=10_000_000, help="random bytes per IUT start (default 10 MB)")
    ap.add_argument("--select", action="append", help="only these cases (id globs)")
    args = ap.parse_args()

    t = time.monotonic()
    result = flood_run(args.bytes, args.select)
    run_s = time.monotonic() - t
    kept = sum(len(R.wire_events(c.transcript)) for c in result.cases)
    print(f"suite against a {args.bytes / 1e6:g} MB flooder: {len(result.cases)} cases in {run_s:.1f} s, "
          f"verdicts {dict((k, v) for k, v in result.counts().items() if v)}, {kept} bytes kept in all")
    view = load_profile(PROFILE).procedure.report_view()   # the procedure's view, as the command line hands it in
    with tempfile.TemporaryDirectory() as d:
        out = Path(d)
        total = 0.0
        for name, write in (("junit.xml", write_junit), ("results.json", lambda r, p: r.write_json(p)),
                            ("report.html", lambda r, p: write_html(r, p, view))):
            t = time.monotonic()
            write(result, out / name)
            dt = time.monotonic() - t
            total += dt
            print(f"  {name:<13} {(out / name).stat().st_size / 1e6:7.2f} MB written in {dt:5.2f} s")
        print(f"  all reports written in {total:.2f} s")
        t = time.monotonic()
        again = R.RunResult.read_json(out / "results.json")
        write_html(again, out / "again.html", view)
        write_junit(again, out / "again.xml")
        print(f"  ptpcert report (read the JSON, write HTML and JUnit): {time.monotonic() - t:.2f} s")
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"  peak memory of this process: {rss:.0f} MB")


if __name__ == "__main__":
    main()
