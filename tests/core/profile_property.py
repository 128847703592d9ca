"""The property every profile must have, as a function the tests and the long run share: a
profile the validation accepts configures a reference (sim:, the model in virtual time) that
passes every case and golden vector generated for it; a profile it refuses is refused in one
line that names the key."""

from __future__ import annotations

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


def judge(raw: dict, iut: str = "sim:") -> tuple[str, list[str]]:
    """("refused", [why]) or ("run", the problems: cases that failed or ended in error, and
    an empty suite)."""
    try:
        profile = profile_from_dict(raw, "<drawn>")
    except ProfileError as exc:
        return "refused", [str(exc)]
    cases = load_suite(profile, vectors())
    if not cases:
        return "run", ["no case at all"]
    factory = make_factory(iut, profile)
    try:
        result = R.RunResult(tool_version="test", started="now")
        opts = RunOptions(echo=profile.echo, check_status=profile.status_from_stderr)
        Runner(factory, profile, opts).run(cases, result)
    finally:
        factory.shutdown()
    bad = [f"{c.id}: {c.verdict}: {c.message[:300]}" for c in result.cases
           if c.verdict in (R.FAIL, R.ERROR) or (c.verdict == R.UNSUPPORTED and not c.message.strip())]
    if all(c.verdict == R.UNSUPPORTED for c in result.cases):
        bad.append("every case is unsupported")
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
