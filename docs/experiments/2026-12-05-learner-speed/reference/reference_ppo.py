"""Time one PPO update of the reference Kinetix (the `kinetix-env` wheel) the way `kinetix bench train` times ours.

Run it with the reference venv's python (.cache/reference-venv/bin/python); see README.md next to this file.
The update is the wheel's own `kinetix.util.learning.sample_trajectories_and_learn` with one outer step:
a rollout of --steps x --envs, the wheel's GAE, then --epochs x --minibatches PPO minibatch steps.
We only build its inputs (env, network, optimiser, config dict) and time it.
"""

from __future__ import annotations

import argparse
import importlib.metadata
import json
import os
import platform
import statistics
import sys
import time

import jax
import jax.numpy as jnp
import optax
from flax.training.train_state import TrainState
from kinetix.environment.env import make_kinetix_env
from kinetix.environment.env_state import EnvParams
from kinetix.environment.spaces import ActionType, ObservationType
from kinetix.environment.ued.ued import make_reset_fn_from_config
from kinetix.environment.utils import static_env_params_from_size
from kinetix.environment.wrappers import GymnaxWrapper, LogWrapper
from kinetix.models import ScannedRNN, make_network_from_config
from kinetix.util.learning import sample_trajectories_and_learn

# Compatibility shim, not a change to the reference's maths: kinetix-env 3.0.2's `update_actor_critic_rnn` and
# `sample_trajectories_and_learn` call `jax.tree.tree_map`, a name no jax release has (the function is
# `jax.tree.map`), so they fail while tracing. Give the name to the module for this process only.
if not hasattr(jax.tree, "tree_map"):
    jax.tree.tree_map = jax.tree.map

# Hyperparameters of the reference's PPO config (configs/learning/ppo-base.yaml); they do not change the speed.
PPO_SETTINGS = dict(gamma=0.995, gae_lambda=0.9, clip_eps=0.2, ent_coef=0.01, vf_coef=0.5, lr=5e-5, max_grad_norm=0.5)
# The reference's transformer settings (configs/model/model-transformer.yaml); used with --model transformer only.
TRANSFORMER_SETTINGS = dict(
    transformer_depth=2,
    transformer_size=16,
    transformer_encoder_size=128,
    num_heads=8,
    full_attention_mask=False,
    aggregate_mode="dummy_and_mean",
    transformer_ffn=False,
    multilayer_joint_thruster_mixing=False,
    joint_thruster_block_num_layers=2,
    joint_thruster_block_hidden_dim_multiplication=4,
    dropout_prob=0.0,
    legacy_entity_id=False,
    permutation_invariant_mlp=False,
)


class FreshLevelOnReset(GymnaxWrapper):
    """Drops the `override_reset_state` that `sample_trajectories_and_learn` hands to every step.

    That helper resets a finished episode to the state its rollout started from (the wheel's PLR/SFL replay use).
    The reference's PPO script resets to a newly sampled random level instead; without an override the wheel's env
    does exactly that (its reset function samples a level, computed every step, kept where an episode ended).
    """

    def step(self, key, state, action, env_params=None, override_reset_state=None):
        return self._env.step(key, state, action, env_params)

    def __hash__(self):
        return hash(("fresh-level-on-reset", hash(self._env)))

    def __eq__(self, other):
        return hash(self) == hash(other)


def version(name: str) -> str | None:
    try:
        return importlib.metadata.version(name)
    except importlib.metadata.PackageNotFoundError:
        return None


