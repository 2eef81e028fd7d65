"""Training commands: pretrain, finetune and eval."""

from __future__ import annotations

from pathlib import Path

import typer
from rich.table import Table
from rich.text import Text

from kinetix_cli.cli.console import console
from kinetix_cli.cli.processes import COORDINATOR, DEVICES, NUM_PROCESSES, PROCESS_ID, joined
from kinetix_cli.constants import INT32_MAX
from kinetix_cli.io import check_output_file

commands = typer.Typer()


@commands.command()
def pretrain(
    config: Path = typer.Option(..., "--config", help="Experiment config (YAML), e.g. experiments/cpu-small.yaml."),
    run_dir: Path = typer.Option(..., "--run-dir", help="Folder for config, metrics and checkpoints."),
    levels: Path = typer.Option(None, "--levels", help="Train on this level set instead of generated levels."),
    resume: bool = typer.Option(False, "--resume", help="Continue the run from its latest checkpoint."),
    overrides: list[str] = typer.Option([], "--set", help="Override a config value: --set ppo.lr=3e-4."),
    wandb: str = typer.Option(None, "--wandb", help="Also log to Weights & Biases: offline or online."),
    devices: int = DEVICES,
    coordinator: str = COORDINATOR,
    num_processes: int = NUM_PROCESSES,
    process_id: int = PROCESS_ID,
) -> None:
    """Train a PPO agent (PureJaxRL-style, jitted) on generated levels or a level set, on all local devices (or
    --devices N) of one process or of several (--coordinator, --num-processes, --process-id)."""
    from kinetix_cli.config import load_config

    extra = ["levels.source=levelset", f"levels.levelset={levels}"] if levels else []
    extra += [f"run.wandb={wandb}"] if wandb else []
    experiment = load_config(config, [*extra, *overrides])
    with joined(coordinator, num_processes, process_id):
        _train_with_progress(experiment, run_dir, resume, devices=devices)


@commands.command()
def finetune(
    levels: list[Path] = typer.Argument(..., help="Level files or folders to train on (one size)."),
    source: str = typer.Option(
        ...,
        "--from",
        help="Run directory, checkpoint, agent folder or shipped agent (kinetix agents) to start from, or 'none'.",
    ),
    run_dir: Path = typer.Option(..., "--run-dir", help="Folder for config, metrics and checkpoints."),
    config: Path = typer.Option(Path("experiments/finetune.yaml"), "--config", help="Experiment config (YAML)."),
    resume: bool = typer.Option(False, "--resume", help="Continue the run from its latest checkpoint."),
    overrides: list[str] = typer.Option([], "--set", help="Override a config value: --set ppo.lr=3e-4."),
    devices: int = DEVICES,
    coordinator: str = COORDINATOR,
    num_processes: int = NUM_PROCESSES,
    process_id: int = PROCESS_ID,
) -> None:
    """Train on hand-made levels, starting from a trained agent (--from RUN) or from scratch (--from none).

    With --from RUN the model and the agent's interface to the environment (observation, action type, frame
    skip) come from that run, so its parameters fit and it acts at the rate it learned; a --set of one of them
    still wins. --from none uses the config's, so pass the same --set values to compare the two at equal
    settings."""
    from kinetix_cli.levels.files import level_paths
    from kinetix_cli.rl.train import finetune_config

    with joined(coordinator, num_processes, process_id):
        pretrained, params = (None, None) if source == "none" else _load_from(source)
        origin = None if source == "none" else source
        experiment = finetune_config(config, level_paths(levels), pretrained, overrides, init_from=origin)
        _train_with_progress(experiment, run_dir, resume, params, devices)


def _load_from(source: str):
    """(config, params) of the agent `--from` names; an error names the flag and the source."""
    from kinetix_cli.errors import UserError
    from kinetix_cli.rl.agents import load_policy

    try:
        policy = load_policy(source)
        return policy.config, policy.params
    except UserError as exc:
        text = str(exc)
        raise UserError(f"--from {text}" if text.startswith(source) else f"--from {source}: {text}") from None


