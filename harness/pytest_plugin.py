"""pytest plugin: the conformance cases as pytest items, for vendors whose CI already runs
pytest.

    pytest --ptpcert-iut 'exec:./my-driver --stdio' --ptpcert-profile my-iut.toml

collects every case of the suite and the golden vectors for the profile as one item each,
with the case id as its node id and its group as a marker (``-k`` and ``-m`` select), and
runs it through the same runner as ``ptpcert run``. Verdicts map to pytest outcomes: pass,
non-strict and informational pass (the grade is shown in the report section), fail fails,
unsupported skips, an expected failure of the profile is an xfail (an unexpected pass
fails: strict), and a harness error is a pytest *error*. ``--junitxml`` and pytest-xdist
(``-n 4``: every worker starts its own IUT processes; use it with exec:, pty: and sim:,
not with one serial port) work as usual; ``--ptpcert-shard K/N`` collects only shard K of N,
split as ``ptpcert run --shard K/N`` splits the cases.

Nothing is imported and nothing is collected unless ``--ptpcert-iut`` is given, so the
plugin costs other pytest runs nothing.
"""

from __future__ import annotations

import math

import pytest

_STATE = pytest.StashKey[dict]()


def pytest_addoption(parser) -> None:
    g = parser.getgroup("ptpcert", "ptpcert conformance cases")
    g.addoption("--ptpcert-iut", metavar="URL", default=None,
                help="run the ptpcert cases against this IUT (exec:COMMAND, pty:COMMAND, sim:, a serial URL)")
    g.addoption("--ptpcert-profile", metavar="FILE", default=None, help="the IUT profile (TOML)")
    g.addoption("--ptpcert-vectors", metavar="DIR", action="append", default=[],
                help="a directory of vectors in addition to the bundled golden vectors (repeatable)")
    g.addoption("--ptpcert-select", metavar="GLOB", action="append", default=[],
                help="only cases whose id matches (repeatable; -k works too)")
    g.addoption("--ptpcert-shard", metavar="K/N", default=None,
                help="only shard K of N of the cases, as 'ptpcert run --shard K/N' splits them")
    g.addoption("--ptpcert-tolerance-ms", type=float, default=50.0,
                help="how late a reply may be beyond its window, plus 25%% of the window (default 50)")
    g.addoption("--ptpcert-evidence", metavar="FILE.zip", default=None,
                help="write the cases' evidence bundle at the end (as 'ptpcert run --evidence'; 'ptpcert verify' "
                     "checks it)")
    g.addoption("--ptpcert-sign", metavar="KEY", default=None,
                help="sign the evidence bundle's manifest with this OpenSSH private key")


def _group_marker(group: str) -> str:
    return "ptpcert_" + group.replace("-", "_")


def pytest_configure(config) -> None:
    # bad input is refused as `ptpcert run` refuses it: one usage error, before any case
    url = config.getoption("--ptpcert-iut")
    path = config.getoption("--ptpcert-profile")
    if url is None:
        if path is not None:
            raise pytest.UsageError("ptpcert: --ptpcert-profile needs --ptpcert-iut URL (the IUT to run the "
                                    "cases against); without it no case is collected")
        return
    if not url.strip():
        raise pytest.UsageError("ptpcert: --ptpcert-iut is empty; give the IUT's URL (exec:COMMAND, pty:COMMAND, "
                                "sim:, a serial URL)")
    if not path:
        raise pytest.UsageError("ptpcert: --ptpcert-iut needs --ptpcert-profile FILE (the IUT profile)")
    tolerance = config.getoption("--ptpcert-tolerance-ms")
    if not (math.isfinite(tolerance) and 0 <= tolerance <= 10_000):
        raise pytest.UsageError(f"ptpcert: --ptpcert-tolerance-ms {tolerance:g} is out of range (allowed: a "
                                "number from 0 to 10000 milliseconds)")
    shard = config.getoption("--ptpcert-shard")
    if shard is not None:
        from .results import parse_shard
        try:
            shard = parse_shard(shard)
        except ValueError as exc:
            raise pytest.UsageError(f"ptpcert: --ptpcert-shard {exc}") from None
    from .procedure import ProcedureError
    from .profile import ProfileError, load_profile
    from .scenario import VectorError, load_vector_sets
    from .suite import check_expected_failures, load_suite

    try:
        profile = load_profile(path)
        vectors = load_vector_sets(config.getoption("--ptpcert-vectors"))
        check_expected_failures(profile, load_suite(profile, vectors))
        cases = load_suite(profile, vectors, select=config.getoption("--ptpcert-select") or None)
    except (ProfileError, VectorError, ProcedureError, ValueError) as exc:
        raise pytest.UsageError(f"ptpcert: {exc}") from None
    if not cases:
        raise pytest.UsageError("ptpcert: no case matches --ptpcert-select "
                                + " ".join(config.getoption("--ptpcert-select")))
    config.addinivalue_line("markers", "ptpcert: a ptpcert conformance case")
    for g in profile.procedure.groups:
        config.addinivalue_line("markers", f"{_group_marker(g)}: ptpcert cases of the group '{g}'")
    selection = cases
    if shard is not None:
        from .suite import shard_of
        cases = shard_of(profile, selection, *shard)[0]
    evidence = _evidence_args(config, tolerance)
    if evidence is not None:
        evidence.shard = shard
        from .evidence.output import options_problem
        problem = options_problem(evidence)
        if problem:
            raise pytest.UsageError(f"ptpcert: {problem}")
    config.stash[_STATE] = {"url": url, "profile": profile, "cases": cases, "runner": None,
                            "evidence": evidence, "results": {}}
    idle = _runner(config).nothing_to_test(selection)
    if idle:   # every case would skip: a gate must not read that as a pass
        raise pytest.UsageError(f"ptpcert: {idle}")


