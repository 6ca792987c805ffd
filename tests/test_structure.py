"""The code's structure, as the project keeps it: modules under 500 lines, no private
name imported from another module, every project import resolvable, and every design
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
MAX_LINES = 500


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


@pytest.mark.parametrize("path", [p for p in SOURCES if p.parts[len(REPO.parts)] in PACKAGES],
                         ids=lambda p: str(p.relative_to(REPO)))
def test_module_is_at_most_500_lines(path):
    assert len(path.read_text().splitlines()) <= MAX_LINES


def _project_imports():
    """``(where, module, names)`` of every import of the project's own modules."""
    for path in SOURCES:
        for line, module, names in _imports(path):
            if module.split(".")[0] in PACKAGES + ("tests",):
                yield f"{path.relative_to(REPO)}:{line}", module, names


def test_no_private_name_is_imported_from_another_module():
    found = []
    for where, module, names in _project_imports():
        private = [n for n in names + module.split(".") if n.startswith("_") and not n.startswith("__")]
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
