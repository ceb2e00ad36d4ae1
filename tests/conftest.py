import os
import sys

# tests/ holds shared helpers (oracle, exact twins, mesh cases) imported as plain modules.
sys.path.insert(0, os.path.dirname(__file__))
