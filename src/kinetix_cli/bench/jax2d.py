"""Build our scenes in the reference engine (Jax2D 1.0.2, extra `compare`) for side-by-side benchmarks.

Imports jax2d lazily: the rest of the toolkit never needs it.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from engine import Scene, Static


class Jax2DMissing(RuntimeError):
    """Jax2D is not installed."""


def _import():
    try:
        from jax2d.engine import PhysicsEngine, create_empty_sim
        from jax2d.scene import (
            add_circle_to_scene,
            add_fixed_joint_to_scene,
            add_polygon_to_scene,
            add_revolute_joint_to_scene,
            add_thruster_to_scene,
        )
        from jax2d.sim_state import SimParams, StaticSimParams
    except ImportError as exc:
        raise Jax2DMissing("jax2d is not installed; install the extra: pip install -e '.[compare]'") from exc
    return {
        "PhysicsEngine": PhysicsEngine,
        "create_empty_sim": create_empty_sim,
        "SimParams": SimParams,
        "StaticSimParams": StaticSimParams,
        "circle": add_circle_to_scene,
        "fixed": add_fixed_joint_to_scene,
        "polygon": add_polygon_to_scene,
        "revolute": add_revolute_joint_to_scene,
        "thruster": add_thruster_to_scene,
    }


def jax2d_static(static: Static):
    """Jax2D's StaticSimParams with our capacities and solver iterations."""
    j2d = _import()
    return j2d["StaticSimParams"](
        num_polygons=static.num_polygons,
        num_circles=static.num_circles,
        num_joints=static.num_joints,
        num_thrusters=static.num_thrusters,
        num_solver_iterations=static.solver_iterations,
    )


def jax2d_engine(static: Static):
    """(step function (state, params, actions) -> (state, manifolds), SimParams) of the reference engine."""
    j2d = _import()
    engine = j2d["PhysicsEngine"](jax2d_static(static))
    return engine.step, j2d["SimParams"]()


def build_jax2d_state(scene: Scene, static: Static):
    """The same scene as a Jax2D SimState: same slots, centres of mass, anchors, materials and actuators.

    Polygons are passed clockwise about our area centroid (Jax2D's convention). Jax2D's own defects apply
    (vertex-average centroid for triangles, half circle inertia, fixed joints without a reference angle).
    """
    j2d = _import()
    ssp = jax2d_static(static)
    state = j2d["create_empty_sim"](ssp)
    built = scene.build_numpy(static)
    b = built.bodies

    def material(slot):
        return {
            "rotation": float(b.angle[slot]),
            "velocity": np.asarray(b.velocity[slot]),
            "angular_velocity": float(b.angular_velocity[slot]),
            "density": float(b.density[slot]),
            "friction": float(b.friction[slot]),
            "restitution": float(b.restitution[slot]),
            "fixated": bool(b.fixed[slot]),
        }

    for i in range(len(scene.polygons)):
        slot = static.slot("polygon", i)
        n = int(b.num_vertices[slot])
        clockwise = np.asarray(b.vertices[slot, :n][::-1])
        state, _ = j2d["polygon"](state, ssp, np.asarray(b.position[slot]), clockwise, n, **material(slot))
    for i in range(len(scene.circles)):
        slot = static.slot("circle", i)
        state, _ = j2d["circle"](state, ssp, np.asarray(b.position[slot]), float(b.radius[slot]), **material(slot))
    jt = built.joints
    for j in range(len(scene.joints)):
        args = (
            state,
            ssp,
            int(jt.body_a[j]),
            int(jt.body_b[j]),
            np.asarray(jt.anchor_a[j]),
            np.asarray(jt.anchor_b[j]),
        )
        if jt.fixed[j]:
            state, _ = j2d["fixed"](*args)
        else:
            state, _ = j2d["revolute"](
                *args,
                motor_on=bool(jt.motor_on[j]),
                motor_speed=float(jt.motor_speed[j]),
                motor_power=float(jt.motor_power[j]),
                has_joint_limits=bool(jt.has_limits[j]),
                min_rotation=float(jt.min_angle[j]),
                max_rotation=float(jt.max_angle[j]),
            )
    th = built.thrusters
    for t in range(len(scene.thrusters)):
        state, _ = j2d["thruster"](
            state, int(th.body[t]), np.asarray(th.anchor[t]), float(th.angle[t]), float(th.power[t])
        )
    return state


