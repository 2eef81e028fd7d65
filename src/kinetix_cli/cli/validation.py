"""`kinetix validation`: the suite every choice is made on. `build` rebuilds its held-out generated levels (or checks
the shipped ones against a rebuild); `run` plays an agent on it, zero-shot and fine-tuned, into a record that
`kinetix agents record` puts on the agent's card."""

from __future__ import annotations

from pathlib import Path

import typer
from rich.table import Table

from kinetix_cli.cli.console import console, int_list
from kinetix_cli.constants import INT32_MAX, VALIDATION_SEED
from kinetix_cli.io import check_output_file

validation_app = typer.Typer(
    help="The validation suite: held-out generated levels, our levels/s, m, l, and fine-tuning on two of ours."
)


@validation_app.command("build")
def build(
    out: Path = typer.Option(
        None, "-o", "--out", help="Folder to write <size>/*.json into (default: the shipped one)."
    ),
    check: bool = typer.Option(False, "--check", help="Rebuild into a scratch folder and compare with the shipped."),
    sizes: str = typer.Option("s,m,l", help="Sizes to build, comma-separated."),
) -> None:
    """Generate the held-out levels of the validation suite from its reserved seeds (the same files every time)."""
    import tempfile

    from kinetix_cli.errors import UserError
    from kinetix_cli.levels.suites import HELDOUT, suites_root
    from kinetix_cli.tools.validation import build_heldout, shipped_heldout_matches

    chosen = tuple(s for s in sizes.split(",") if s)
    if not chosen or not set(chosen) <= {"s", "m", "l"}:
        raise UserError(f"--sizes: expected sizes among s, m, l separated by commas, got {sizes!r}")
    if check:
        with tempfile.TemporaryDirectory() as scratch:
            build_heldout(scratch, chosen, progress=console.print)
            differ = [name for name in shipped_heldout_matches(scratch) if name.split("/")[-2] in chosen]
        if differ:
            raise UserError(f"--check: {len(differ)} held-out levels differ from a rebuild: {', '.join(differ[:5])}")
        console.print(f"--check: the shipped held-out levels ({', '.join(chosen)}) are what a rebuild writes")
        return
    root = out if out is not None else suites_root() / HELDOUT
    files = build_heldout(root, chosen, progress=console.print)
    console.print(f"wrote {len(files)} held-out levels under {root}")


@validation_app.command("run")
def run(
    agent: str = typer.Argument(..., help="Run directory, checkpoint, agent folder or shipped agent."),
    json_path: Path = typer.Option(..., "--json", help="The validation record to write (kinetix-validation/1)."),
    attempts: int = typer.Option(50, min=1, max=10**5, help="Episodes per level, zero-shot and after fine-tuning."),
    seed: int = typer.Option(1000, min=0, max=INT32_MAX, help="Seed of the sampled actions."),
    finetune_seeds: str = typer.Option("0,1,2", help="Training seeds of the fine-tuning part ('' for none)."),
    config: Path = typer.Option(Path("experiments/cpu-small.yaml"), "--config", help="The fine-tuning runs' config."),
    overrides: list[str] = typer.Option([], "--set", help="A fine-tuning setting over the protocol's (a quick look)."),
) -> None:
    """The agent on the validation suite: zero-shot on the held-out levels and our levels/s, m, l, and its solve
    rate after fine-tuning on two of our levels (make demo's settings), each seed apart."""
    check_output_file(json_path, "--json")
    from kinetix_cli.tools.validation import ValidationSettings, validate_agent, write_validation

    seeds = int_list("--finetune-seeds", finetune_seeds, low=0, high=VALIDATION_SEED - 1) if finetune_seeds else ()
    settings = ValidationSettings(attempts, seed, seeds, str(config), tuple(overrides))
    record = validate_agent(agent, settings, progress=console.print)
    table = Table("part", "levels", "solve rate")
    for suite, row in record["suites"].items():
        table.add_row(suite, str(row["levels"]), f"{row['solve_rate']:.1%}")
    for level, row in record["finetune"]["levels"].items():
        rates = " / ".join(f"{r:.0%}" for r in row["solve_rate"])
        table.add_row(f"fine-tuned on {level} (seeds {row['seeds']})", "1", rates)
    console.print(table)
    score = record["score"]
    tuned = "" if score["finetune"] is None else f", fine-tuned {score['finetune']:.1%}"
    parts = f"held out {score['heldout']:.1%}, our levels {score['ours']:.1%}, zero-shot {score['zero_shot']:.1%}"
    console.print(f"validation: {parts}{tuned}")
    write_validation(json_path, record)
    console.print(f"wrote {json_path}")
