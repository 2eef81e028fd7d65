"""`kinetix agents`: the shipped agents with their scores; `kinetix agents export`, which makes an agent folder
(a policy with its config, checksums, training commands and evaluation) from a run or another agent folder; and
`kinetix agents blend`, which averages the parameters of several policies of one network into an agent folder."""

from __future__ import annotations

import json
from pathlib import Path

import typer
from rich.table import Table

from kinetix_cli.cli.console import console, say

agents_app = typer.Typer(help="Shipped agents (usable by name: kinetix eval general-s) and agent folders.")


@agents_app.callback(invoke_without_command=True)
def agents(
    ctx: typer.Context,
    as_json: bool = typer.Option(False, "--json", help="Print the agents' cards as JSON instead of a table."),
) -> None:
    """List the shipped agents (NAME is the version chosen on validation; `NAME@VERSION` loads any other): name and
    version, model, training steps, zero-shot solve rate per suite, and what chose it (validation, test, rule)."""
    if ctx.invoked_subcommand is not None:
        return
    from kinetix_cli.rl.agents import default_agent, shipped_agents

    agents = shipped_agents()
    if as_json:
        cards = [
            card.as_dict() | {"model": _model(config), "init_from": config.run.init_from} for card, config in agents
        ]
        console.print(json.dumps(cards, indent=2))
        return
    if not agents:
        console.print("no shipped agents are installed")
        return
    default = default_agent()
    for card, config in agents:
        evaluation = card.evaluation
        attempts = f", {evaluation['attempts']} attempts per level" if "attempts" in evaluation else ""
        mark = " (the default: make demo fine-tunes it)" if card.folder.name == default else ""
        say(
            (f"{card.name} v{card.version}", "bold"),
            f"{mark}: {_model(config)}, {_steps(card, config)}; zero-shot{attempts}",
        )
        table = Table("suite", "levels", "solve rate")
        for suite, row in evaluation.get("suites", {}).items():
            table.add_row(suite, str(row["levels"]), f"{row['solve_rate']:.1%}")
        console.print(table if table.rows else "  not evaluated")
        console.print(f"  {_chosen(card)}", soft_wrap=True)


def _steps(card, config) -> str:
    """The card's env steps; a run started from another policy counts only its own (a blend's are its sources'
    summed), so name where it started: "5,300,224 env steps after general@3"."""
    steps = f"{card.trained.get('steps', 0):,} env steps"
    start = config.run.init_from
    return steps if start is None or "blend" in card.trained else f"{steps} after {start}"


def _chosen(card) -> str:
    """One line on what chose the agent: its validation scores, its test scores per seed, and the rule."""
    if not card.validation:
        return "validation: none recorded (chosen before the protocol, or not a shipped choice)"
    score = card.validation["score"]
    tuned = "" if score.get("finetune") is None else f", fine-tuned {score['finetune']:.1%}"
    line = f"validation: held out {score['heldout']:.1%}, our levels {score['ours']:.1%}{tuned}"
    tests = [
        f"{suites['all']['solve_rate']:.1%} (seed {seed})" for seed, suites in card.test.get("by_seed", {}).items()
    ]
    return f"{line}; test (the paper's 74): {', '.join(tests) or 'none'}; rule: {card.rule}"


def _model(config) -> str:
    """One line on an agent's model and what it sees."""
    model, env = config.model, config.env
    return f"{model.name} width {model.width}, {env.observation}, size {env.size}"


@agents_app.command("export")
def export(
    run: str = typer.Argument(
        ..., help="Run directory (latest checkpoint), RUN/checkpoints/<update>, an agent folder or a shipped agent."
    ),
    out: Path = typer.Option(..., "-o", "--out", help="Agent folder to write (new, or an agent folder to replace)."),
    name: str = typer.Option(..., "--name", help="The agent's name, e.g. general-s."),
    version: int = typer.Option(1, "--version", min=1, max=10**6, help="The agent's version."),
    evaluation: Path = typer.Option(None, "--eval", help="A kinetix eval --json file of this run, put on the card."),
    commands: list[str] = typer.Option([], "--command", help="A command that made the run (repeatable, in order)."),
    temperature: float = typer.Option(1.0, "--temperature", help="Divide the policy's action logits by this."),
) -> None:
    """Write a run's policy (or an agent folder's, e.g. a blend's, or a shipped agent's) as an agent folder:
    config.yaml, params.msgpack and agent.json (kinetix-agent/1)."""
    from kinetix_cli.rl.agents import export_agent

    card = export_agent(
        run, out, name=name, version=version, commands=commands, evaluation=evaluation, temperature=temperature
    )
    size = sum((card.folder / f).stat().st_size for f in card.files)
    console.print(f"wrote {out}: agent {card.name} version {card.version} ({size / 1024:,.0f} KiB)")


@agents_app.command("blend")
def blend(
    sources: list[str] = typer.Argument(
        ..., help="Policies of one network: runs, RUN/checkpoints/<update>, agent folders or shipped agents."
    ),
    out: Path = typer.Option(..., "-o", "--out", help="Agent folder to write (new, or an agent folder to replace)."),
    name: str = typer.Option(..., "--name", help="The agent's name, e.g. general."),
    version: int = typer.Option(1, "--version", min=1, max=10**6, help="The agent's version."),
    weights: list[float] = typer.Option([], "--weight", help="Each policy's weight, in order (default: equal)."),
    commands: list[str] = typer.Option([], "--command", help="A command that made the sources (repeatable)."),
) -> None:
    """Average the parameters of policies fine-tuned from one agent (a model soup) into an agent folder; its card
    lists them. Evaluate it with kinetix eval, then ship it with kinetix agents export --eval."""
    from kinetix_cli.rl.agents import blend_agents

    card = blend_agents(sources, out, name=name, version=version, commands=commands, weights=weights)
    parts = ", ".join(f"{b['source']} x{b['weight']:.3g}" for b in card.trained["blend"])
    console.print(f"wrote {out}: agent {card.name} version {card.version}, the average of {parts}")


@agents_app.command("record")
def record(
    folder: Path = typer.Argument(..., help="The agent folder whose card gets the record."),
    validation: Path = typer.Option(..., "--validation", help="Its kinetix validation run --json record."),
    test: list[Path] = typer.Option(..., "--test", help="A kinetix eval --json file on --levels test (per seed)."),
    rule: str = typer.Option(..., "--rule", help="The rule, written before the runs, that chose this agent."),
) -> None:
    """Record on an agent's card what chose it (its validation scores and the rule) and its test scores, read after
    the choice; the agent's files are untouched."""
    from kinetix_cli.rl.agents import record_choice
    from kinetix_cli.rl.evaluate import read_evaluation
    from kinetix_cli.tools.validation import read_validation

    card = record_choice(
        folder, validation=read_validation(validation), test=[read_evaluation(t) for t in test], rule=rule
    )
    console.print(f"{card.folder}: {_chosen(card)}", soft_wrap=True)
