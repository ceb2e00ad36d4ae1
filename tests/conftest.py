import os
import sys

# tests/ holds shared helpers (oracle, exact twins, mesh cases) imported as plain modules.
sys.path.insert(0, os.path.dirname(__file__))

# Scenes are cached on disk; tests use a private cache so they never read a user's stale one.
# It is removed when the run ends, so repeated runs do not fill /tmp.
import atexit  # noqa: E402
import shutil  # noqa: E402
import tempfile  # noqa: E402

if "CONECULL_CACHE" not in os.environ:
    _cache = tempfile.mkdtemp(prefix="conecull-cache-")
    os.environ["CONECULL_CACHE"] = _cache
    atexit.register(shutil.rmtree, _cache, ignore_errors=True)

# Hypothesis: a failure always prints how to replay it; in CI (.ci/run sets CONECULL_CI=1) the
# examples are derived from each test's name, so a red run replays identically.
from hypothesis import settings  # noqa: E402

settings.register_profile("conecull", print_blob=True)
settings.register_profile("conecull-ci", print_blob=True, derandomize=True, database=None)
from shared_data import in_ci  # noqa: E402

settings.load_profile("conecull-ci" if in_ci() else "conecull")
