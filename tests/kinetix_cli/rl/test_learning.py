"""The learning smoke test: the tiny SFL run (tests/helpers/runs.py: 300 updates of 8 envs x 8 steps from scratch on
a hand-made level that PPO learns within 20K steps) must raise the policy's solve rate well above where it started.
It fails if learning breaks anywhere on the way (environment, rewards, GAE, losses, optimiser, curriculum mixing); it
asserts outcomes only, never a time."""

from __future__ import annotations

import jax

from helpers.runs import LEARN_LEVEL, SFL_RUN_GROUP, sfl_config
from kinetix_cli.env.factory import make_env
from kinetix_cli.rl.evaluate import Evaluator
from kinetix_cli.rl.networks import make_network
from kinetix_cli.rl.pool import level_pool
from kinetix_cli.rl.ppo import init_runner

pytestmark = SFL_RUN_GROUP


def test_a_small_sfl_run_learns_a_level_from_scratch(sfl_run):
    trained, _ = sfl_run
    config = sfl_config()
    env, _ = make_env(config.env)
    network = make_network(config.model, config.env)
    start = init_runner(env, network, config.ppo, level_pool(config), jax.random.key(config.run.seed))
    evaluator = Evaluator(config, [LEARN_LEVEL], attempts=64)
    before = evaluator(start.params, seed=1)[0].solve_rate
    after = evaluator(trained.params, seed=1)[0].solve_rate
    # measured here (64 attempts each): 39% -> 97%; with run.seed 1 and 2: 38% -> 78%, 66% at the end; lr 1e-9: +0
    assert after >= before + 0.2, (before, after)