def build(args):
    """(update function, its first arguments, facts for the record)."""
    static_env_params = static_env_params_from_size(args.size)
    env_params = EnvParams()  # dense_reward_scale 0.1, max_timesteps 256: the reference's defaults
    observation = ObservationType.SYMBOLIC_FLAT if args.model == "mlp" else ObservationType.SYMBOLIC_ENTITY
    config = {
        "action_type": ActionType.MULTI_DISCRETE,
        "observation_type": observation,
        "train_level_mode": "random",
        "static_env_params": {
            "num_motor_bindings": static_env_params.num_motor_bindings,
            "num_thruster_bindings": static_env_params.num_thruster_bindings,
        },
        "recurrent_model": args.recurrent,
        "actor_width": args.width,
        "critic_width": args.width,
        "actor_depth": args.layers,
        "critic_depth": args.layers,
        "activation": "tanh",
        "num_train_envs": args.envs,
        "num_steps": args.steps,
        "outer_rollout_steps": 1,
        "update_epochs": args.epochs,
        "num_minibatches": args.minibatches,
        **PPO_SETTINGS,
        **(TRANSFORMER_SETTINGS if args.model == "transformer" else {}),
    }
    reset_fn = make_reset_fn_from_config(config, env_params, static_env_params)
    base = make_kinetix_env(
        config["action_type"], observation, reset_fn, env_params, static_env_params, auto_reset=True
    )
    env = LogWrapper(FreshLevelOnReset(base))
    network = make_network_from_config(env, env_params, config)

    key = jax.random.PRNGKey(args.seed)
    key, key_reset, key_init = jax.random.split(key, 3)
    obs, env_state = jax.vmap(env.reset, (0, None))(jax.random.split(key_reset, args.envs), env_params)
    # The hidden state is carried and shuffled by the wheel even when the model is not recurrent.
    hstate = ScannedRNN.initialize_carry(args.envs)
    dones = jnp.zeros((args.envs,), dtype=bool)
    params = network.init(key_init, hstate, jax.tree.map(lambda x: x[None], (obs, dones)))
    tx = optax.chain(optax.clip_by_global_norm(config["max_grad_norm"]), optax.adam(config["lr"], eps=1e-5))
    train_state = TrainState.create(apply_fn=network.apply, params=params, tx=tx)

    def update(rng, train_state, hstate, obs, env_state):
        new_carry, _rollout = sample_trajectories_and_learn(
            env, env_params, config, rng, train_state, hstate, obs, env_state
        )
        return new_carry  # (rng, train_state, hstate, last obs, last env state)

    facts = {
        # Trainable weights only. `network.init` also returns the model's sown 'custom_intermediates' (dormancy
        # statistics and the (1, envs, width) actor and critic features); the reference's PPO keeps them inside
        # its train state too, so we do the same, and report their size apart.
        "parameters": int(sum(x.size for x in jax.tree_util.tree_leaves(params["params"]))),
        "train_state_leaves_size": int(sum(x.size for x in jax.tree_util.tree_leaves(params))),
        "obs_size": int(sum(x.size for x in jax.tree_util.tree_leaves(obs)) // args.envs),
        "action_dims": [int(n) for n in env.action_space(env_params).number_of_dims_per_distribution]
        if hasattr(env.action_space(env_params), "number_of_dims_per_distribution")
        else None,
        "frame_skip": int(static_env_params.frame_skip),
    }
    return update, (key, train_state, hstate, obs, env_state), facts


def flops(compiled) -> float | None:
    """XLA's count of the compiled update's floating-point operations (as `kinetix bench train` reads it)."""
    cost = compiled.cost_analysis()
    cost = cost[0] if isinstance(cost, (list, tuple)) else cost
    return float(cost["flops"]) if cost and "flops" in cost else None


def time_update(update, carry, steps_per_call: int, min_time: float):
    """Compile time, median env steps/s over the timed calls, number of timed calls (as our `time_calls`), and
    the update's FLOPs."""
    start = time.perf_counter()
    compiled = jax.jit(update).lower(*carry).compile()
    compile_s = time.perf_counter() - start
    carry = jax.block_until_ready(compiled(*carry))  # warm-up
    rates, spent = [], 0.0
    while len(rates) < 2 or spent < min_time:
        start = time.perf_counter()
        carry = jax.block_until_ready(compiled(*carry))
        elapsed = time.perf_counter() - start
        spent += elapsed
        rates.append(steps_per_call / elapsed)
    return compile_s, statistics.median(rates), len(rates), flops(compiled)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--envs", type=int, default=256)
    parser.add_argument("--steps", type=int, default=32)
    parser.add_argument("--epochs", type=int, default=4)
    parser.add_argument("--minibatches", type=int, default=4)
    parser.add_argument("--width", type=int, default=64)
    parser.add_argument("--layers", type=int, default=3)
    parser.add_argument("--min-time", type=float, default=10.0)
    parser.add_argument("--model", choices=["mlp", "transformer"], default="mlp")
    parser.add_argument("--size", choices=["s", "m", "l"], default="s")
    parser.add_argument("--recurrent", action="store_true", help="use the reference's GRU (256 units); off by default")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", type=str, default=None)
    args = parser.parse_args()
    if args.envs % args.minibatches:
        parser.error(f"--minibatches {args.minibatches} must divide --envs {args.envs} (the reference splits by env)")

    started = time.perf_counter()
    update, carry, facts = build(args)
    build_s = time.perf_counter() - started  # env reset + network init, eager (compiled apart from the update)
    print(f"built env and network in {build_s:.1f} s; compiling the update", file=sys.stderr, flush=True)
    compile_s, steps_per_s, calls, update_flops = time_update(update, carry, args.envs * args.steps, args.min_time)
    record = {
        "side": "reference",
        "model": args.model,
        "observation": "symbolic_flat" if args.model == "mlp" else "symbolic_entity",
        "size": args.size,
        "envs": args.envs,
        "steps": args.steps,
        "epochs": args.epochs,
        "minibatches": args.minibatches,
        "width": args.width,
        "layers": args.layers,
        "recurrent": args.recurrent,
        **facts,
        "build_s": round(build_s, 3),
        "compile_s": round(compile_s, 3),
        "steps_per_s": round(steps_per_s, 1),
        "calls": calls,
        "update_gflop": None if update_flops is None else round(update_flops / 1e9, 3),
        "min_time": args.min_time,
        "versions": {n: version(n) for n in ("jax", "jaxlib", "kinetix-env", "jax2d", "flax", "optax", "distrax")},
        "machine": {
            "processor": platform.processor(),
            "cpu_count": os.cpu_count(),
            "platform": platform.platform(),
            "python": platform.python_version(),
            "devices": [str(d) for d in jax.devices()],
        },
    }
    line = json.dumps(record)
    print(line, flush=True)
    if args.json:
        with open(args.json, "w") as f:
            f.write(line + "\n")
    # The process can hang for a while at interpreter exit (seen in the smoke test); the record is written.
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)


if __name__ == "__main__":
    main()
