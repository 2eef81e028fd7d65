"""Curricula: which levels training episodes start from (`curriculum.name` in the experiment config).

- `dr` (domain randomisation, the baseline): uniformly from the level source (`levels.source`: fresh levels
  sampled every update, or a fixed pool). It needs no module: it is `rl.ppo.ppo_update`.
- `sfl` (`sfl.py`, sampling for learnability): a buffer of the levels the current policy solves about half of
  the time, refreshed every `curriculum.refresh_every` updates; a share of the episodes start from it.
- `plr` and `accel` (`plr.py`, robust prioritised level replay and its mutating variant): every update either
  replays buffer levels and trains on them, or scores new (or mutated) levels without training.

Curricula keep their levels in a `rl.buffer.LevelBuffer` (levels, scores, solve rates), carried in the PPO `Runner`
and so saved in every checkpoint: a resumed run ends bit-identical to an uninterrupted one.
"""
