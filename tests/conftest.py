import os
import sys

# tests/ holds shared helpers (oracle, exact twins, mesh cases) imported as plain modules.
sys.path.insert(0, os.path.dirname(__file__))

# Scenes are cached on disk; tests use a private cache so they never read a user's stale one.
import tempfile  # noqa: E402

os.environ.setdefault("CONECULL_CACHE", tempfile.mkdtemp(prefix="conecull-cache-"))
