"""``ptpcert fuzz``: generated partner behaviour against an IUT, the model as the oracle;
one campaign, or several worker processes over a shared example database."""

from __future__ import annotations

import sys

from ptpcert import __version__

from .common import load_profile, number
from .run import Interrupts, connect

BUDGET_S = number(float, 1, 7 * 24 * 3600, "seconds")
MAX_ACTIONS = number(int, 1, 100)
WORKERS = number(int, 1, 64)


def add_commands(sub) -> None:
    """The ``fuzz`` command."""
    f = sub.add_parser("fuzz", help="fuzz an IUT with generated partner behaviour, the model as oracle",
                       description="Generate partner behaviour (hypothesis), predict a conforming IUT's answers "
                                   "with the reference model, and report every divergence as a shrunk "
                                   "transcript, saved as a vector. Exit status: 0 nothing found, 1 findings, "
                                   "2 bad usage or a harness error.")
    f.add_argument("--iut", required=True, metavar="URL", help="as for 'ptpcert run'")
    f.add_argument("--profile", required=True, metavar="FILE", help="the IUT profile (TOML)")
    f.add_argument("--budget", type=BUDGET_S, default=60.0, metavar="SECONDS",
                   help="time budget (default 60; 1 to 604800, a week)")
    f.add_argument("--seed", type=int, default=None, help="seed (printed, so any run can be replayed)")
    f.add_argument("--export", metavar="DIR", default=None,
                   help="where findings are written as vectors (default: ./vectors/regressions in the current directory)")
    f.add_argument("--settings", choices=["ptpcert-quick", "ptpcert-thorough"], default="ptpcert-quick",
                   help="hypothesis settings profile (both extend hypothesis's 'ci' profile)")
    f.add_argument("--database", metavar="DIR",
                   help="hypothesis example database, to share a campaign between runs or machines")
    f.add_argument("--max-actions", type=MAX_ACTIONS, default=6, help="tester actions per example (default 6; 1 to 100)")
    f.add_argument("--workers", type=WORKERS, default=1, metavar="N",
                   help="example streams at once, each a process with its own IUT instance (exec:, pty:, "
                        "sim:), all sharing the example database (default 1; 1 to 64)")
    f.set_defaults(func=cmd_fuzz)


def cmd_fuzz(args) -> int:
    import random
    import time

    from ptpcert.fuzz import Campaign, export, register_profiles
    from ptpcert.paths import findings_dir
    from ptpcert.runner import Runner, RunOptions

    register_profiles()

    profile = load_profile("fuzz", args.profile)
    if profile is None:
        return 2
    seed = args.seed if args.seed is not None else random.SystemRandom().randrange(1, 2**31)
    out_dir = args.export or str(findings_dir())
    # before the first example: a finding must never be lost for want of a place to put it
    from ptpcert.results import directory_problem
    problem = directory_problem(out_dir)
    if problem:
        print(f"ptpcert fuzz: --export {out_dir}: {problem}", file=sys.stderr)
        return 2
    try:
        from ptpcert.fuzz import open_database
        open_database(args.database)
    except (ValueError, OSError) as exc:
        print(f"ptpcert fuzz: {exc}", file=sys.stderr)
        return 2
    if args.workers > 1:
        if not args.iut.startswith(("exec:", "pty:", "sim:")):
            print(f"ptpcert fuzz: --workers {args.workers} needs an IUT that can be started several times "
                  f"(exec:, pty:, sim:); {args.iut} is one line", file=sys.stderr)
            return 2
        return _fuzz_workers(args, profile, seed, out_dir)
    with Interrupts(args) as interrupts:
        camp = None
        interrupted = False
        factory = None
        try:
            factory = connect("fuzz", args.iut, profile)
            if factory is None:
                interrupts.disarm()
                return 2
            print(f"ptpcert fuzz {__version__}: iut {args.iut}, profile {args.profile}")
            print(f"seed {seed}, settings {args.settings}, budget {args.budget:g} s"
                  + (f", database {args.database}" if args.database else ""))
            print(f"replay: ptpcert fuzz --iut '{args.iut}' --profile {args.profile} --seed {seed} "
                  f"--settings {args.settings} --budget {args.budget:g}", flush=True)
            kit = profile.procedure.fuzz_kit()
            check = bool(kit is not None and kit.check_reports and profile.status_from_stderr)
            runner = Runner(factory, profile, RunOptions(check_status=check, late_ms=50.0))
            idle = nothing_to_fuzz(runner, profile)
            if idle:
                interrupts.disarm()
                factory.shutdown()
                print(f"ptpcert fuzz: {idle}", file=sys.stderr)
                return 2
            camp = Campaign(profile, runner, args.budget, seed, args.settings, args.database,
                            progress=lambda line: print(line, flush=True), max_actions=args.max_actions)
            camp.run()
            interrupts.disarm()
        except KeyboardInterrupt:
            interrupted = True
        interrupts.disarm()
        if factory is not None:
            factory.shutdown()
        interrupted = interrupted or interrupts.count > 0
        if camp is None:
            return 2
        try:
            paths = export(camp.findings, out_dir) if camp.findings else []
        except OSError as exc:
            print(f"ptpcert fuzz: findings cannot be written to {out_dir} ({exc.strerror or exc})", file=sys.stderr)
            paths, interrupted = [], True
    elapsed = time.monotonic() - camp.started if camp.started else 0.0
    print(f"\n{camp.examples} examples in {elapsed:.1f} s ({camp.examples / max(elapsed, 1e-9):.1f}/s), "
          f"{len(camp.findings)} finding(s), {camp.informational} divergence(s) explained by another reading, "
          f"{camp.not_reproduced} not reproduced, {camp.void} void (interruption reached the IUT late)"
          + (", INTERRUPTED" if interrupted else ""))
    _blocks(camp.findings, paths)
    if interrupted:
        return 2
    return 1 if camp.findings else 0


