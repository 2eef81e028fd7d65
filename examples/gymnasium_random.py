"""Random play on Kinetix through Gymnasium's vector API: what a PyTorch training loop (CleanRL, SB3, PufferLib)
sees of the environment.

    python examples/gymnasium_random.py --levels s --num-envs 64 --steps 512

Everything crossing the interface is numpy: observations, actions, rewards, terminated and truncated flags, and
`infos["final_obs"]` (the observation an episode ended on; the returned observation is already the next
episode's). Prints episodes ended, solved and failed, and the steps per second of the loop.
"""

from __future__ import annotations

import argparse
import time

import gymnasium
import numpy as np

import kinetix_cli.gym  # noqa: F401  registers kinetix/Kinetix-v0


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", default="s", help="'fresh', a suite (s, m, l), level files or a folder")
    parser.add_argument("--size", default=None, help="s, m or l (default: what the levels need; m for fresh)")
    parser.add_argument("--observation", default="symbolic-flat")
    parser.add_argument("--max-steps", type=int, default=256, help="episode cap [environment steps]")
    parser.add_argument("--num-envs", type=int, default=64)
    parser.add_argument("--steps", type=int, default=512)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)

    envs = gymnasium.make_vec(
        "kinetix/Kinetix-v0",
        num_envs=args.num_envs,
        levels=args.levels,
        size=args.size,
        observation=args.observation,
        max_steps=args.max_steps,
    )
    envs.action_space.seed(args.seed)
    obs, _ = envs.reset(seed=args.seed)
    episodes = solved = failed = 0
    returns = np.zeros(args.num_envs)
    finished = []
    start = None
    for step in range(args.steps):
        if step == 1:
            start = time.perf_counter()  # after the first step, which compiles
        obs, reward, terminated, truncated, infos = envs.step(envs.action_space.sample())
        returns += reward
        done = terminated | truncated
        episodes += int(done.sum())
        solved += int(infos["solved"][done].sum())
        failed += int(infos["failed"][done].sum())
        finished += returns[done].tolist()
        returns[done] = 0.0
        assert envs.observation_space.contains(obs)
    seconds = time.perf_counter() - start if start else float("nan")
    rate = (args.steps - 1) * args.num_envs / seconds
    print(
        f"{episodes} episodes: {solved} solved, {failed} failed, mean return {np.mean(finished or [0.0]):+.3f}; "
        f"{rate:,.0f} env steps/s"
    )
    envs.close()
    return {"episodes": episodes, "solved": solved, "failed": failed, "steps_per_second": rate}


if __name__ == "__main__":
    main()
