"""rel-mlp's actor and critic first layers at the general recipe's shapes (a minibatch of 2,048 rows of the 772
pooled features, width 64): two dense layers with tanh against one layer of width 128 split in two, forward and
backward, jitted; the median of 40 rounds of 20 calls each, the two alternating, in one process.
Run: KINETIX_CPU_DEVICES=1 .venv/bin/python bench.py"""

import statistics
import time

import jax
import jax.numpy as jnp

ROWS, FEATURES, WIDTH = 2048, 772, 64
keys = jax.random.split(jax.random.key(0), 5)
x = jax.random.normal(keys[0], (ROWS, FEATURES))
params = (
    jax.random.normal(keys[1], (FEATURES, WIDTH)) * 0.03,
    jnp.zeros(WIDTH),
    jax.random.normal(keys[2], (FEATURES, WIDTH)) * 0.03,
    jnp.zeros(WIDTH),
)
cotangents = (jax.random.normal(keys[3], (ROWS, WIDTH)), jax.random.normal(keys[4], (ROWS, WIDTH)))


def two(p, x):
    actor_kernel, actor_bias, critic_kernel, critic_bias = p
    return jnp.tanh(x @ actor_kernel + actor_bias), jnp.tanh(x @ critic_kernel + critic_bias)


def one(p, x):
    actor_kernel, actor_bias, critic_kernel, critic_bias = p
    kernel, bias = jnp.concatenate([actor_kernel, critic_kernel], 1), jnp.concatenate([actor_bias, critic_bias])
    y = jnp.tanh(x @ kernel + bias)
    return y[:, :WIDTH], y[:, WIDTH:]


def gradient(layers):
    loss = lambda p, x: sum(jnp.vdot(out, g) for out, g in zip(layers(p, x), cotangents, strict=True))  # noqa: E731
    return jax.jit(jax.grad(loss, argnums=(0, 1)))


programs = {"two layers": gradient(two), "one layer": gradient(one)}
for program in programs.values():
    jax.block_until_ready(program(params, x))
times = {name: [] for name in programs}
for _ in range(40):
    for name, program in programs.items():
        start = time.perf_counter()
        for _ in range(20):
            out = program(params, x)
        jax.block_until_ready(out)
        times[name].append((time.perf_counter() - start) / 20)
for name in programs:
    print(f"{name}: {statistics.median(times[name]) * 1e3:.3f} ms")
print(f"two / one: {statistics.median(times['two layers']) / statistics.median(times['one layer']):.3f}")