def _blocks(findings, paths) -> None:
    """The end of a campaign's output: one block per finding (the rule broken, the STATUS
    events involved, the shrunk transcript) and the files its vectors were written to."""
    for f in findings:
        print("\n" + f.describe())
    if paths:
        print()
    for p in paths:
        print(f"  written: {p}")


def nothing_to_fuzz(runner, profile) -> str | None:
    """Why the fuzzer has nothing to search under ``profile`` with this IUT: where every
    case of the suite generated for the profile is unsupported (the IUT neither answers nor
    sends anything the profile lets the harness drive), a campaign could find nothing, and
    its "0 findings" would read as a clean bill."""
    from ptpcert.scenario import load_vector_sets
    from ptpcert.suite import load_suite

    return runner.nothing_to_test(load_suite(profile, load_vector_sets()))


def _fuzz_workers(args, profile, seed: int, out_dir: str) -> int:
    """``ptpcert fuzz --workers N``: N campaigns at once (:func:`ptpcert.fuzz.run_workers`)."""
    from ptpcert.fuzz import WorkerSpec, export, run_workers

    factory = connect("fuzz", args.iut, profile)   # the IUT starts: checked once, here
    if factory is None:
        return 2
    from ptpcert.runner import Runner

    idle = nothing_to_fuzz(Runner(factory, profile), profile)
    factory.shutdown()
    if idle:
        print(f"ptpcert fuzz: {idle}", file=sys.stderr)
        return 2
    print(f"ptpcert fuzz {__version__}: iut {args.iut}, profile {args.profile}, {args.workers} workers")
    print(f"seed {seed}, settings {args.settings}, budget {args.budget:g} s"
          + (f", database {args.database}" if args.database else ""))
    print(f"replay: ptpcert fuzz --iut '{args.iut}' --profile {args.profile} --seed {seed} "
          f"--settings {args.settings} --budget {args.budget:g} --workers {args.workers}", flush=True)
    spec = WorkerSpec(args.iut, str(args.profile), args.budget, seed, args.settings, args.database,
                      args.max_actions, args.workers)
    with Interrupts(args) as interrupts:
        res = run_workers(spec, progress=lambda line: print(line, flush=True))
        interrupts.disarm()
    interrupted = res.interrupted or interrupts.count > 0
    for i, why in res.errors:
        print(f"ptpcert fuzz: worker {i}: {why}", file=sys.stderr)
    try:
        paths = export(res.findings, out_dir) if res.findings else []
    except OSError as exc:
        print(f"ptpcert fuzz: findings cannot be written to {out_dir} ({exc.strerror or exc})", file=sys.stderr)
        paths, interrupted = [], True
    print(f"\n{res.examples} examples in {res.elapsed:.1f} s ({res.examples / max(res.elapsed, 1e-9):.1f}/s, "
          f"{args.workers} workers), {len(res.findings)} finding(s), {res.informational} divergence(s) "
          f"explained by another reading, {res.not_reproduced} not reproduced, {res.void} void "
          "(interruption reached the IUT late)" + (", INTERRUPTED" if interrupted else ""))
    _blocks(res.findings, paths)
    if interrupted or (res.errors and not res.findings):
        return 2
    return 1 if res.findings else 0
