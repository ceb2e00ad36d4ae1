"""Effects of the simulator, one module per kind (forces, constraints, colliders, contact), one class each, in five stages:
  force(sim, dt)       adds to velocities before prediction (gravity, wind);
  constrain(sim, dt)   projects predicted positions, XPBD style (stretch, bend);
  collide(sim, dt)     pushes predicted positions out of kinematic colliders, with friction;
  pin(sim, t)          overrides positions of pinned vertices;
  contact(sim, dt)     last: keeps the step free of self-contact (conecull's own CCD).
Each effect implements only the stages it needs; the simulator calls only declared effects."""

from conecull.datasets.sim.effects.base import Effect, _scatter_add
from conecull.datasets.sim.effects.colliders import CapsuleCollider, FunnelCollider, PlaneCollider, SphereCollider
from conecull.datasets.sim.effects.constraints import (Bend, IsometricBend, PinnedVertices, Stretch, StrainLimit,
                                                       Tethers, grid_skip_pairs)
from conecull.datasets.sim.effects.contact import SelfContact
from conecull.datasets.sim.effects.forces import Gravity, Wind

__all__ = ["Effect", "Gravity", "Wind", "PinnedVertices", "Tethers", "Stretch", "StrainLimit", "Bend", "IsometricBend",
           "PlaneCollider", "SphereCollider", "FunnelCollider", "CapsuleCollider", "SelfContact"]
