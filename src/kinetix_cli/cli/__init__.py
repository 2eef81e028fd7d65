"""The `kinetix` command line: thin typer commands, one module per group (`levels`, `generate`, `train`, `bench`),
registered on one app in `app`. Each command builds a config and calls one library function.

Commands import the library inside the function that runs them, so `kinetix --help` and a mistyped flag answer
without loading JAX (about 3 s on a laptop CPU); the import contract (`make lint`) still sees those imports.
"""
