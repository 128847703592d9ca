"""A suite that is right for every profile a user writes. For profiles drawn from the profile
schema (every key within the manual's ranges, the combinations the validation allows), the
reference configured from the profile passes every case and golden vector generated for it:
no fail, no error, no harness fault; a case that cannot be built for a setting is unsupported
with its reason. A profile the validation refuses is refused in one line that names the key.

In virtual time (sim:, which is the IUT the profile declares) a fixed number of profiles per
procedure here; ``benchmarks/profile_property.py`` is the long run. A few drawn profiles run
in real time against ``exec:ptpcert iut --profile FILE``."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, Phase, given, settings
from profile_property import judge, to_toml

from ptpcert.fuzz.profiles import profile_dicts
from ptpcert.profile import load_profile
from ptpcert.registry import by_id, procedures

ROOT = Path(__file__).resolve().parents[2]
PY = sys.executable
#: profiles drawn per procedure in the fast tests
EXAMPLES = 60


def _check(raw: dict, iut: str = "sim:") -> None:
    kind, problems = judge(raw, iut)
    if kind == "refused":
        (why,) = problems
        assert "\n" not in why and ": " in why, why
        return
    assert not problems, "the reference fails under this profile:\n" + to_toml(raw) + "\n" + "\n".join(problems[:20])


@pytest.mark.parametrize("pid", [p.id for p in procedures() if p.suite])
def test_the_reference_passes_under_every_drawn_profile(pid):
    proc = by_id(pid)

    @settings(max_examples=EXAMPLES, deadline=None, database=None,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
    @given(profile_dicts(proc, setups=dict(proc.reference_setups)))
    def check(raw):
        _check(raw)
    check()


def test_a_drawn_profile_round_trips_through_its_file(tmp_path):
    """The profiles the property uses are the files users write: written out and read back,
    the loader makes the same profile of them."""
    from ptpcert.profile import profile_from_dict
    for proc in procedures():
        if not proc.suite:
            continue
        raw = profile_dicts(proc, setups=dict(proc.reference_setups)).example()
        f = tmp_path / f"{proc.id}.toml"
        f.write_text(to_toml(raw))
        try:
            want = profile_from_dict(raw, str(f))
        except ValueError:
            continue
        assert load_profile(f) == want


#: profiles drawn per procedure, and cases of each run, in the real-time sample
REALTIME_PROFILES = 2
REALTIME_CASES = 30


@pytest.mark.realtime
@pytest.mark.parametrize("pid", [p.id for p in procedures() if p.suite])
def test_a_sample_of_drawn_profiles_passes_over_exec(pid, tmp_path):
    """``exec:ptpcert iut --profile FILE`` is the reference for any profile: drawn profiles
    (their timers at the shortest legal setting, as real-time tests run) pass a sample of
    their cases with the reference as a process, paced by the line."""
    from profile_property import exec_url, in_real_time
    proc = by_id(pid)
    seen = []

    # no shrinking in real time: the profile that failed is printed whole
    @settings(max_examples=REALTIME_PROFILES, deadline=None, database=None, derandomize=True,
              suppress_health_check=list(HealthCheck), phases=[Phase.explicit, Phase.generate])
    @given(profile_dicts(proc, setups=dict(proc.reference_setups)))
    def check(raw):
        raw = in_real_time(proc, raw)
        f = tmp_path / f"drawn{len(seen)}.toml"
        f.write_text(to_toml(raw))
        kind, problems = judge(raw, exec_url(PY, f, raw), sample=REALTIME_CASES, seed=len(seen))
        seen.append(kind)
        if kind == "refused":
            return
        assert not problems, "the reference over exec: fails under this profile:\n" + to_toml(raw) + "\n" + \
            "\n".join(problems[:20])
    check()
    assert seen
