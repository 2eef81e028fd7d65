"""The package stands on its own: the wheel built from the repository, installed in a fresh virtual environment
outside the checkout, carries the shipped agents and the hand-made suites, and `kinetix agents`, `kinetix eval
general-s --levels s`, `kinetix generate` and the gymnax `make` work from another folder. wandb is an extra.

The fresh environment gets the wheel alone and finds the wheel's dependencies in the suite's own environment (a
path entry, not an install: the checkout's editable install stays invisible to it); `make test` runs what needs no
compile there, the slow tests the rest, and once more with the wheel's dependencies installed from the package
index, as a user would.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import sysconfig
import venv
import zipfile
from pathlib import Path

import pytest

from helpers.paths import REPO
from helpers.processes import TIMEOUT, process_env

pytestmark = pytest.mark.xdist_group("wheel")  # one worker builds the wheel once for all of them


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """The wheel, built from a copy of what it is made of (pip builds in the source tree; the checkout stays as
    it is, and nothing else in the suite writes there meanwhile)."""
    source, out = tmp_path_factory.mktemp("source"), tmp_path_factory.mktemp("wheel")
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(REPO / name, source / name)
    for name in ("src", "levels"):
        shutil.copytree(REPO / name, source / name, symlinks=True, ignore=shutil.ignore_patterns("__pycache__"))
    pip = [sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", str(source), "-w", str(out)]
    subprocess.run(pip, check=True, timeout=TIMEOUT, capture_output=True)
    (built,) = out.glob("kinetix-*.whl")
    return built


def _fresh_venv(root: Path, *, with_pip: bool) -> Path:
    venv.EnvBuilder(with_pip=with_pip).create(root)
    return root / "bin" / "python"


def _install(python: Path, wheel: Path, *, deps: bool) -> None:
    command = [sys.executable, "-m", "pip", "--python", str(python), "install", "-q", str(wheel)]
    command += [] if deps else ["--no-deps"]
    subprocess.run(command, check=True, timeout=TIMEOUT, capture_output=True)


def _run(python: Path, args: list[str], cwd: Path) -> str:
    kinetix = python.parent / "kinetix"
    done = subprocess.run(
        [str(kinetix), *args] if args[0] != "-c" else [str(python), *args],
        cwd=cwd,
        env=process_env() | {"PYTHONPATH": ""},
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )
    assert done.returncode == 0, f"{args}: exit {done.returncode}\n{done.stdout}\n{done.stderr}"
    return done.stdout


def test_the_wheel_carries_agents_suites_and_the_studio_and_wandb_is_an_extra(wheel):
    names = zipfile.ZipFile(wheel).namelist()
    for size in ("s", "m", "l"):
        assert sum(n.startswith(f"kinetix_levels/{size}/") and n.endswith(".json") for n in names) >= 10
    assert any(n.startswith("kinetix_cli/rl/shipped/general-s/") for n in names)
    assert "kinetix_cli/studio/static/studio.js" in names
    metadata = zipfile.ZipFile(wheel).read(next(n for n in names if n.endswith("METADATA"))).decode()
    wandb = [line for line in metadata.splitlines() if line.startswith("Requires-Dist: wandb")]
    assert wandb and all("; extra == " in line for line in wandb)  # only with an extra (wandb, or dev)


def _check_installed(python: Path, work: Path, *, compiles: bool) -> None:
    """The commands a new user runs, from a folder that is not the checkout; with `compiles`, also those that
    compile a program (evaluation, generation), which take minutes on the CI's 2 cores."""
    probe = (
        "import kinetix_cli, kinetix_levels\n"
        "from kinetix_cli.levels.files import level_paths\n"
        "from kinetix_cli.gym import make\n"
        "env, params = make('m')\n"
        "print(kinetix_cli.__file__, len(level_paths(['s'])), env.name, int(params.pool_count),"
        " len(level_paths(['validation'])))\n"
    )
    where, suite_s, name, count, validation = _run(python, ["-c", probe], work).split()
    assert str(python.parent.parent) in where and str(REPO) not in where
    assert (int(suite_s), name, int(count), int(validation)) == (10, "Kinetix-m", 20, 180)
    assert "general-s" in _run(python, ["agents"], work)
    if not compiles:
        return
    listed = _run(python, ["levels", "list", "s", "--markdown"], work)
    assert "rocket-car-jump" in listed and str(REPO) not in listed
    evaluated = _run(python, ["eval", "general-s", "--levels", "s", "--attempts", "2", "--json", "eval.json"], work)
    record = json.loads((work / "eval.json").read_text())
    assert "levels/s/rocket-car-jump.json" in [entry["level"] for entry in record["levels"]]
    assert list(record["suites"]) == ["levels/s", "all"] and "levels/s" in evaluated
    _run(python, ["generate", "--size", "s", "--count", "4", "--seed", "0", "--out", "made"], work)
    assert (work / "made" / "manifest.json").is_file()


def _wheel_only_venv(wheel: Path, root: Path) -> Path:
    """A fresh environment with the wheel alone, finding its dependencies in this suite's environment."""
    python = _fresh_venv(root / "venv", with_pip=False)
    _install(python, wheel, deps=False)
    purelib = Path(sysconfig.get_paths()["purelib"])
    fresh_purelib = next((root / "venv" / "lib").glob("python3*/site-packages"))
    (fresh_purelib / "suite_dependencies.pth").write_text(f"{purelib}\n")
    (root / "elsewhere").mkdir()
    return python


@pytest.mark.slow  # ~40 s: a fresh environment and three processes; make test keeps the wheel's contents (above)
def test_installed_outside_the_checkout_it_finds_its_agents_suites_and_gym_from_any_folder(wheel, tmp_path):
    _check_installed(_wheel_only_venv(wheel, tmp_path), tmp_path / "elsewhere", compiles=False)


@pytest.mark.slow
def test_installed_outside_the_checkout_eval_and_generate_work(wheel, tmp_path):
    _check_installed(_wheel_only_venv(wheel, tmp_path), tmp_path / "elsewhere", compiles=True)


@pytest.mark.slow
def test_installed_with_its_dependencies_from_the_index(wheel, tmp_path):
    python = _fresh_venv(tmp_path / "venv", with_pip=True)
    _install(python, wheel, deps=True)
    work = tmp_path / "elsewhere"
    work.mkdir()
    _check_installed(python, work, compiles=True)
    missing = subprocess.run([str(python), "-c", "import wandb"], capture_output=True, timeout=TIMEOUT)
    assert missing.returncode != 0  # not installed without the extra
