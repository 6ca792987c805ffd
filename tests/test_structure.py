"""The code's structure, as the project keeps it: rvcore's layers (which sub-package may
import which), its map (the package docstring names every module), no private name
imported from another module, every project import resolvable, and every design
reference pointing into docs/ (the project stands alone)."""
from __future__ import annotations

import ast
import importlib.util
import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
PACKAGES = ("rvcore", "pipeline")
SOURCES = sorted(p for pkg in PACKAGES + ("tests",) for p in (REPO / pkg).rglob("*.py") if "__pycache__" not in p.parts)
#: rvcore's own shared module (the kernel decorator and the cache): private to the
#: project, not to one module.
SHARED_PRIVATE = "rvcore._numba"


def _module_name(path: Path) -> str:
    parts = path.relative_to(REPO).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path):
    """``(line, module, names)`` of every ``import``/``from … import`` in ``path``, the
    module made absolute."""
    tree = ast.parse(path.read_text(), str(path))
    package = _module_name(path) if path.name == "__init__.py" else _module_name(path).rpartition(".")[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[:len(base) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            yield node.lineno, module, [a.name for a in node.names]
        elif isinstance(node, ast.Import):
            for a in node.names:
                yield node.lineno, a.name, []


def _project_imports():
    """``(where, module, names)`` of every import of the project's own modules."""
    for path in SOURCES:
        for line, module, names in _imports(path):
            if module.split(".")[0] in PACKAGES + ("tests",):
                yield f"{path.relative_to(REPO)}:{line}", module, names


def test_no_private_name_is_imported_from_another_module():
    found = []
    for where, module, names in _project_imports():
        parts = names + module.split(".")
        if module == SHARED_PRIVATE:
            parts = names
        elif module == "rvcore":
            parts = [n for n in parts if n != "_numba"]
        private = [n for n in parts if n.startswith("_") and not n.startswith("__")]
        if private:
            found.append(f"{where}: {module} {private}")
    assert not found, "\n".join(found)


def test_every_project_import_resolves():
    missing = []
    for where, module, names in _project_imports():
        if importlib.util.find_spec(module) is None:
            missing.append(f"{where}: no module {module}")
            continue
        missing += [f"{where}: {module} has no {name}" for name in names if not _provides(module, name)]
    assert not missing, "\n".join(missing)


def _provides(module: str, name: str) -> bool:
    """Whether ``from module import name`` finds a name or a submodule."""
    mod = importlib.import_module(module)
    if hasattr(mod, name):
        return True
    return hasattr(mod, "__path__") and importlib.util.find_spec(f"{module}.{name}") is not None


def test_design_references_point_into_docs():
    """Every 'model.md' a source file cites is docs/model.md, and 'pipeline.md' (a
    specification outside the project) is not cited at all; every § cited exists."""
    sections = set(re.findall(r"^#+ §?(\d+(?:\.\d+)?)", (REPO / "docs" / "model.md").read_text(), flags=re.M))
    bad = []
    for path in SOURCES:
        if path == Path(__file__).resolve():
            continue
        text = path.read_text()
        for m in re.finditer(r"(\S*)model\.md(?: §(\d+(?:\.\d+)?))?", text):
            if not m.group(1).endswith("docs/") or (m.group(2) and m.group(2) not in sections):
                bad.append(f"{path.relative_to(REPO)}: {m.group(0)}")
        bad += [f"{path.relative_to(REPO)}: pipeline.md" for _ in re.finditer(r"\bpipeline\.md", text)]
    assert not bad, "\n".join(bad)


#: rvcore's layers, lowest first: a module may import from its own layer and the layers
#: below it, never from one above (docs: the map in rvcore/__init__.py).
LAYERS = ("_numba", "hertz", "standards", "output_table", "bearing", "rings", "contact", "profile", "dynamics", "statics",
          "recording", "integrate", "simulation")
#: What a layer may import besides itself, where the rule is tighter than "any layer below".
ONLY = {"hertz": {"_numba"}, "standards": {"_numba", "hertz"}}
RVCORE = REPO / "rvcore"


def _layer(module: str) -> str:
    """The layer of ``rvcore.<layer>[.<module>]``."""
    return module.split(".")[1]


def _rvcore_imports():
    """``(where, importing layer, imported layer)`` of every import between rvcore's layers."""
    for path in sorted(RVCORE.rglob("*.py")):
        if "__pycache__" in path.parts or path == RVCORE / "__init__.py":
            continue
        here = _layer(_module_name(path))
        for line, module, names in _imports(path):
            if module.split(".")[0] != "rvcore":
                continue
            targets = [module] if module != "rvcore" else [f"rvcore.{n}" for n in names]
            for target in targets:
                if target.count(".") == 1 and target.split(".")[1] in LAYERS and _layer(target) == here:
                    continue
                yield f"{path.relative_to(REPO)}:{line}", here, _layer(target)


def test_every_rvcore_module_sits_in_a_layer():
    layers = {_layer(_module_name(p)) for p in RVCORE.rglob("*.py")
              if "__pycache__" not in p.parts and p != RVCORE / "__init__.py"}
    assert layers == set(LAYERS)


def _upward(edges) -> list:
    """The ``(where, layer, imported layer)`` edges that break the layer rule."""
    return [f"{where}: {here} imports {there}" for where, here, there in edges
            if there != here and (there not in LAYERS or LAYERS.index(there) > LAYERS.index(here)
                                  or (here in ONLY and there not in ONLY[here]))]


def test_no_rvcore_module_imports_from_a_layer_above_its_own():
    edges = list(_rvcore_imports())
    assert ("x", "dynamics", "contact") in [("x", h, t) for _, h, t in edges]  # the walk sees imports
    upward = _upward(edges)
    assert not upward, "\n".join(upward)


def test_the_layer_rule_flags_an_upward_import_and_passes_a_downward_one():
    assert _upward([("a.py:1", "standards", "bearing")]) == ["a.py:1: standards imports bearing"]
    assert _upward([("a.py:1", "standards", "output_table")])   # below it, yet not _numba
    assert _upward([("a.py:1", "contact", "statics")])
    assert _upward([("a.py:1", "simulation", "integrate"), ("a.py:2", "standards", "_numba")]) == []


def _module_graph() -> dict:
    """``{module: modules it imports}`` among rvcore's and pipeline's own modules, imports
    inside functions included (``from . import imex`` names the module ``imex``; an import
    from a package that is not one of its modules names the package's ``__init__``)."""
    paths = {_module_name(p): p for pkg in PACKAGES for p in (REPO / pkg).rglob("*.py")
             if "__pycache__" not in p.parts}
    graph = {}
    for module, path in paths.items():
        targets = set()
        for _, imported, names in _imports(path):
            if imported.split(".")[0] not in PACKAGES:
                continue
            submodules = {f"{imported}.{n}" for n in names if f"{imported}.{n}" in paths}
            targets |= submodules or ({imported} if imported in paths else set())
        graph[module] = targets - {module}
    return graph


def _circles(graph: dict) -> list:
    """The import circles of ``graph``: each set of two or more modules that import one
    another, directly or through each other (a strongly connected component, Tarjan)."""
    index, low, stack, on_stack, circles = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while not component or component[-1] != v:
                component.append(stack.pop())
                on_stack.discard(component[-1])
            if len(component) > 1:
                circles.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(circles)


def test_no_modules_import_each_other_in_a_circle():
    """Each module sits above all it imports: no module of rvcore or pipeline imports one
    that imports it back, directly or around a circle (a circle is a concept cut in two)."""
    graph = _module_graph()
    assert "rvcore.integrate.imex" in graph["rvcore.integrate.methods"]   # the walk sees `from . import x`
    circles = _circles(graph)
    assert not circles, "\n".join(" <-> ".join(c) for c in circles)


def test_the_circle_check_finds_a_circle_and_passes_a_chain():
    assert _circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert _circles({"a": {"b"}, "b": {"a"}, "c": {"d"}, "d": {"c"}}) == [["a", "b"], ["c", "d"]]
    assert _circles({"a": {"b", "c"}, "b": {"c"}, "c": set()}) == []


def _map_entries() -> set:
    """The modules named in rvcore's map (its docstring's ``- ``name`` `` lines)."""
    import rvcore

    return set(re.findall(r"^- ``([a-z_0-9.]+)``", rvcore.__doc__, flags=re.M))


def test_every_module_named_in_the_map_exists_and_every_module_is_named():
    on_disk = {_module_name(p).removeprefix("rvcore.") for p in RVCORE.rglob("*.py")
               if "__pycache__" not in p.parts and p.name != "__init__.py"}
    named = _map_entries()
    assert named - on_disk == set(), "named in rvcore/__init__.py but not there"
    assert on_disk - named == set(), "there but not named in rvcore/__init__.py"


def test_every_kernel_is_compiled_by_the_one_decorator():
    """No module of rvcore calls numba's ``njit``/``jit`` itself: every kernel goes
    through ``rvcore._numba.kernel``, which sets the flags and the error model once."""
    found = [f"{p.relative_to(REPO)}:{n}" for p in sorted(RVCORE.rglob("*.py"))
             if "__pycache__" not in p.parts and p.name != "_numba.py"
             for n, line in enumerate(p.read_text().splitlines(), 1)
             if re.search(r"\b(njit|jit|vectorize|generated_jit)\s*\(|@(njit|jit)\b|from numba import", line)]
    assert not found, "\n".join(found)


def test_the_kernel_decorator_sets_the_error_model_and_no_fast_math():
    from rvcore.contact.laws import hertz_load
    from rvcore.dynamics.rhs import rhs

    for fn in (rhs, hertz_load):
        options = fn.targetoptions
        assert options["error_model"] == "numpy" and options["fastmath"] is False
        assert options["nogil"] is True
    assert hertz_load.targetoptions["inline"] == "always" and rhs.targetoptions["inline"] == "never"


#: Where the project names its own modules in prose: the README, docs/ and every docstring
#: and comment (CHANGELOG.md is history: it names what was renamed, under the old names).
PROSE = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md")), *SOURCES]
#: ``rvcore.integrate.imex.TANGENT_LOAD_TOL``, ``pipeline.schema.fields.Field`` (not a file
#: name such as ``pipeline.md``, nor a family such as ``rvcore.profile.CH_*``).
_DOTTED = re.compile(r"(?<![\w./-])((?:rvcore|pipeline)(?:\.[A-Za-z_]\w*)+)(?![\w*])")
#: ``rvcore/dynamics/races.py``, ``pipeline/run/`` as a path from the repository's root.
_PATH = re.compile(r"(?<![\w./-])((?:rvcore|pipeline|tests|tools)/[\w/.-]*\w)")
#: A bare ``races.py`` in the README or docs/ (in backticks or a link).
_FILE = re.compile(r"[`(]([A-Za-z_]\w*\.py)\b")
#: Names that are not in a checkout on purpose: the shipped files' home inside a wheel, and
#: Exudyn's example that the 6010 bearing's data come from (docs/validation.md).
_ELSEWHERE = {"pipeline/sweeps", "ballBearningModel.py"}


def _resolves(name: str) -> bool:
    """Whether the dotted ``name`` is a module, or a module and attributes (a dataclass's
    fields count) found in it."""
    parts = name.split(".")
    for i in range(len(parts), 0, -1):
        module = ".".join(parts[:i])
        try:
            found = importlib.util.find_spec(module) is not None
        except ModuleNotFoundError:
            found = False
        if not found:
            continue
        obj = importlib.import_module(module)
        for attr in parts[i:]:
            if attr in getattr(obj, "__dataclass_fields__", {}):
                return attr == parts[-1]
            if not hasattr(obj, attr):
                return False
            obj = getattr(obj, attr)
        return True
    return False


def _stale_names(files) -> list:
    """``where: name`` of every module, function or path named in ``files`` that does not exist."""
    on_disk = {p.name for p in REPO.rglob("*.py") if ".venv" not in p.parts}
    bad = []
    for path in files:
        if path == Path(__file__).resolve():
            continue
        text, where = path.read_text(), path.relative_to(REPO) if path.is_relative_to(REPO) else path.name
        bad += [f"{where}: {m.group(1)}" for m in _DOTTED.finditer(text)
                if not m.group(1).endswith((".md", ".py", ".toml", ".nc")) and not _resolves(m.group(1))]
        bad += [f"{where}: {m.group(1)}" for m in _PATH.finditer(text)
                if m.group(1) not in _ELSEWHERE and not (REPO / m.group(1)).exists()]
        if path.suffix == ".md":
            bad += [f"{where}: {m.group(1)}" for m in _FILE.finditer(text)
                    if m.group(1) not in on_disk | _ELSEWHERE]
    return sorted(set(bad))


def test_every_module_function_and_path_named_in_the_docs_and_docstrings_exists():
    """Names in prose go stale when code moves (issue 38 found 14); each must resolve."""
    stale = _stale_names(PROSE)
    assert not stale, "\n".join(stale)


def test_the_stale_name_check_finds_a_moved_module(tmp_path):
    doc = tmp_path / "x.md"
    doc.write_text("See `rvcore.driver.Sensor`, rvcore/integrator.py and `friction_law.py`; "
                   "`rvcore.simulation.settings.Sensor`, `Bearing.rows` as "
                   "rvcore.bearing.geometry.Bearing.rows and rvcore/integrate/loop.py are real.")
    assert _stale_names([doc]) == ["x.md: friction_law.py", "x.md: rvcore.driver.Sensor", "x.md: rvcore/integrator.py"]
