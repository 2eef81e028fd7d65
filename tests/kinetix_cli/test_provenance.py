"""What a written file records about the toolkit that made it."""

from __future__ import annotations

import tomllib
from importlib import metadata

import kinetix_cli
from helpers.paths import REPO
from kinetix_cli import provenance


def test_the_version_is_the_installed_one_else_the_checkouts_marked_source(monkeypatch):
    assert provenance.tool_version() == metadata.version("kinetix")

    def not_installed(name):
        raise metadata.PackageNotFoundError(name)

    monkeypatch.setattr(provenance.metadata, "version", not_installed)  # kinetix run from src/, as on a lent GPU
    declared = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]["version"]
    assert kinetix_cli.__version__ == declared  # the package's version is the one it is installed as
    assert provenance.tool_version() == f"{declared} (source)"
    assert provenance.environment_info()["versions"]["kinetix"] == f"{declared} (source)"
