"""kinetix command-line toolkit: environment, generator, PPO and the `kinetix` CLI (work in progress)."""

__version__ = "0.3.0"
