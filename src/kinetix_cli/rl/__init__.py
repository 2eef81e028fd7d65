"""Reinforcement learning: networks, action distributions, PPO, training runs on disk, checkpoints and evaluation."""
