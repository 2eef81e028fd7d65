"""Probe: `general` v3's six sources played as an ensemble instead of one averaged network. At every step each
source's action distribution is computed and they are combined with v3's blend weights, either as a mixture
(`mix`: the weighted mean of each action entry's probabilities) or as a product of experts (`poe`: the weighted
mean of the log-probabilities, renormalised); `soup` is v3 itself (the averaged parameters) as the control.
Run: `python ensemble.py heldout 20 2000 soup,mix,poe > ensemble-heldout-2000.jsonl` (levels, attempts,
evaluation seed, modes); reads runs/heldout/ (benchmarks/general-v3-cpu-2026-11-27/heldout.sh) or the paper
levels (`paper`)."""

import json
import sys
from pathlib import Path

import jax
import jax.numpy as jnp

import kinetix_cli.rl.evaluate as evaluate
from kinetix_cli.rl.agents import load_policy, read_card, resolve
from kinetix_cli.rl.distributions import MultiCategorical

which, attempts, seed = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
modes = sys.argv[4].split(",")
root = "runs/heldout" if which == "heldout" else ".cache/reference-levels"
files = sorted(p for size in "sml" for p in Path(root, size).glob("*.json"))

soup = load_policy("general@3")
blend = read_card(resolve("general@3")).trained["blend"]
sources = [load_policy(b["source"]) for b in blend]
weights = [float(b["weight"]) for b in blend]


def ensemble_policy(mode):
    def make(network, params):
        def policy(key, obs, t):
            logits = [network.apply(p, obs)[0].logits for p in params]
            log_p = [jax.nn.log_softmax(x, axis=-1) for x in logits]
            if mode == "mix":
                p = sum(w * jnp.exp(lp) for w, lp in zip(weights, log_p, strict=True))
                combined = jnp.where(p > 0, jnp.log(p), -jnp.inf)
            else:
                finite = [jnp.where(jnp.isneginf(lp), 0.0, lp) for lp in log_p]
                combined = jnp.where(
                    jnp.isneginf(logits[0]), -jnp.inf, sum(w * x for w, x in zip(weights, finite, strict=True))
                )
            return MultiCategorical(combined).sample(key)

        return policy

    return make


standard = evaluate.sampling_policy
for mode in modes:
    evaluate.sampling_policy = standard if mode == "soup" else ensemble_policy(mode)
    evaluate.play_policy.clear_cache()
    evaluator = evaluate.Evaluator(soup.config, files, attempts)
    params = soup.params if mode == "soup" else [s.params for s in sources]
    results = evaluator(params, seed)
    by_size = {}
    for r in results:
        by_size.setdefault(r.size, []).append(r.solve_rate)
    rates = [r.solve_rate for r in results]
    row = {"which": which, "seed": seed, "attempts": attempts, "mode": mode, "mean": sum(rates) / len(rates)}
    levels = {r.level: r.solve_rate for r in results}
    print(
        json.dumps({**row, **{k: sum(v) / len(v) for k, v in by_size.items()}, "n": len(rates), "levels": levels}),
        flush=True,
    )
