"""The shipped agents: installed with the package, verified on load, and carrying what made them and their scores."""

from __future__ import annotations

import json
import re

import pytest

from helpers.cli import kinetix
from helpers.paths import EXPERIMENTS, REPO
from kinetix_cli.config import CONFIG_FILENAME, load_config
from kinetix_cli.constants import SIZE_INDEPENDENT_OBSERVATIONS
from kinetix_cli.rl import agents


@pytest.mark.parametrize("size", ["s", "m", "l"])
def test_a_general_agent_per_size_is_shipped_with_its_commands_and_evaluation(size):
    name = f"general-{size}"
    assert name in agents.shipped_names()
    policy = agents.load_policy(name)  # checksums verified, parameters fit the model
    card = agents.read_card(agents.SHIPPED / name)
    trained_at = policy.config.env
    # one trained at another size reads a size-independent observation (general-m v2: trained at s, then at l)
    assert trained_at.size == size or trained_at.observation in SIZE_INDEPENDENT_OBSERVATIONS
    assert policy.update == card.trained["update"] > 0
    assert any(c.startswith("kinetix pretrain") for c in card.trained["commands"])
    assert card.evaluation["attempts"] >= 20
    assert {f"levels/{size}", f".cache/reference-levels/{size}"} <= set(card.evaluation["suites"])
    files = {p.name: p.stat().st_size for p in (agents.SHIPPED / name).iterdir()}
    assert set(files) == {"agent.json", CONFIG_FILENAME, "params.msgpack"} and sum(files.values()) < 5_000_000


def test_the_general_agent_is_shipped_with_its_score_over_the_74_paper_levels():
    """`general`: one agent for every size, scored as the paper scores its general agents (all 74 levels)."""
    policy = agents.load_policy("general")
    card = agents.read_card(agents.SHIPPED / "general")
    assert policy.config.env.observation in SIZE_INDEPENDENT_OBSERVATIONS
    assert policy.update == card.trained["update"] > 0 and policy.config.run.init_from
    assert any(c.startswith("kinetix pretrain") for c in card.trained["commands"])
    # v3: a blend of general-s v2, general v1 and four runs trained on from v1; v1 and v2 stay loadable by version
    assert card.version == 3 and {"general-s@2", "general@1"} <= {b["source"] for b in card.trained["blend"]}
    assert len(card.trained["blend"]) == 6
    assert any(c.startswith("kinetix agents blend") for c in card.trained["commands"])
    assert agents.load_policy("general@1").config.run.init_from == "general-s"
    assert agents.read_card(agents.shipped_agent("general@2")).version == 2
    suites = card.evaluation["suites"]
    assert card.evaluation["attempts"] == 50 and suites["all"]["levels"] == 74
    assert [suites[f".cache/reference-levels/{size}"]["levels"] for size in "sml"] == [10, 24, 40]


def test_shipped_versions_are_listed_newest_first():
    general = [card.version for card, _ in agents.shipped_agents() if card.name == "general"]
    assert general == sorted(general, reverse=True) and len(general) >= 3


def test_kinetix_agents_lists_the_shipped_agents_with_their_scores(capsys):
    result = kinetix(capsys, "agents")
    assert result.code == 0 and "levels/s" in result.out
    assert all(f"general-{size}" in result.out for size in "sml")
    # a run trained on from another agent names it beside its own steps; a blend's steps are its sources'
    assert "5,300,224 env steps after general@3" in result.out
    assert "35,659,776 env steps;" in result.out
    cards = {(c["name"], c["version"]): c for c in json.loads(kinetix(capsys, "agents", "--json").out)}
    assert cards["general-m", 3]["init_from"] == "general@3" and cards["general-l", 2]["init_from"] is None


def test_the_v2_recipe_file_is_the_config_general_s_v2_was_trained_with():
    config = agents.load_policy("general-s@2").config
    assert agents.read_card(agents.shipped_agent("general-s@2")).version == 2
    recipe = load_config(EXPERIMENTS / "general.yaml", ["run.eval_levels=[.cache/reference-levels/s]"])
    assert config == recipe


def test_general_s_v3_is_v2_blended_with_three_runs_of_the_recipe_trained_on_from_it():
    card = agents.read_card(agents.shipped_agent("general-s@3"))
    blend = card.trained["blend"]
    assert card.version == 3 and [b["source"] for b in blend][0] == "general-s@2" and len(blend) == 4
    assert [b["weight"] for b in blend] == pytest.approx([0.25] * 4, abs=1e-9)  # [share, 0-1]: float64 on the card
    continued = ["ppo.total_timesteps=3276800", "run.init_from=general-s@2", "run.eval_every=0", "run.seed=6"]
    assert agents.load_policy("general-s@3").config == load_config(EXPERIMENTS / "general.yaml", continued)


def test_a_name_is_its_version_chosen_on_validation_and_every_other_version_loads_by_number():
    """general-s v3 was shipped for its score on the paper's s levels; re-decided on the validation suite
    (docs/experiments/2026-11-28-protocol), `general-s` is v2 again, and v3 stays loadable."""
    assert agents.read_card(agents.shipped_agent("general-s")).version == 2
    assert [agents.read_card(agents.shipped_agent(f"general-s@{v}")).version for v in (1, 2, 3)] == [1, 2, 3]
    listed = [card.version for card, _ in agents.shipped_agents() if card.name == "general-s"]
    assert listed == [2, 3, 1]  # the chosen version first, then the others newest first


def test_general_m_v3_is_general_v3_trained_on_at_m_and_v2_loads_by_number():
    """The second v4 round (docs/experiments/2026-11-29-agents-v4-round2): `general` v3 trained on for 12 minutes at
    m beat general-m v2 on the validation suite's m levels, so `general-m` is v3 and v2 stays loadable."""
    card = agents.read_card(agents.shipped_agent("general-m"))
    continued = ["env.size=m", "run.init_from=general@3", "run.minutes=12", "ppo.total_timesteps=100_000_000"]
    continued += ["run.eval_every=0", "run.seed=2"]
    assert card.version == 3 and "2026-11-29-agents-v4-round2/PLAN.md" in card.rule
    assert agents.load_policy("general-m").config == load_config(EXPERIMENTS / "general.yaml", continued)
    assert agents.read_card(agents.shipped_agent("general-m@2")).version == 2
    assert [card.version for card, _ in agents.shipped_agents() if card.name == "general-m"] == [3, 2, 1]


def test_every_shipped_name_carries_its_validation_its_test_and_the_rule_that_chose_it():
    """The protocol: a name's version is chosen on the validation suite by a rule written before the runs, and its
    test scores (the paper's 74 levels, two evaluation seeds) are read once, after."""
    for name in agents.shipped_names():
        card = agents.read_card(agents.SHIPPED / name)
        assert card.validation["attempts"] == 50 and card.validation["suites"]["all"]["levels"] == 180, name
        assert set(card.validation["score"]) == {"heldout", "ours", "zero_shot", "finetune"}, name
        assert len(card.validation["finetune"]) == 2 and card.validation["update"] == card.trained["update"], name
        assert len(card.test["by_seed"]) == 2 and card.test["attempts"] == [50], name
        assert all(suites["all"]["levels"] == 74 for suites in card.test["by_seed"].values()), name
        assert "PLAN.md" in card.rule, name


def test_make_demo_fine_tunes_the_shipped_default():
    demo = re.search(r"^DEMO_AGENT := (\S+)", (REPO / "Makefile").read_text(encoding="utf-8"), re.M).group(1)
    assert demo == agents.default_agent() and demo in agents.shipped_names()
