"""The shipped agents: installed with the package, verified on load, and carrying what made them and their scores."""

from __future__ import annotations

from helpers.cli import kinetix
from kinetix_cli.config import CONFIG_FILENAME
from kinetix_cli.rl import agents


def test_general_s_is_shipped_with_its_commands_and_evaluation():
    assert "general-s" in agents.shipped_names()
    config, params, update = agents.load_policy("general-s")  # checksums verified, parameters fit the model
    card = agents.read_card(agents.SHIPPED / "general-s")
    assert config.env.size == "s" and update == card.trained["update"] > 0
    assert any(c.startswith("kinetix pretrain") for c in card.trained["commands"])
    assert card.evaluation["attempts"] >= 20
    assert {"levels/s", ".cache/reference-levels/s"} <= set(card.evaluation["suites"])
    files = {p.name: p.stat().st_size for p in (agents.SHIPPED / "general-s").iterdir()}
    assert set(files) == {"agent.json", CONFIG_FILENAME, "params.msgpack"} and sum(files.values()) < 5_000_000


def test_kinetix_agents_lists_general_s_with_its_scores(capsys):
    result = kinetix(capsys, "agents")
    assert result.code == 0 and "general-s" in result.out and "levels/s" in result.out
