"""On a CPU split into devices, no branch of a program that training runs holds a collective, and no collective
that could start while a device is inside a loop's collectives waits outside it.

XLA's CPU runtime starts the collectives of a program in order, but a `lax.cond`'s collectives start only when
its branch reaches them, so two devices can wait at different collectives, and the run aborts after 40 s. The
general recipe's first update did so in 3 of 4 tries on 2 devices (2026-12-05): one device in the first reset's
gather (a branch), the other at a gather outside it. The first reset is now a select, `ppo.final_values` decides
per device (`parallel.per_device`), and PLR and ACCEL choose their round on the host (`plr.plr_round`).

Each case trains the tiny run on a fresh level source (so the first reset is compiled in; SFL scores its levels at
update 0) for 2 updates, PLR for 6 and ACCEL for 18 (until each of their rounds has come), on 2 forced host devices,
and reads every optimised program it ran from XLA's dump.

Loops may hold collectives (the update's minibatch loop holds the gradient all-reduce), and each runs on every
device for the same trip count. But a loop is, like a branch, one thunk whose collectives start as its iterations
reach them, and XLA's CPU runtime orders collectives only by when they start (a scheduling edge: a later one may
start once the earlier has started). So a collective scheduled after a loop that holds collectives, and not
computed from the loop's results, can start on one device before the loop's first collective and on the other
after it: the same wait as the branch's. The check: in every computation, each collective (or instruction holding
one) scheduled after such a loop depends on the loop; an independent one must be scheduled before it (it then
starts on every device before the loop does). Both checks are shown to find their case in a real 2-device
program. `make test` checks SFL (the shipped recipe's curriculum: its update, scoring and the rollout's
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
    return [
        (re.search(r'op_name="([^"]*)"', line) or re.search(r"%([\w.\-]+)", line)).group(1)
        for lines in module.values()
        for line in lines
        if " conditional(" in line and holds(module, line)
    ]


def loose_collectives(hlo: str) -> list[tuple[str, str]]:
    """The pairs (loop, collective) of an optimised HLO module (scheduled: its instructions in the order they start)
    where an instruction holding a collective is scheduled after a loop that holds one and does not depend on the
    loop's results, each by its name."""
    module = computations(hlo)
    found = []
    for lines in module.values():
        names = [re.match(r"\s+(?:ROOT )?%?([\w.\-]+) = ", line).group(1) for line in lines]
        operands = [set(re.findall(r"%([\w.\-]+)", line.split(" = ", 1)[1])) for line in lines]
        holding = [holds(module, line) for line in lines]
        for i, line in enumerate(lines):
            if not (holding[i] and " while(" in line):
                continue
            after = {names[i]}  # the loop and what is computed from it
            for j in range(i + 1, len(lines)):
                if operands[j] & after:
                    after.add(names[j])
                elif holding[j]:
                    found.append((names[i], names[j]))
    return found


def holds(module: dict[str, list[str]], line: str, seen: set | None = None) -> bool:
    """Whether an instruction is a collective or calls a computation that holds one."""
    seen = set() if seen is None else seen
    if COLLECTIVE.search(line):
        return True
    fresh = [name for name in called(line) if name in module and name not in seen]
    seen.update(fresh)
    return any(holds(module, inner, seen) for name in fresh for inner in module[name])


def called(line: str) -> list[str]:
    """The computations an instruction calls (branches, loop bodies and conditions, reductions, calls)."""
    names = [match.group(1) or match.group(2) for match in CALLED.finditer(line)]
    return [name.strip().lstrip("%") for listed in names for name in listed.split(",")]


BAD_PROGRAM = """
import jax, jax.numpy as jnp
from jax.sharding import AxisType, NamedSharding, PartitionSpec
mesh = jax.make_mesh((2,), ("b",), (AxisType.Auto,))
x = jax.device_put(jnp.arange(8.0), NamedSharding(mesh, PartitionSpec("b")))
sort = lambda x: x[jnp.argsort(-x)]  # gathers rows of the other device
print(jax.jit(lambda x: jax.lax.cond(x.sum() > 0, sort, lambda x: x, x)).lower(x).compile().as_text())
"""
LOOSE_PROGRAM = """
import jax, jax.numpy as jnp
from jax.sharding import AxisType, NamedSharding, PartitionSpec
mesh = jax.make_mesh((2,), ("b",), (AxisType.Auto,))
x = jax.device_put(jnp.arange(8.0), NamedSharding(mesh, PartitionSpec("b")))
sort = lambda x: x[jnp.argsort(-x)]  # gathers rows of the other device
looped = lambda x: (jax.lax.fori_loop(0, 3, lambda i, v: sort(v) + 1.0, x), sort(2.0 * x))  # the second: beside it
print(jax.jit(looped).lower(x).compile().as_text())
"""


def compiled_on_2_devices(program: str) -> str:
    env = process_env() | {"XLA_FLAGS": FORCE_2}
    return subprocess.run([sys.executable, "-c", program], env=env, capture_output=True, text=True, check=True).stdout


def test_the_check_finds_a_collective_in_a_branch():
    """A 2-device program whose branch gathers across devices is flagged; its other parts are not."""
    hlo = compiled_on_2_devices(BAD_PROGRAM)
    assert len(branch_collectives(hlo)) == 1
    assert branch_collectives(hlo.replace(" conditional(", " call(")) == []


def test_the_check_finds_a_collective_scheduled_after_a_loop_it_does_not_depend_on():
    """XLA schedules the gathers of a sort beside a loop of sorts one before the loop and one after it; the one
    after is flagged. Scheduled after both (the loop's line moved down), the loop leaves none."""
    hlo = compiled_on_2_devices(LOOSE_PROGRAM)
    (pair,) = loose_collectives(hlo)
    entry = hlo[hlo.index("\nENTRY") :].splitlines()
    loop = next(line for line in entry if " while(" in line)
    root = next(i for i, line in enumerate(entry) if line.startswith("  ROOT "))
    moved = [line for line in entry[:root] if line != loop] + [loop] + entry[root:]
    assert loose_collectives(hlo.replace("\n".join(entry), "\n".join(moved))) == []
    assert pair[0] == loop.split(" = ")[0].strip().lstrip("%")


@pytest.mark.parametrize(
    "curriculum", [name if name == "sfl" else pytest.param(name, marks=pytest.mark.slow) for name in CURRICULA]
)
def test_training_holds_no_collective_in_a_branch_and_none_loose_beside_a_loop(tmp_path, curriculum):
    dump = tmp_path / "hlo"
    args = ["pretrain", "--config", "experiments/cpu-small.yaml", *set_args([*TINY, *FRESH, *CURRICULA[curriculum]])]
    flags = f"{FORCE_2} --xla_dump_to={dump} --xla_dump_hlo_pass_re=NONE"
    run_ok([start([*args, "--run-dir", tmp_path / "run"], process_env(), XLA_FLAGS=flags)])
    programs = {path.name: path.read_text() for path in sorted(dump.glob("*after_optimizations.txt"))}
    updates = [name for name in programs if UPDATES[curriculum] in name]
    assert len(updates) == ROUNDS[curriculum], sorted(programs)
    found = {name: branch_collectives(text) for name, text in programs.items()}
    assert {name: ops for name, ops in found.items() if ops} == {}
    loose = {name: loose_collectives(text) for name, text in programs.items()}
    assert {name: pairs for name, pairs in loose.items() if pairs} == {}
