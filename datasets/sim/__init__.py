"""A small position-based simulator whose effects are modules: a scene declares its effects and
only those are ever constructed or computed (`Simulator.calls` counts what ran)."""

from conecull.datasets.sim.effects import (Bend, CapsuleCollider, FunnelCollider, Gravity, IsometricBend,
                                           PinnedVertices, PlaneCollider, SelfContact, SphereCollider, StrainLimit,
                                           Stretch, Tethers, Wind, grid_skip_pairs)
from conecull.datasets.sim.simulator import Simulator

__all__ = ["Simulator", "Gravity", "PinnedVertices", "Wind", "Stretch", "Bend", "IsometricBend", "PlaneCollider",
           "SphereCollider", "SelfContact", "FunnelCollider", "CapsuleCollider", "Tethers", "StrainLimit",
           "grid_skip_pairs"]
