"""Static capacities (`Static`) and traced physical constants (`Params`) of the engine.

`Static` is frozen and hashable: every number in it sets an array shape, a loop length or a branch,
so a change means a new compile. `Params` holds constants that are traced (and may be vmapped):
changing them never recompiles.
"""

from __future__ import annotations

import dataclasses

from flax import struct

NUM_ARENA_POLYGONS = 4
"""Polygon slots 0..3 hold the static arena: floor, left wall, right wall, ceiling."""


@dataclasses.dataclass(frozen=True)
class Static:
    """Compile-time capacities of a scene. Two scenes with equal `Static` share one compiled step.

    Attributes:
        num_polygons: polygon slots, including the 4 arena slots.
        num_circles: circle slots.
        num_joints: joint slots (revolute or fixed).
        num_thrusters: thruster slots.
        solver_iterations: velocity-solver (Gauss-Seidel) sweeps per step.
        max_contacts: contact points solved per step; when more points touch, the deepest are kept and
            the rest are counted in `StepInfo.dropped_contacts`. 0 means "every candidate point".
    """

    num_polygons: int
    num_circles: int
    num_joints: int
    num_thrusters: int
    solver_iterations: int = 10
    max_contacts: int = 0

    def __post_init__(self) -> None:
        if self.num_polygons < NUM_ARENA_POLYGONS:
            raise ValueError(f"num_polygons must be >= {NUM_ARENA_POLYGONS} (the arena), got {self.num_polygons}")
        for name in ("num_circles", "num_joints", "num_thrusters", "max_contacts"):
            if getattr(self, name) < 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")
        if self.solver_iterations < 1:
            raise ValueError(f"solver_iterations must be >= 1, got {self.solver_iterations}")
        if self.num_bodies < 1:
            raise ValueError("a scene needs at least one body slot")

    @property
    def num_bodies(self) -> int:
        """Polygons then circles: body slots [0, P) are polygons, [P, P + C) circles."""
        return self.num_polygons + self.num_circles

    def slot(self, kind: str, index):
        """The body slot of the `index`-th body of `kind`: 'arena' (slots 0-3: floor, left wall, right wall,
        ceiling), 'polygon' (the level's polygons, from slot 4) or 'circle' (from slot `num_polygons`). The one
        rule that numbers body slots; `index` may be an int or a traced array."""
        first = {"arena": 0, "polygon": NUM_ARENA_POLYGONS, "circle": self.num_polygons}
        if kind not in first:
            raise ValueError(f"kind must be one of {', '.join(first)}, got {kind!r}")
        return first[kind] + index

    @property
    def num_actions(self) -> int:
        """One action per joint (motor, in [-1, 1]) then one per thruster (in [0, 1])."""
        return self.num_joints + self.num_thrusters

    def replace(self, **changes) -> Static:
        return dataclasses.replace(self, **changes)


SIZES: dict[str, Static] = {
    "s": Static(num_polygons=5, num_circles=2, num_joints=1, num_thrusters=1, max_contacts=8),
    "m": Static(num_polygons=6, num_circles=3, num_joints=2, num_thrusters=2, max_contacts=12),
    "l": Static(num_polygons=12, num_circles=4, num_joints=6, num_thrusters=2, max_contacts=24),
}
"""The Kinetix sizes (polygons incl. arena / circles / joints / thrusters): s 5/2/1/1, m 6/3/2/2, l 12/4/6/2."""


def size(name: str) -> Static:
    """The `Static` of a named size ('s', 'm', 'l'); raises ValueError naming the choices otherwise."""
    try:
        return SIZES[name]
    except KeyError:
        raise ValueError(f"unknown size {name!r}; choose one of {', '.join(SIZES)}") from None


@struct.dataclass
class Params:
    """Traced physical constants. Defaults are the reference engine's, plus our speculative margin.

    Attributes:
        dt: time step [s].
        baumgarte: fraction of contact penetration (beyond `slop`) removed per step [1].
        slop: penetration left uncorrected, so resting contacts do not jitter [m].
        speculative_distance: contacts are created this far before touching, so fast bodies cannot
            tunnel and stacks settle without a cascade [m].
        touch_distance: a pair counts as touching (`StepInfo.touching`) at separation <= this [m].
        restitution_threshold: slower approaches than this do not bounce [m/s].
        friction_scale: contact friction coefficient = friction_scale * sqrt(f_a^2 + f_b^2) [1].
        joint_velocity_bias: velocity bias of the revolute point constraint per metre of drift [1/s].
        joint_position_correction: fraction of joint drift projected away after integration [1].
        fixed_joint_bias: velocity bias of the fixed-joint angle constraint per radian of drift [1/s].
        limit_bias: velocity bias of violated revolute limits per radian [1/s].
        base_motor_speed: motor target speed = motor_speed * action * base_motor_speed [rad/s].
        base_motor_power: motor strength; relative speed change per step is at most
            base_motor_power * power * dt * tanh(0.1 * |error|) [rad/s per (rad/s) of dt].
        motor_limit_fade: a motor fades to zero within this angle of a joint limit it pushes into [rad].
        base_thruster_power: thruster force = base_thruster_power * power * action [N].
        clip_position: |position| is clipped to this [m].
        clip_velocity: |velocity| components are clipped to this [m/s].
        clip_angular_velocity: |angular velocity| is clipped to this [rad/s].
    """

    dt: float = 1.0 / 60.0
    baumgarte: float = 0.2
    slop: float = 0.01
    speculative_distance: float = 0.04
    touch_distance: float = 0.005
    restitution_threshold: float = 1.0
    friction_scale: float = 0.4
    joint_velocity_bias: float = 2.0
    joint_position_correction: float = 0.7
    fixed_joint_bias: float = 2.0
    limit_bias: float = 5.0
    base_motor_speed: float = 6.0
    base_motor_power: float = 900.0
    motor_limit_fade: float = 0.1
    base_thruster_power: float = 10.0
    clip_position: float = 15.0
    clip_velocity: float = 100.0
    clip_angular_velocity: float = 50.0
