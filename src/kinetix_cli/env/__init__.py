"""The environment: levels on the device, actions, observations, the step, and the episode runner.

`make_env(settings)` builds a `KinetixEnv` and its `EnvParams` from an experiment's `env` section;
`run_episode` plays one episode under any policy.
"""
