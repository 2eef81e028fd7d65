"""The level generator: the reference distribution as a jitted sampler, and the filters that drop trivial levels."""