def _train_with_progress(experiment, run_dir: Path, resume: bool, init_params=None, devices=None) -> None:
    """Run `train` under a rich progress bar (steps, SPS, return, solve rate, ETA)."""
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

    from kinetix_cli.parallel import is_primary
    from kinetix_cli.rl.train import train

    if not is_primary():  # the primary process shows progress and writes the run; the others train quietly
        train(experiment, run_dir, resume=resume, init_params=init_params, devices=devices)
        return
    p = experiment.ppo
    columns = (TextColumn("training"), BarColumn(), TextColumn("{task.fields[info]}"), TimeElapsedColumn())
    with Progress(*columns, TextColumn("ETA"), TimeRemainingColumn(), console=console) as bar:
        task = bar.add_task("train", total=p.num_updates * p.batch_size, info="levels and compile...")
        last_eval, steps = "", 0

        def report(r: dict) -> None:
            nonlocal last_eval, steps
            if "clone_step" in r:  # behaviour cloning before PPO
                info = f"cloning {r['clone_step']:,}/{r['clone_steps']:,}, loss {r['clone_loss']:.3f}"
                bar.update(task, info=info + f", accuracy {r['clone_accuracy']:.0%}")
                return
            steps = r["steps"]
            if "eval_solve_rate" in r:
                last_eval = f", eval {r['eval_solve_rate']:.0%}"
            info = f"{r['steps']:,} steps, {r['sps']:,.0f} SPS, return {r['return']:+.2f}"
            info += f", solve rate {r['solve_rate']:.0%}{last_eval}"
            bar.update(task, completed=r["steps"], info=info)

        train(experiment, run_dir, resume=resume, progress=report, init_params=init_params, devices=devices)
    if experiment.run.minutes and 0 < steps < p.num_updates * p.batch_size:  # 0: resumed with the budget spent
        console.print(f"run.minutes: the {experiment.run.minutes:g}-minute budget ended the run at {steps:,} steps")
    console.print(f"wrote {run_dir}: config.yaml, metrics.jsonl, checkpoints/")


@commands.command("eval")
def eval_command(
    policy: str = typer.Argument(
        ..., help="Run directory (latest checkpoint), RUN/checkpoints/<update>, an agent folder or a shipped agent."
    ),
    levels: list[Path] = typer.Option(
        [Path("s")], "--levels", help="Level files or folders, or a shipped suite: s, m, l (repeatable)."
    ),
    attempts: int = typer.Option(50, min=1, max=10**5, help="Stochastic episodes per level."),
    seed: int = typer.Option(0, min=0, max=INT32_MAX, help="Seed of the sampled actions."),
    json_path: Path = typer.Option(None, "--json", help="Also write the results to this JSON file."),
    mirror: str = typer.Option(
        None,
        "--mirror",
        help="Act on the policy's view of each level joined with its view of the level's mirror image (left-right "
        "equivariant; two network calls a step): mean (of the action probabilities), geometric (their geometric "
        "mean) or value (the view the critic values higher).",
    ),
    devices: int = DEVICES,
) -> None:
    """Solve rate, return and episode length of a trained policy per level and per suite, in the run's own
    environment settings; the episodes are split over all local devices (or --devices N)."""
    if json_path is not None:
        check_output_file(json_path, "--json")
    from kinetix_cli.constants import EVAL_FORMAT
    from kinetix_cli.errors import WriteError
    from kinetix_cli.io import atomic_write_json
    from kinetix_cli.levels.files import level_paths
    from kinetix_cli.rl.agents import load_policy
    from kinetix_cli.rl.evaluate import evaluate, evaluation_record, suite_summary

    loaded = load_policy(policy)
    config, update = loaded.config, loaded.update
    results = evaluate(config, loaded.params, level_paths(levels), attempts, seed, devices, mirror)
    table = Table("level", "solve rate", "return", "length")
    for r in results:
        table.add_row(r.level, f"{r.solve_rate:.0%}", f"{r.mean_return:+.2f}", f"{r.mean_length:.0f}")
    summary = suite_summary(results)
    for name, row in summary.items():
        table.add_row(Text(f"{name} ({row['levels']} levels)", style="bold"), f"{row['solve_rate']:.0%}", "", "")
    console.print(table)
    if json_path is not None:
        existed = json_path.exists()
        try:
            atomic_write_json(
                json_path, evaluation_record(str(policy), update, attempts, seed, results, mirror), EVAL_FORMAT
            )
        except WriteError as exc:
            kept = f"; {json_path} is unchanged" if existed else ""
            raise WriteError(f"--json {exc}; the results are in the table above{kept}") from None
        console.print(f"wrote {json_path}")
