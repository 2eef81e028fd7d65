"""Run the `kinetix` command given as arguments; at exit print (stderr, lines starting PROBE) the time this
process spent reading programs from JAX's compile cache (each read, hit or miss), compiling, the reads' five
slowest, and the wall time from this script's start."""

import atexit
import sys
import time

START = time.monotonic()

from jax._src import compiler  # noqa: E402

reads: list[tuple[str, float, float, bool]] = []
"""(program, seconds, when it ended after START, hit) per cache read."""
compiles: list[float] = []
_read, _compile = compiler._cache_read, compiler.backend_compile_and_load


def timed_read(name, *args, **kwargs):
    start = time.monotonic()
    found = _read(name, *args, **kwargs)
    reads.append((name, time.monotonic() - start, time.monotonic() - START, found[0] is not None))
    return found


def timed_compile(*args, **kwargs):
    start = time.monotonic()
    compiled = _compile(*args, **kwargs)
    compiles.append(time.monotonic() - start)
    return compiled


compiler._cache_read, compiler.backend_compile_and_load = timed_read, timed_compile


@atexit.register
def report():
    hits = sum(hit for *_, hit in reads)
    print(
        f"PROBE reads {len(reads)} hits {hits} read_s {sum(r[1] for r in reads):.2f} compiles {len(compiles)} "
        f"compile_s {sum(compiles):.2f} wall {time.monotonic() - START:.2f}",
        file=sys.stderr,
    )
    for name, seconds, at, hit in sorted(reads, key=lambda r: -r[1])[:5]:
        print(f"PROBE   {name} {seconds:.2f} s, ended at {at:.1f} s, hit {hit}", file=sys.stderr)


from kinetix_cli.cli.app import main  # noqa: E402

sys.argv[0] = "kinetix"
main()
