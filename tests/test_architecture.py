"""The house's structure (`docs/concepts/architecture.md`): no import cycle between rockcal's
modules, counting imports inside functions (a lazy import that breaks a cycle at run time is
still one in the design) and `from rockcal import X` as an import of the package's face; no
cycle between its rooms (the subpackages and top-level modules); the engines load no lab test,
material or campaign; parsing a campaign file loads no planner."""

import ast
import subprocess
import sys
from graphlib import CycleError, TopologicalSorter
from pathlib import Path

import pytest

import rockcal

SRC = Path(rockcal.__file__).parent.parent


def _modules() -> dict[str, Path]:
    found = {}
    for path in (SRC / "rockcal").rglob("*.py"):
        name = ".".join(path.relative_to(SRC).with_suffix("").parts).removesuffix(".__init__")
        found[name] = path
    return found


MODULES = _modules()


def _module_of(name: str) -> str | None:
    """The module an imported name lives in (its longest prefix that is a module)."""
    while name and name not in MODULES:
        name = name.rpartition(".")[0]
    return name or None


def _imports(name: str) -> set[str]:
    """The rockcal modules `name` imports, anywhere in it but under `if TYPE_CHECKING:`."""
    path = MODULES[name]
    tree = ast.parse(path.read_text())
    typing_only = {id(n) for node in ast.walk(tree) if isinstance(node, ast.If)
                   and "TYPE_CHECKING" in ast.unparse(node.test) for b in node.body for n in ast.walk(b)}
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(tree):
        if id(node) in typing_only:
            continue
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(parts + ([base] if base else []))
            targets = [base, *(f"{base}.{alias.name}" for alias in node.names)]
        else:
            continue
        found |= {m for t in targets if (m := _module_of(t)) and m != name}
    return found


GRAPH = {name: _imports(name) for name in MODULES}


def _room(module: str) -> str:
    """rockcal.dem3d.laws -> dem3d; the face, rockcal, is a room of its own."""
    return module.split(".")[1] if "." in module else module


def _cycle(graph: dict) -> list | None:
    try:
        tuple(TopologicalSorter(graph).static_order())
    except CycleError as error:
        return error.args[1]
    return None


def test_no_import_cycle_between_modules():
    assert _cycle(GRAPH) is None


def test_no_import_cycle_between_rooms():
    rooms = {}
    for module, imported in GRAPH.items():
        rooms.setdefault(_room(module), set()).update(_room(m) for m in imported if _room(m) != _room(module))
    assert _cycle(rooms) is None


def _loaded_by(statement: str) -> set[str]:
    """The rockcal modules a fresh interpreter has loaded after `statement`."""
    code = f"{statement}; import sys; print(' '.join(m for m in sys.modules if m.startswith('rockcal')))"
    return set(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split())


@pytest.mark.parametrize("engine", ["rockcal.dem.simulate", "rockcal.dem3d.simulate"])
def test_an_engine_loads_no_lab_test_material_or_campaign(engine):
    loaded = _loaded_by(f"import {engine}")
    assert engine in loaded
    assert not {m for m in loaded if _room(m) in ("labtests", "materials", "campaign", "api", "cli", "specimens")}


def test_parsing_a_campaign_loads_no_planner():
    loaded = _loaded_by("import rockcal.campaign.input.config")
    assert not {m for m in loaded if m.startswith("rockcal.campaign.plan")}
