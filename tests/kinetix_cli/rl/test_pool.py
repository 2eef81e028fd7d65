"""The training pool: a generated pool refreshed every K updates (`levels.refresh_every`) is a filtered stream of
new levels, one pool per round, the same in a resumed run; a solved set's pool can leave its unsolved levels out."""

from __future__ import annotations

import json
import shutil

import jax
import numpy as np
import pytest

from engine import SIZES
from helpers.levelsets import small_levelset, solved_levelset
from helpers.paths import LEVELS
from helpers.runs import tiny_config
from kinetix_cli.config import ConfigError
from kinetix_cli.constants import VALIDATION_SEED
from kinetix_cli.env.level import level_count
from kinetix_cli.errors import UserError
from kinetix_cli.rl.pool import fresh_source, level_pool, pool_seed
from kinetix_cli.rl.train import train

REFRESHED = [
    "levels.source=generated",
    "levels.files=[]",
    "levels.pool_size=2",
    "levels.pool_chunk=32",
    "levels.refresh_every=2",
    "ppo.total_timesteps=256",  # 4 updates: rounds 0, 0, 1, 1
    "run.checkpoint_every=1",  # not refresh_every: the two are counted apart
    "run.eval_every=0",
]


@pytest.mark.slow  # ~75 s in make test's busiest worker: three pool generations and two runs
def test_a_refreshed_pool_trains_on_new_levels_each_round_and_resumes_bit_identically(tmp_path):
    config = tiny_config(*REFRESHED)
    assert pool_seed(config.run.seed, 0) == config.run.seed != pool_seed(config.run.seed, 1)
    first, second = level_pool(config), level_pool(config, round=1)
    assert jax.tree.structure(first) == jax.tree.structure(second)
    assert not np.array_equal(first.physics.bodies.position, second.physics.bodies.position)

    whole = train(config, tmp_path / "whole")
    records = [json.loads(line) for line in (tmp_path / "whole" / "metrics.jsonl").read_text().splitlines()]
    assert [r["pool_round"] for r in records] == [0, 0, 1, 1]

    cut = tmp_path / "cut"  # killed after checkpoint 2: the resumed run makes round 1's pool again
    shutil.copytree(tmp_path / "whole", cut)
    for update in ("3", "4"):
        shutil.rmtree(cut / "checkpoints" / update)
    resumed = train(config, cut, resume=True)
    jax.tree.map(np.testing.assert_array_equal, whole.params, resumed.params)


def test_refresh_needs_a_generated_pool():
    with pytest.raises(ConfigError, match="levels.refresh_every: is only used when levels.source is 'generated'"):
        tiny_config("levels.refresh_every=2")


def test_a_fresh_source_draws_the_configured_size_mix():
    config = tiny_config("levels.source=fresh", "levels.files=[]", "env.size=m", "levels.fresh_like=[s,m]")
    source = fresh_source(config)
    assert source.static == SIZES["m"] and source.sampler.like == ("s", "m")
    assert fresh_source(tiny_config("levels.source=fresh", "levels.files=[]")).sampler.like == ()


def test_no_generated_pool_draws_the_validation_suites_seeds():
    seeds = [pool_seed(run, r) for run in range(20) for r in range(1, 200)]
    assert max(seeds) < VALIDATION_SEED and len(set(seeds)) == len(seeds)


def test_a_solved_set_pool_can_leave_its_unsolved_levels_out(tmp_path):
    files = [
        LEVELS / "s" / "rocket-car-jump.json",
        LEVELS / "s" / "pad-to-pad.json",
        LEVELS / "s" / "jet-ball-hop.json",
    ]
    solved_levelset(tmp_path / "solved", files, unsolved=1)
    source = ["levels.source=levelset", "levels.files=[]", f"levels.levelset={tmp_path / 'solved'}"]
    every, solved = level_pool(tiny_config(*source)), level_pool(tiny_config(*source, "levels.solved_only=true"))
    assert level_count(every) == 3 and level_count(solved) == 2  # the last level is marked unsolved
    jax.tree.map(lambda a, b: np.testing.assert_array_equal(a[:2], b), every, solved)
    with pytest.raises(ConfigError, match="levels.solved_only: is only used when levels.source is 'levelset'"):
        tiny_config("levels.solved_only=true")
    small_levelset(tmp_path / "plain")
    plain = ["levels.source=levelset", "levels.files=[]", f"levels.levelset={tmp_path / 'plain'}"]
    with pytest.raises(UserError, match="holds no solutions; write a solved set with kinetix levels solve"):
        level_pool(tiny_config(*plain, "levels.solved_only=true"))
    solved_levelset(tmp_path / "none", files[:1], unsolved=1)
    nothing = ["levels.source=levelset", "levels.files=[]", f"levels.levelset={tmp_path / 'none'}"]
    with pytest.raises(UserError, match="levels.solved_only: .*: no level of the set is solved"):
        level_pool(tiny_config(*nothing, "levels.solved_only=true"))