def pytest_collection_modifyitems(session, config, items) -> None:
    state = config.stash.get(_STATE, None)
    if state is None:
        return
    for v in state["cases"]:
        item = CaseItem.from_parent(session, name=v.id, nodeid=v.id, vector=v)
        item.add_marker("ptpcert")
        item.add_marker(_group_marker(v.group))
        items.append(item)


def _runner(config):
    state = config.stash[_STATE]
    if state["runner"] is None:
        from .runner import RunOptions, Runner
        from .transport import TransportError, make_factory, preflight

        profile = state["profile"]
        try:
            factory = make_factory(state["url"], profile)
        except TransportError as exc:
            raise pytest.UsageError(f"ptpcert: {exc}") from None
        try:   # an IUT that cannot even start is the harness's error, not 100 failed cases
            preflight(state["url"], factory, profile.params)
        except TransportError as exc:
            factory.shutdown()
            raise pytest.UsageError(f"ptpcert: the IUT could not be started: {exc}") from None
        opts = RunOptions(late_ms=config.getoption("--ptpcert-tolerance-ms"), echo=profile.echo,
                          check_status=profile.status_from_stderr)
        state["runner"] = Runner(factory, profile, opts)
    return state["runner"]


def _now() -> str:
    """The time now, to the second, for the bundle's results."""
    import datetime as dt
    return dt.datetime.now(dt.timezone.utc).astimezone().isoformat(timespec="seconds")


def _evidence_args(config, tolerance: float):
    """The options of the evidence bundle as ``ptpcert run`` has them, or None without
    ``--ptpcert-evidence``."""
    import argparse

    path, key = config.getoption("--ptpcert-evidence"), config.getoption("--ptpcert-sign")
    if path is None and key is None:
        return None
    if path is None:
        raise pytest.UsageError("ptpcert: --ptpcert-sign needs --ptpcert-evidence FILE.zip")
    if getattr(config.option, "numprocesses", None):   # each xdist worker holds only its own cases
        raise pytest.UsageError("ptpcert: --ptpcert-evidence collects every case in one process: run it without -n")
    return argparse.Namespace(evidence=path, sign=key, tolerance_ms=tolerance,
                              select=config.getoption("--ptpcert-select"), vectors=config.getoption("--ptpcert-vectors"),
                              vectors_only=False, priority="normal", jobs=1)


def pytest_sessionfinish(session, exitstatus) -> None:
    """The evidence bundle of the cases run (every case not reached: not run)."""
    state = session.config.stash.get(_STATE, None)
    if state is None or state["evidence"] is None or hasattr(session.config, "workerinput"):
        return
    from . import __version__
    from . import results as R
    from .evidence.output import write_evidence
    from .scenario import vector_set_hash

    profile, cases = state["profile"], state["cases"]
    result = R.RunResult(tool_version=__version__, started=state.get("started", _now()), iut=state["url"],
                         procedure=profile.procedure.title, profile=profile.to_dict(), profile_path=str(profile.path),
                         vector_set="bundled", vector_set_hash=vector_set_hash(cases), iut_identity=dict(profile.identity))
    result.cases = [state["results"][v.id] for v in cases if v.id in state["results"]]
    result.interrupted = bool(session.shouldstop) or exitstatus == pytest.ExitCode.INTERRUPTED
    result.fill_missing(cases, R.NOT_RUN, "not run in this pytest session")
    result.finished = _now()
    write_evidence(result, state["evidence"], profile, cases, [state["url"]], profile.procedure.report_view(),
                   cmd="pytest")


def pytest_unconfigure(config) -> None:
    state = config.stash.get(_STATE, None)
    if state is not None and state["runner"] is not None:
        state["runner"].factory.shutdown()


class CaseFailed(Exception):
    """The IUT did not do what the case's rule says."""


class HarnessError(Exception):
    """The harness could not run the case (never a verdict on the IUT)."""


class CaseItem(pytest.Item):
    def __init__(self, *, vector, **kw):
        super().__init__(**kw)
        self.vector = vector
        self.result = None

    def setup(self) -> None:
        # the case runs here, so that a harness error is a pytest error, not a failure
        from . import results as R

        state = self.config.stash[_STATE]
        if "started" not in state:
            state["started"] = _now()
        self.result = res = _runner(self.config).run_case(self.vector)
        state["results"][self.vector.id] = res
        self.user_properties.append(("verdict", res.verdict))
        self.user_properties.append(("reference", self.vector.reference))
        if res.verdict == R.ERROR:
            raise HarnessError(res.message)

    def runtest(self) -> None:
        from . import results as R
        from .report import failure_text

        res = self.result
        if res.message or res.notes:
            self.add_report_section("call", "ptpcert", "\n".join([f"{res.verdict}: {res.message}", *res.notes]))
        if res.verdict == R.UNSUPPORTED:
            pytest.skip(f"unsupported: {res.message}")
        if res.verdict == R.XFAIL:
            pytest.xfail(res.message)
        if res.verdict == R.XPASS:
            raise CaseFailed(res.message)
        if res.verdict == R.NOT_RUN:
            pytest.skip(res.message or "not run")
        if res.verdict == R.FAIL:
            raise CaseFailed(failure_text(res))

    def repr_failure(self, excinfo):
        if isinstance(excinfo.value, (CaseFailed, HarnessError)):
            v = self.vector
            return f"{v.id}: {v.title}\n  rule: {v.rule}\n  manual: {v.reference}\n{excinfo.value}"
        return super().repr_failure(excinfo)

    def reportinfo(self):
        return self.path, None, f"{self.vector.id} ({self.vector.reference})"
