"""Benchmarks: compile time apart from steady-state throughput of the engine, the environment, the generator and PPO."""
