"""The type stub (softbond/_core.pyi) and the docstrings cover the extension's public names."""

import ast
import pathlib

import softbond
from softbond import _core

STUB = pathlib.Path(__file__).resolve().parents[1] / "softbond" / "_core.pyi"


def stub_names():
    tree = ast.parse(STUB.read_text())
    names = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            members = set()
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    members.add(item.name)
                elif isinstance(item, ast.AnnAssign):
                    members.add(item.target.id)
            names[node.name] = members
        elif isinstance(node, ast.AnnAssign):
            names[node.target.id] = set()
        elif isinstance(node, ast.FunctionDef):
            names[node.name] = set()
    return names


def test_every_public_name_is_in_the_stub_with_a_docstring():
    stub = stub_names()
    for name in dir(_core):
        if name.startswith("_"):
            continue
        assert name in stub, f"{name} missing from _core.pyi"
        value = getattr(_core, name)
        if callable(value):
            assert value.__doc__, f"{name} has no docstring"
        if isinstance(value, type) and not issubclass(value, BaseException):
            assert value.__doc__, f"{name} has no docstring"
            for member, attribute in vars(value).items():
                if member.startswith("_"):
                    continue
                assert member in stub[name], f"{name}.{member} missing from _core.pyi"
                assert attribute.__doc__, f"{name}.{member} has no docstring"
    assert "advance" in softbond.Solver.advance.__doc__
