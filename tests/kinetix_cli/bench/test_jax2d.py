"""The Jax2D adapter used by `kinetix bench engine --against jax2d` (needs the `compare` extra; `make test-all`)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("jax2d")

import jax  # noqa: E402
import jax.numpy as jnp  # noqa: E402

from engine import SIZES  # noqa: E402
from engine.random_scenes import random_scene  # noqa: E402
from kinetix_cli.bench.jax2d import build_jax2d_state, jax2d_engine  # noqa: E402


@pytest.mark.slow
def test_same_scene_in_both_engines():
    """Bodies land in the same slots at the same centres of mass (1e-5 m); joints and thrusters point at the
    same bodies; Jax2D steps the scene without NaN."""
    static = SIZES["m"]
    scene = random_scene(static, 3)
    ours = scene.build_numpy(static)
    theirs = build_jax2d_state(scene, static)
    p = static.num_polygons
    np.testing.assert_allclose(np.asarray(theirs.polygon.position[4:]), ours.bodies.position[4:p], atol=1e-5)
    np.testing.assert_allclose(np.asarray(theirs.circle.position), ours.bodies.position[p:], atol=1e-5)
    np.testing.assert_allclose(np.asarray(theirs.circle.radius), ours.bodies.radius[p:], atol=1e-6)
    assert np.asarray(theirs.joint.a_index).tolist() == ours.joints.body_a.tolist()
    assert np.asarray(theirs.joint.b_index).tolist() == ours.joints.body_b.tolist()
    assert np.asarray(theirs.thruster.object_index).tolist() == ours.thrusters.body.tolist()

    engine_step, params = jax2d_engine(static)
    advance = jax.jit(
        lambda s: jax.lax.scan(lambda c, _: (engine_step(c, params, jnp.zeros(4))[0], None), s, None, 30)[0]
    )
    state = advance(theirs)
    assert bool(jnp.isfinite(state.polygon.position).all()) and bool(jnp.isfinite(state.circle.position).all())
