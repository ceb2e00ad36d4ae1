"""Scenes and mesh sequences: `names()`, `load(name, resolution=None, frames=None)` (cached on
disk), generators in `generated`, file loaders in `inputs`."""

from conecull.datasets.registry import SCENES, cache_dir, describe, load, names

__all__ = ["names", "load", "describe", "cache_dir", "SCENES"]
