"""On a CPU split into devices, no branch of a program that training runs holds a collective.

XLA's CPU runtime starts the collectives of a program in order, but a `lax.cond`'s collectives start only when
its branch reaches them, so two devices can wait at different collectives, and the run aborts after 40 s. The
general recipe's first update did so in 3 of 4 tries on 2 devices (2026-12-05): one device in the first reset's
gather (a branch), the other at a gather outside it. The first reset is now a select, `ppo.final_values` decides
per device (`parallel.per_device`), and PLR and ACCEL choose their round on the host (`plr.plr_round`).

Each case trains the tiny run on a fresh level source (so the first reset is compiled in; SFL scores its levels at
update 0) for 2 updates, PLR for 6 and ACCEL for 18 (until each of their rounds has come), on 2 forced host devices,
and reads every optimised program it ran from XLA's dump. The check itself is shown to find such a branch in a real
2-device program. `make test` checks SFL (the shipped recipe's curriculum: its update, scoring and the rollout's
truncated values); `make test-all` also DR, PLR and ACCEL."""

from __future__ import annotations

import re
import subprocess
import sys

import pytest

from helpers.processes import FORCE_2, process_env, run_ok, start
from helpers.runs import SFL, TINY, set_args

COLLECTIVE = re.compile(r"\b(all-gather|all-reduce|all-to-all|collective-permute|reduce-scatter)(-start)?\(")
CALLED = re.compile(r"\b(?:branch_computations|calls|body|condition|to_apply)=(?:\{([^}]*)\}|(%?[\w.\-]+))")
FRESH = ["levels.source=fresh", "levels.files=[]", "ppo.total_timesteps=128", "run.eval_every=0"]
"""2 updates of the tiny run (8 envs x 8 steps) on fresh levels, no evaluation."""
PLR = [
    "curriculum.name=plr",
    "curriculum.buffer_size=4",
    "curriculum.min_fill=0.5",
    "env.max_steps=8",
    "ppo.total_timesteps=384",  # 6 updates: PLR's both rounds come (`ROUNDS` below)
]
CURRICULA = {
    "sfl": [s for s in SFL if s.startswith("curriculum.")],
    "dr": [],
    "plr": PLR,
    "accel": [*PLR, "curriculum.name=accel", "curriculum.edits=2", "ppo.total_timesteps=1152"],  # its first replay: 18
}
UPDATES = {"sfl": "sfl_update", "dr": "ppo_update", "plr": "plr_update", "accel": "plr_update"}
"""The jitted update each curriculum's run must have compiled (so the check cannot pass on an empty dump)."""
ROUNDS = {"sfl": 1, "dr": 1, "plr": 2, "accel": 3}
"""Programs of that update: PLR and ACCEL compile one per round (`rl.curricula.plr.ROUNDS`), all of them played."""


def computations(hlo: str) -> dict[str, list[str]]:
    """The computations of an HLO module's text: name -> its instruction lines."""
    found, lines = {}, None
    for line in hlo.splitlines():
        header = re.match(r"(?:ENTRY )?%?([\w.\-]+) .*\{$", line)
        if header and not line.startswith(" "):
            lines = found[header.group(1)] = []
        elif lines is not None and line.startswith("  "):
            lines.append(line)
    return found


def branch_collectives(hlo: str) -> list[str]:
    """The conditionals of an optimised HLO module (`compiled.as_text()`, XLA's dumps) whose branches hold a
    collective, directly or in a computation they call: each one's `op_name`."""
    module = computations(hlo)

    def holds(name: str, seen: set) -> bool:
        if name in seen:
            return False
        seen.add(name)
        return any(COLLECTIVE.search(line) or any(holds(c, seen) for c in called(line)) for line in module[name])

    def called(line: str) -> list[str]:
        names = [match.group(1) or match.group(2) for match in CALLED.finditer(line)]
        return [name.strip().lstrip("%") for listed in names for name in listed.split(",")]

    return [
        (re.search(r'op_name="([^"]*)"', line) or re.search(r"%([\w.\-]+)", line)).group(1)
        for lines in module.values()
        for line in lines
        if " conditional(" in line and any(holds(branch, set()) for branch in called(line))
    ]


BAD_PROGRAM = """
import jax, jax.numpy as jnp
from jax.sharding import AxisType, NamedSharding, PartitionSpec
mesh = jax.make_mesh((2,), ("b",), (AxisType.Auto,))
x = jax.device_put(jnp.arange(8.0), NamedSharding(mesh, PartitionSpec("b")))
sort = lambda x: x[jnp.argsort(-x)]  # gathers rows of the other device
print(jax.jit(lambda x: jax.lax.cond(x.sum() > 0, sort, lambda x: x, x)).lower(x).compile().as_text())
"""


def test_the_check_finds_a_collective_in_a_branch():
    """A 2-device program whose branch gathers across devices is flagged; its other parts are not."""
    env = process_env() | {"XLA_FLAGS": FORCE_2}
    hlo = subprocess.run([sys.executable, "-c", BAD_PROGRAM], env=env, capture_output=True, text=True, check=True)
    assert len(branch_collectives(hlo.stdout)) == 1
    assert branch_collectives(hlo.stdout.replace(" conditional(", " call(")) == []


@pytest.mark.parametrize(
    "curriculum", [name if name == "sfl" else pytest.param(name, marks=pytest.mark.slow) for name in CURRICULA]
)
def test_training_holds_no_collective_in_a_branch(tmp_path, curriculum):
    dump = tmp_path / "hlo"
    args = ["pretrain", "--config", "experiments/cpu-small.yaml", *set_args([*TINY, *FRESH, *CURRICULA[curriculum]])]
    flags = f"{FORCE_2} --xla_dump_to={dump} --xla_dump_hlo_pass_re=NONE"
    run_ok([start([*args, "--run-dir", tmp_path / "run"], process_env(), XLA_FLAGS=flags)])
    programs = {path.name: path.read_text() for path in sorted(dump.glob("*after_optimizations.txt"))}
    updates = [name for name in programs if UPDATES[curriculum] in name]
    assert len(updates) == ROUNDS[curriculum], sorted(programs)
    found = {name: branch_collectives(text) for name, text in programs.items()}
    assert {name: ops for name, ops in found.items() if ops} == {}
