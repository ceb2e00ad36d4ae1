"""_core.pyi against the compiled module: the same names (functions, submodules, classes, their
methods and properties) and, for every function, the same parameters in the same order, with a
default where the binding has one. The stubs are written by hand; this catches them going stale."""

import ast
import pathlib
import re
import types

import pytest

import conecull
from conecull import _core

STUB = pathlib.Path(conecull.__file__).with_name("_core.pyi")
SUBMODULES = sorted(n for n in dir(_core) if isinstance(getattr(_core, n), types.ModuleType))
CLASSES = sorted(n for n in dir(_core) if not n.startswith("_") and isinstance(getattr(_core, n), type))


def _stub_tree():
    tree = ast.parse(STUB.read_text())
    functions = {n.name: n for n in tree.body if isinstance(n, ast.FunctionDef)}
    classes = {n.name: n for n in tree.body if isinstance(n, ast.ClassDef)}
    return functions, classes


def _stub_params(fn: ast.FunctionDef):
    """[(name, has_default)] of a stub function, without self."""
    args = fn.args.args
    defaults = [False] * (len(args) - len(fn.args.defaults)) + [True] * len(fn.args.defaults)
    return [(a.arg, d) for a, d in zip(args, defaults) if a.arg != "self"]


def _split_top_level(text: str):
    parts, depth, cur = [], 0, ""
    for ch in text:
        depth += ch in "[("
        depth -= ch in "])"
        if ch == "," and depth == 0:
            parts.append(cur)
            cur = ""
        else:
            cur += ch
    return [p.strip() for p in parts + [cur] if p.strip()]


def _binding_params(obj):
    """[(name, has_default)] from pybind11's signature line, without self."""
    first = (obj.__doc__ or "").splitlines()[0]
    m = re.match(r"\w+\((.*)\) ->", first)
    assert m, f"no signature in {first!r}"
    params = []
    for p in _split_top_level(m.group(1)):
        name = p.split(":")[0].strip()
        if name != "self":
            params.append((name, "=" in p))
    return params


def _methods(cls_node: ast.ClassDef):
    return {n.name: n for n in cls_node.body if isinstance(n, ast.FunctionDef)}


def _attributes(cls_node: ast.ClassDef):
    return {n.target.id for n in cls_node.body if isinstance(n, ast.AnnAssign)}


def test_top_level_names_match():
    functions, classes = _stub_tree()
    runtime_functions = {n for n in dir(_core) if not n.startswith("_") and callable(getattr(_core, n))
                         and not isinstance(getattr(_core, n), type)}
    assert set(functions) == runtime_functions
    assert set(classes) == set(SUBMODULES) | set(CLASSES)


@pytest.mark.parametrize("name", SUBMODULES)
def test_submodule_functions_match(name):
    _, classes = _stub_tree()
    stub = _methods(classes[name])
    mod = getattr(_core, name)
    runtime = {n for n in dir(mod) if not n.startswith("_")}
    assert set(stub) == runtime
    for fn_name, node in stub.items():
        assert _stub_params(node) == _binding_params(getattr(mod, fn_name)), f"{name}.{fn_name}"


@pytest.mark.parametrize("name", CLASSES)
def test_class_members_match(name):
    _, classes = _stub_tree()
    cls = getattr(_core, name)
    stub_methods, stub_attrs = _methods(classes[name]), _attributes(classes[name])
    props = {n for n, v in vars(cls).items() if isinstance(v, property)}
    methods = {n for n, v in vars(cls).items() if not n.startswith("_") and not isinstance(v, property)}
    assert stub_attrs == props
    assert set(stub_methods) - {"__init__"} == methods
    for m in methods | ({"__init__"} & set(stub_methods)):
        assert _stub_params(stub_methods[m]) == _binding_params(getattr(cls, m)), f"{name}.{m}"


def test_build_topology_params_match():
    functions, _ = _stub_tree()
    assert _stub_params(functions["build_topology"]) == _binding_params(_core.build_topology)


def test_a_stale_stub_is_caught():
    """The comparison itself can fail: a parameter missing from a stub is seen."""
    fn = ast.parse("def contour_test(loop, V, l, r=None): ...").body[0]
    assert _stub_params(fn) != _binding_params(_core.contour.contour_test)
