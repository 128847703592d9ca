"""pytest configuration: the hypothesis settings profiles of ptpcert (both extend
hypothesis's built-in "ci" profile) and where the example database lives.

* ``--hypothesis-profile ptpcert-thorough`` (or PTPCERT_HYPOTHESIS_PROFILE) for a long
  campaign; the default is ``ptpcert-quick``.
* PTPCERT_HYPOTHESIS_DB=DIR keeps the examples (and failures) in DIR, to share a campaign:
  several machines running pytest-xdist workers (``pytest -n auto``) against one database
  on a shared directory is the path past one machine.
"""

import os

from hypothesis import settings
from hypothesis.database import DirectoryBasedExampleDatabase

import ptpcert.fuzz  # noqa: F401  (registers ptpcert-quick and ptpcert-thorough)

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
