"""The extension's type stub (fnopt/_fnopt.pyi) names exactly what the module has, with the same
argument names, and every public function, method and property is documented (numpydoc)."""
import ast
import inspect
import pathlib
import re

import pytest

import fnopt
from fnopt import _fnopt

PACKAGE = pathlib.Path(fnopt.__file__).resolve().parent
STUB = ast.parse((PACKAGE / "_fnopt.pyi").read_text())


def public(names):
    return {n for n in names if not n.startswith("_")}


def stub_names(body):
    """Names a stub module or class body defines (functions, classes, annotated names)."""
    names = set()
    for node in body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
    return names


def stub_classes():
    return {node.name: node for node in STUB.body if isinstance(node, ast.ClassDef)}


def stub_functions(body):
    return {node.name: node for node in body if isinstance(node, ast.FunctionDef)}


def stub_arguments(function):
    """The argument names of a stub's def, self left out, `**name` as `**`."""
    args = function.args
    names = [a.arg for a in args.posonlyargs + args.args + args.kwonlyargs]
    if args.vararg:
        names.append("*")
    if args.kwarg:
        names.append("**")
    return [n for n in names if n != "self"]


def split_top_level(text):
    parts, depth, current, quote = [], 0, "", None
    for c in text:
        if quote:
            quote = None if c == quote else quote
        elif c in "'\"":
            quote = c
        elif c in "([{":
            depth += 1
        elif c in ")]}":
            depth -= 1
        elif c == "," and depth == 0:
            parts.append(current)
            current = ""
            continue
        current += c
    if current.strip():
        parts.append(current)
    return [p.strip() for p in parts]


def runtime_arguments(function):
    """The argument names pybind11 gives a function (its docstring's signature line)."""
    line = function.__doc__.splitlines()[0]
    inside = line[line.index("(") + 1 : line.rindex(") ->")]
    names = []
    for part in split_top_level(inside):
        if part.startswith("**"):
            names.append("**")
        elif part.startswith("*"):
            names.append("*")
        else:
            names.append(re.split(r"[:=]", part)[0].strip())
    return [n for n in names if n != "self"]


def test_the_stub_names_every_public_name_of_the_module_and_no_other():
    module = public(dir(_fnopt)) | {"__version__"}
    stub = {n for n in stub_names(STUB.body) if not n.startswith("_") or n == "__version__"}
    assert module == stub


@pytest.mark.parametrize("name", sorted(stub_classes()))
def test_a_stub_class_has_exactly_the_classs_members(name):
    cls = getattr(_fnopt, name)
    stub = stub_names(stub_classes()[name].body)
    assert public(vars(cls)) == public(stub)
    for dunder in stub - public(stub):
        assert dunder in vars(cls), f"{name}.{dunder} is in the stub, not in the class"
    # A property in the stub is one in the class, a static method one too.
    for member, node in stub_functions(stub_classes()[name].body).items():
        decorators = {d.id for d in node.decorator_list if isinstance(d, ast.Name)}
        runtime = inspect.getattr_static(cls, member, None)
        assert ("property" in decorators) == isinstance(runtime, property), f"{name}.{member}"
        assert ("staticmethod" in decorators) == isinstance(runtime, staticmethod), f"{name}.{member}"


def functions_and_methods():
    yield from ((name, getattr(_fnopt, name), node) for name, node in stub_functions(STUB.body).items())
    for class_name, class_node in stub_classes().items():
        cls = getattr(_fnopt, class_name)
        for name, node in stub_functions(class_node.body).items():
            member = inspect.getattr_static(cls, name, None)
            if member is None or isinstance(member, property):
                continue  # a member the class lacks fails test_a_stub_class_has_exactly_the_classs_members
            yield f"{class_name}.{name}", getattr(cls, name), node


@pytest.mark.parametrize("name, function, node", list(functions_and_methods()), ids=lambda x: x if isinstance(x, str) else None)
def test_a_functions_arguments_have_the_stubs_names(name, function, node):
    assert runtime_arguments(function) == stub_arguments(node), name


def documented():
    for name in public(dir(_fnopt)):
        member = getattr(_fnopt, name)
        if callable(member) and not isinstance(member, type):
            yield name, member
    for cls in (_fnopt.Scene, _fnopt.Simulator, _fnopt.StepProblem, _fnopt.Rollout, _fnopt.RecordedRollout):
        for name, member in vars(cls).items():
            if not name.startswith("_") or name in ("__eq__", "__repr__"):
                yield f"{cls.__name__}.{name}", member


@pytest.mark.parametrize("name, member", list(documented()), ids=lambda x: x if isinstance(x, str) else None)
def test_every_public_function_method_and_property_is_documented(name, member):
    if isinstance(member, property):
        # numpydoc's form for a property: "type: what it is."
        assert re.match(r"^[\w. ,()]+: \S", member.__doc__ or ""), f"{name}: {member.__doc__!r}"
        return
    member = getattr(member, "__func__", member)
    doc = member.__doc__
    assert "Returns\n-------\n" in doc, name
    if runtime_arguments(member):
        assert "Parameters\n----------\n" in doc, name


def test_every_class_and_record_says_what_it_is_and_its_constructors_parameters():
    for cls in (_fnopt.Scene, _fnopt.Simulator, fnopt.StepRecord, fnopt.Material, fnopt.Comparison, fnopt.CompareRow,
                fnopt.Evaluation, fnopt.RolloutFile):
        assert "Parameters\n    ----------\n" in cls.__doc__ or "Parameters\n----------\n" in cls.__doc__, cls
    for cls in (_fnopt.StepProblem, _fnopt.Rollout, _fnopt.RecordedRollout, _fnopt.Error):
        assert len(cls.__doc__.split()) > 10, cls


def test_the_package_is_marked_typed():
    assert (PACKAGE / "py.typed").is_file()
