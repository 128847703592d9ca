"""The kill matrix: every deliberately broken variant against the suite, with the cases that
caught it. Prints figures; asserts nothing.

    python benchmarks/kill_matrix.py                 # the mutants, in virtual time (sim:)
    python benchmarks/kill_matrix.py --exec          # the mutants as real processes (ptpcert iut --mutant)
    python benchmarks/kill_matrix.py --independent   # the independent implementation's broken variants
    python benchmarks/kill_matrix.py --procedure RK512 [--exec]   # the RK 512 variants
    python benchmarks/kill_matrix.py --procedure ASCII [--exec | --independent]   # the ASCII driver's
    python benchmarks/kill_matrix.py --procedure RK512 --independent   # the independent RK 512 station's variants

Each variant runs with the profile its broken rule needs (e.g. priority high for a priority
bug), at the shortest legal timers.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

from ptpcert import results as R
from ptpcert.procedures.p3964.mutants import MUTANTS
from ptpcert.procedures.p3964.description import reference_profile
from ptpcert.runner import Runner, RunOptions
from ptpcert.scenario import load_vector_sets
from ptpcert.suite import load_suite
from ptpcert.transport import make_factory

ROOT = Path(__file__).resolve().parent.parent
PY = sys.executable
INDEPENDENT = ROOT / "tests" / "independent" / "iut3964.py"
sys.path[:0] = [str(ROOT / "tests" / "procedures" / d) for d in ("rk512", "ascii")]


def run(url: str, profile) -> R.RunResult:
    cases = load_suite(profile, load_vector_sets())
    factory = make_factory(url, profile)
    # a real process on a loaded machine may be slow to start: its late start-up NAK is no verdict
    startup = 2.0 if url.startswith("sim:") else 5.0
    runner = Runner(factory, profile, RunOptions(echo=profile.echo, check_status=profile.status_from_stderr,
                                                 startup_timeout=startup))
    res = R.RunResult(tool_version="bench", started="")
    try:
        runner.run(cases, res)
    finally:
        factory.shutdown()
    return res


def rk512_variants(args):
    """The RK 512 variants: the suite's profile with every role, set-up and area; over exec:
    with timers a loaded machine can keep (the tester answers the IUT's STX within its ADT)."""
    from rk512_profiles import independent_command, independent_variants, iut_command, rk_profile_dict

    from ptpcert.registry import by_id
    from ptpcert.profile import profile_from_dict

    if args.independent:
        # the independent station is a real process: the real-time timers of the exec: runs
        for name, rule in independent_variants().items():
            raw = rk_profile_dict(cdt=100, adt=100, t_res=1000)
            yield name, rule, independent_command(raw, brk=name), profile_from_dict(raw)
        return
    for name, m in by_id("rk512").mutants().items():
        raw = rk_profile_dict(**m.profile, **(dict(cdt=100, adt=100, t_res=1000) if args.exec else {}))
        url = iut_command(raw, mutant=name) if args.exec else f"sim:?mutant={name}"
        yield name, m.rule, url, profile_from_dict(raw)


def ascii_variants(args):
    """The ASCII variants, each with the profile settings its broken rule needs (its
    slow_reader and send_job setups included); over exec: a CDT of 50 ms in the CDT criterion,
    so that a loaded machine does not cut its own frames. --independent: the independent
    station's variants (tests/independent/ascii), through the issue's interface only."""
    from ptpcert.procedures.ascii.description import iut_command
    from ptpcert.procedures.ascii.description import reference_profile as ascii_profile
    from ptpcert.procedures.ascii.mutants import MUTANTS as ASCII_MUTANTS

    if args.independent:
        import tempfile

        from test_ascii_independent import BROKEN, command, profile_text

        from ptpcert.profile import load_profile

        for name, (settings, _select) in BROKEN.items():
            path = Path(tempfile.mkdtemp()) / "p.toml"
            path.write_text(profile_text(settings))
            yield name, "independent variant", f"exec:{command(settings, name)}", load_profile(path)
        return
    for name, m in ASCII_MUTANTS.items():
        settings = dict(m.profile)
        if args.exec and settings.get("end_criterion") == "cdt":
            settings.setdefault("character_delay_ms", 50)
        prof = ascii_profile(**settings)
        url = f"exec:{iut_command(prof.params, mutant=name)}" if args.exec else f"sim:?mutant={name}"
        yield name, m.rule, url, prof


def variants(args):
    if args.procedure == "RK512":
        yield from rk512_variants(args)
        return
    if args.procedure == "ASCII":
        yield from ascii_variants(args)
        return
    if args.independent:
        names = subprocess.run([PY, str(INDEPENDENT), "--list-breaks"], capture_output=True, text=True).stdout.split("\n")
        for line in names:
            if line.strip():
                name = line.split()[0]
                prof = reference_profile(priority="high" if "prio" in name else "low")
                url = (f"exec:{PY} {INDEPENDENT} --cdt-ms 20 --adt-ms 20 --parmrk --priority {prof.params.priority} "
                       f"--break {name}")
                yield name, line[len(name):].strip(), url, prof
        return
    for name, m in MUTANTS.items():
        prof = reference_profile(**m.profile)
        if args.exec:
            url = (f"exec:{PY} -m ptpcert.cli iut --cdt-ms 20 --adt-ms 20 --parmrk "
                   f"--priority {prof.params.priority} --mutant {name}")
        else:
            url = f"sim:?mutant={name}"
        yield name, m.rule, url, prof


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exec", action="store_true", help="run the mutants as real processes over exec:")
    ap.add_argument("--independent", action="store_true", help="the independent implementation's variants")
    ap.add_argument("--only", nargs="*", help="only these variant names")
    ap.add_argument("--procedure", choices=["3964R", "RK512", "ASCII"], default="3964R",
                    help="the procedure whose variants run (default 3964R)")
    args = ap.parse_args()
    t0 = time.monotonic()
    missed = []
    rows = []
    for name, rule, url, prof in variants(args):
        if args.only and name not in args.only:
            continue
        t = time.monotonic()
        res = run(url, prof)
        caught = [c.id for c in res.cases if c.verdict in (R.FAIL, R.XPASS)]
        errors = [c.id for c in res.cases if c.verdict == R.ERROR]
        rows.append((name, rule, caught, errors, time.monotonic() - t))
        if not caught:
            missed.append(name)
        print(f"{name:<30} caught by {len(caught):>3} case(s) in {time.monotonic() - t:5.1f} s   {rule}", flush=True)
        for cid in caught:
            print(f"    {cid}")
        for cid in errors:
            print(f"    (error) {cid}")
    print()
    print(f"{len(rows)} variants, {len(rows) - len(missed)} caught, {len(missed)} missed"
          + (f": {', '.join(missed)}" if missed else "") + f"; {time.monotonic() - t0:.0f} s")


if __name__ == "__main__":
    main()
