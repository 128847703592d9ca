"""The property every profile must have, as a function the tests and the long run share: a
profile the validation accepts configures a reference (sim:, the model in virtual time) that
passes every case and golden vector generated for it; a profile it refuses is refused in one
line that names the key."""

from __future__ import annotations

import random

from ptpcert import results as R
from ptpcert.profile import ProfileError, profile_from_dict
from ptpcert.runner import Runner, RunOptions
from ptpcert.scenario import load_vector_sets
from ptpcert.suite import load_suite
from ptpcert.transport import make_factory

_VECTORS = None


def vectors():
    global _VECTORS
    if _VECTORS is None:
        _VECTORS = load_vector_sets()
    return _VECTORS


def judge(raw: dict, iut: str = "sim:", sample: int = 0, seed: int = 0) -> tuple[str, list[str]]:
    """("refused", [why]) or ("run", the problems: cases that failed or ended in error, and
    an empty suite). A profile that leaves nothing to test is refused as the commands refuse
    it (:meth:`ptpcert.runner.Runner.nothing_to_test`). ``sample``: run only this many of the cases, drawn with ``seed``."""
    try:
        profile = profile_from_dict(raw, "<drawn>")
    except ProfileError as exc:
        return "refused", [str(exc)]
    cases = load_suite(profile, vectors())
    if not cases:
        return "run", ["no case at all"]
    if sample and len(cases) > sample:
        cases = random.Random(seed).sample(cases, sample)
    factory = make_factory(iut, profile)
    try:
        result = R.RunResult(tool_version="test", started="now")
        opts = RunOptions(echo=profile.echo, check_status=profile.status_from_stderr)
        runner = Runner(factory, profile, opts)
        idle = None if sample else runner.nothing_to_test(cases)
        if idle:   # run, fuzz and the plugin refuse it in this one line (exit 2)
            return "refused", [f"{profile.procedure.title}: {idle}"]
        runner.run(cases, result)
    finally:
        factory.shutdown()
    bad = [f"{c.id}: {c.verdict}: {c.message[:300]}" for c in result.cases
           if c.verdict in (R.FAIL, R.ERROR) or (c.verdict == R.UNSUPPORTED and not c.message.strip())]
    if not sample and all(c.verdict == R.UNSUPPORTED for c in result.cases):
        bad.append("every case is unsupported, and nothing said so before the run")
    return "run", bad


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise TypeError(type(v))


def to_toml(raw: dict) -> str:
    """A drawn profile as the file a user would write (tables of scalars and lists, and
    [iut.setups])."""
    lines = []
    for table, keys in raw.items():
        sub = {k: v for k, v in keys.items() if isinstance(v, dict)}
        lines.append(f"[{table}]")
        lines += [f"{k} = {_toml_value(v)}" for k, v in keys.items() if not isinstance(v, dict)]
        for name, inner in sub.items():
            lines += ["", f"[{table}.{name}]"] + [f"{k} = {_toml_value(v)}" for k, v in inner.items()]
        lines.append("")
    return "\n".join(lines)


#: the shortest timer a real-time test sets: what a loaded 2-core machine keeps (timers of a
#: few milliseconds would end in harness timing faults, honest errors, but no verdict)
REALTIME_TIMER_MS = 20


def in_real_time(proc, raw: dict) -> dict:
    """``raw`` as a profile to run in real time: every timer at the shortest setting the
    schema allows for the profile (as real-time tests use), but not under
    :data:`REALTIME_TIMER_MS`, at 9600 bit/s or faster (a kilobyte at 300 bit/s takes half
    a minute); every other key as drawn."""
    out = {t: dict(v) for t, v in raw.items()}
    base = out.get("iut", {}).get("baud_rate")
    if isinstance(base, int) and base < 9600:
        out["iut"]["baud_rate"] = 9600
    values = {k: v for t in out.values() for k, v in t.items() if not isinstance(v, dict)}
    defaults = {k.name: k.default for k in proc.profile_schema() if not k.required}
    values = {**defaults, **values}
    for key in proc.profile_schema():
        if key.unit == "ms" and key.kind == "int" and key.applies(values):
            low = max(int(key.low(values)), REALTIME_TIMER_MS)
            step = key.step
            out.setdefault(key.table, {})[key.name] = low if step == 1 or low % step == 0 else low + step - low % step
    return out


def exec_url(python: str, profile_path, raw: dict) -> str:
    """The reference configured from the profile file, as an exec: IUT (with the request
    script's place where the profile's IUT takes request scripts)."""
    cmd = f"exec:{python} -m ptpcert.cli iut --profile {profile_path}"
    if raw.get("rk512", {}).get("requests", "script") == "script" and raw["iut"]["procedure"].upper() == "RK512":
        cmd += " --requests {requests}"
    return cmd
