"""pytest configuration: the hypothesis settings profiles of ptpcert (both extend
hypothesis's built-in "ci" profile) and where the example database lives.

* ``--hypothesis-profile ptpcert-thorough`` (or PTPCERT_HYPOTHESIS_PROFILE) for a long
  campaign; the default is ``ptpcert-quick``.
* PTPCERT_HYPOTHESIS_DB=DIR keeps the examples (and failures) in DIR, to share a campaign:
  several machines running pytest-xdist workers (``pytest -n auto``) against one database
  on a shared directory is the path past one machine.
"""

import os

import pytest
from hypothesis import settings
from hypothesis.database import DirectoryBasedExampleDatabase

from ptpcert.fuzz.settings import register_profiles

register_profiles()   # ptpcert-quick and ptpcert-thorough

_profile = os.environ.get("PTPCERT_HYPOTHESIS_PROFILE", "ptpcert-quick")
_db = os.environ.get("PTPCERT_HYPOTHESIS_DB")
if _db:
    settings.register_profile(_profile + "-shared", parent=settings.get_profile(_profile),
                              database=DirectoryBasedExampleDatabase(_db))
    _profile += "-shared"
settings.load_profile(_profile)


def pytest_report_header(config):
    s = settings.default
    return (f"hypothesis profile: {config.getoption('hypothesis_profile', None) or _profile} "
            f"(max_examples={s.max_examples}, derandomize={s.derandomize}, database={s.database})")


@pytest.fixture(autouse=True)
def _no_host_steal_in_fast_tests(request, monkeypatch):
    """A fast test runs the model in virtual time, sometimes behind a transport the runner
    takes for a real-time one: the host's steal time (ptpcert.priority.steal_time), read
    between two of its virtual instants, must not change its outcome. Tests marked realtime
    run against the real machine and keep it; a test that needs steal fakes it."""
    if request.node.get_closest_marker("realtime") is None:
        from ptpcert import priority
        monkeypatch.setattr(priority, "steal_time", lambda: None)