# --- reference-format level files <-> Jax2D states (the reference's own reading of a level, for comparisons) ---


def _plain(value):
    """A reference JSON value with its vectors (`{"0": x, "1": y}`) turned into lists, recursively."""
    if isinstance(value, dict) and value and all(k.isdigit() for k in value):
        return [_plain(value[str(i)]) for i in range(len(value))]
    if isinstance(value, list):
        return [_plain(v) for v in value]
    return value


def _json(value):
    """The inverse of `_plain` for one array: vectors as `{"0": x, ...}` dicts, scalars as Python numbers."""
    value = np.asarray(value)
    if value.ndim == 0:
        return value.item()
    return {str(i): _json(v) for i, v in enumerate(value)}


def jax2d_from_reference(data: dict):
    """(SimState, SimParams, StaticSimParams) of a reference-format level (`{"env_state", "env_params",
    "static_env_params"}`): Jax2D's own reading of the file, slot for slot. Warm-start caches start empty."""
    j2d = _import()
    counts = data["static_env_params"]
    ssp = j2d["StaticSimParams"](
        **{k: counts[k] for k in ("num_polygons", "num_circles", "num_joints", "num_thrusters")},
        num_solver_iterations=counts.get("num_solver_iterations", 10),
    )
    state = j2d["create_empty_sim"](ssp)
    env = data["env_state"]

    def entities(template, entries):
        fields = {}
        for name in template.__dataclass_fields__:
            like = np.asarray(getattr(template, name))
            fields[name] = np.asarray([_plain(e[name]) for e in entries], like.dtype).reshape(like.shape)
        return template.replace(**fields)

    state = state.replace(
        polygon=entities(state.polygon, env["polygon"]),
        circle=entities(state.circle, env["circle"]),
        joint=entities(state.joint, env["joint"]),
        thruster=entities(state.thruster, env["thruster"]),
        collision_matrix=np.asarray(_plain(env["collision_matrix"]), bool),
        gravity=np.asarray(_plain(env["gravity"]), np.float32),
    )
    known = j2d["SimParams"].__dataclass_fields__
    params = j2d["SimParams"](**{k: v for k, v in data["env_params"].items() if k in known})
    return jax.tree.map(jnp.asarray, state), params, ssp


def reference_from_jax2d(state, template: dict, roles=(), densities=()) -> dict:
    """A reference-format level holding a Jax2D `state` (how the reference saves its levels): `template` gives
    `env_params` and `static_env_params`; `roles` and `densities` are per body slot (polygons then circles,
    default role 0 and density 1); every motor and thruster gets binding 0."""
    num_polygons = int(np.asarray(state.polygon.active).shape[0])

    def entities(batch, extra):
        rows = []
        for i in range(np.asarray(batch.active).shape[0]):
            row = {name: _json(np.asarray(getattr(batch, name))[i]) for name in batch.__dataclass_fields__}
            rows.append(row | extra(i))
        return rows

    def body(offset):
        def extra(i):
            slot = offset + i
            role = roles[slot] if slot < len(roles) else 0
            return {"role": role, "density": densities[slot] if slot < len(densities) else 1.0, "highlighted": False}

        return extra

    env_state = {
        "polygon": entities(state.polygon, body(0)),
        "circle": entities(state.circle, body(num_polygons)),
        "joint": entities(state.joint, lambda i: {"motor_binding": 0}),
        "thruster": entities(state.thruster, lambda i: {"thruster_binding": 0}),
        "collision_matrix": _json(state.collision_matrix),
        "gravity": _json(state.gravity),
    }
    return {"env_state": env_state, **{k: template[k] for k in ("env_params", "static_env_params")}}
