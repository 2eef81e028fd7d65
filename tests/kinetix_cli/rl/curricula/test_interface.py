"""The one curriculum interface: every `curriculum.name` is a class of its own module implementing
`base.Curriculum`, and the training loop drives them without asking which one it has."""

from __future__ import annotations

import ast
import inspect
import typing

import pytest

from kinetix_cli.config import CurriculumName, CurriculumSettings
from kinetix_cli.rl import launch, record, train
from kinetix_cli.rl.curricula import CURRICULA, Curriculum, curriculum_class
from kinetix_cli.rl.curricula.base import Curriculum as Base


def test_every_configurable_name_has_a_curriculum_of_its_own_module():
    assert set(CURRICULA) == set(typing.get_args(CurriculumName))
    modules = {cls.__module__ for cls in CURRICULA.values()}
    assert len(modules) == len(CURRICULA)  # one file each
    for name, cls in CURRICULA.items():
        assert issubclass(cls, Curriculum) and cls is curriculum_class(CurriculumSettings(name=name))
        assert cls.update is not Base.update, name  # each says which levels its updates train on


@pytest.mark.parametrize("name", sorted(CURRICULA))
def test_a_curriculum_without_a_buffer_checkpoints_none(name):
    curriculum = CURRICULA[name](None, None, None, None, CurriculumSettings(name=name, buffer_size=8))
    assert curriculum.buffer_size == (0 if name == "dr" else 8)


@pytest.mark.parametrize("module", [launch, record, train], ids=lambda m: m.__name__)
def test_the_training_loop_never_asks_which_curriculum_it_has(module):
    tree = ast.parse(inspect.getsource(module))
    names = [node for node in ast.walk(tree) if isinstance(node, ast.Attribute) and node.attr == "name"]
    asked = [ast.unparse(node) for node in names if "curriculum" in ast.unparse(node.value)]
    assert asked == []
    strings = {node.value for node in ast.walk(tree) if isinstance(node, ast.Constant)}
    assert not strings & set(CURRICULA)
