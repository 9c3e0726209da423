"""The import rule of docs/architecture.md, checked on every module's parsed imports: an
arrow the table forbids, an absolute import of our own package, or a Blender module in a
folder that must run without Blender fails here."""
import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[2]
RULE_PAGE = ROOT / "docs" / "architecture.md"
BLENDER_MODULES = {"bpy", "bpy_extras", "bl_ui", "bmesh", "mathutils", "addon_utils", "gpu", "gpu_extras",
                   "freestyle", "aud", "imbuf", "idprop"}
"""Modules Blender provides: in a folder of ours, an absolute `gpu` is Blender's."""
PACKAGE = "lpv_preview"


def import_rule(text):
    """{folder or file: (the parts of ours it may import, whether it may import Blender)}
    from the table between the page's import-rule markers."""
    table = text.split("<!-- import-rule -->")[1].split("<!-- /import-rule -->")[0]
    rule = {}
    for line in table.strip().splitlines()[2:]:
        name, ours, blender = (cell.strip().strip("`") for cell in line.strip("|").split("|"))
        rule[name.rstrip("/").removesuffix(".py")] = ({part.strip() for part in ours.split(",")}, blender == "yes")
    return rule


def imports_of(source, module_path):
    """(our top-level part, or None) and the absolute module for each import in `source`,
    the module at `module_path` (relative to the repository root)."""
    package = list(module_path.parent.parts)
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found += [(None, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0:
            found.append((None, node.module))
        elif isinstance(node, ast.ImportFrom):
            base = package[:len(package) - (node.level - 1)] if node.level > 1 else package
            if node.module:
                target = base + node.module.split(".")
                found.append((target[0], None))
            elif base:
                found.append((base[0], None))
            else:  # `from . import addon` at the root: the names are our parts
                found += [(alias.name, None) for alias in node.names]
    return found


def violations(source, module_path, rule):
    """What in `source` breaks `rule` for the module at `module_path`."""
    owner = module_path.parts[0] if len(module_path.parts) > 1 else module_path.stem
    ours_allowed, blender_allowed = rule[owner]
    wrong = []
    for ours, absolute in imports_of(source, module_path):
        if ours is not None and ours not in ours_allowed:
            wrong.append(f"{module_path} imports {ours}/")
        if absolute is not None:
            top = absolute.split(".")[0]
            if top == PACKAGE:
                wrong.append(f"{module_path} imports {absolute} absolutely; import our modules relatively")
            elif top in BLENDER_MODULES and not blender_allowed:
                wrong.append(f"{module_path} imports Blender's {absolute}")
    return wrong


def checked_modules(rule):
    for name in rule:
        path = ROOT / name
        yield from (sorted(path.rglob("*.py")) if path.is_dir() else [path.with_suffix(".py")])


def test_every_module_follows_the_import_rule():
    rule = import_rule(RULE_PAGE.read_text())
    assert {"gpu", "corrections", "bench", "addon", "operators", "demo", "cli", "__init__", "__main__"} <= set(rule)
    assert rule["gpu"] == ({"gpu"}, False) and rule["bench"] == ({"gpu", "bench"}, False)
    assert rule["corrections"] == ({"gpu", "corrections"}, False)
    modules = list(checked_modules(rule))
    assert len(modules) > 40
    wrong = [line for path in modules for line in violations(path.read_text(), path.relative_to(ROOT), rule)]
    assert not wrong, "\n".join(wrong)


@pytest.mark.parametrize("path, source, message", [
    ("gpu/pipeline.py", "from ..bench.sweep import run_sweep", "gpu/pipeline.py imports bench/"),
    ("gpu/pipeline.py", "from ..addon import extract", "gpu/pipeline.py imports addon/"),
    ("gpu/scene.py", "import bpy", "imports Blender's bpy"),
    ("bench/sweep.py", "import gpu", "imports Blender's gpu"),
    ("addon/engine.py", "from .. import bench", "addon/engine.py imports bench/"),
    ("operators/compare.py", "from ...bench.page import write_benchmarks_page", "imports bench/"),
    ("__init__.py", "from . import gpu, addon", "__init__.py imports gpu/"),
    ("addon/ui.py", "from lpv_preview.gpu import settings", "absolutely"),
    ("gpu/shade.py", "from ..corrections.guide import Guide", "gpu/shade.py imports corrections/"),
    ("corrections/worker_task.py", "from ..addon.cycles_samples import SampleRenderer", "imports addon/"),
    ("corrections/layers.py", "import bpy", "imports Blender's bpy"),
    ("addon/batch.py", "from ..cli.flags import pass_names", "addon/batch.py imports cli/"),
])
def test_the_check_finds_a_forbidden_arrow(path, source, message):
    rule = import_rule(RULE_PAGE.read_text())
    wrong = violations(source, Path(path), rule)
    assert len(wrong) == 1 and message in wrong[0], wrong


def test_no_module_outside_bench_names_it_in_an_import():
    pattern = re.compile(r"^\s*(from|import)\s.*\bbench\b", re.MULTILINE)
    for folder in ("gpu", "corrections", "addon", "operators", "demo"):
        for path in (ROOT / folder).rglob("*.py"):
            assert not pattern.search(path.read_text()), path


def test_a_sample_worker_unpickles_its_task_without_bpy_or_addon():
    """A Dask worker imports the task's module before anything else: it must load neither
    bpy nor addon/, whose first bpy import has to find the module, not Blender's scripts."""
    import subprocess
    import sys
    probe = ("import sys, lpv_preview.corrections.worker_task, lpv_preview.corrections.sample_workers; "
             "print(sorted(m for m in sys.modules if m == 'bpy' or m.startswith('lpv_preview.addon')))")
    result = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "[]"


def module_edges(path):
    """The modules of ours that the module at `path` imports, at any depth of its code
    (a lazy import inside a function makes a circle all the same), as repository paths."""
    relative = path.relative_to(ROOT)
    package = list(relative.parent.parts)
    edges = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if not isinstance(node, ast.ImportFrom) or node.level == 0:
            continue
        base = package[:len(package) - (node.level - 1)] if node.level > 1 else package
        target = base + (node.module.split(".") if node.module else [])
        candidates = [target + [alias.name] for alias in node.names] + [target]
        for parts in candidates:
            module = ROOT.joinpath(*parts).with_suffix(".py") if parts else None
            if module is not None and module.is_file():
                edges.add(module)
                break
    return edges


def test_no_modules_import_each_other_in_a_circle():
    rule = import_rule(RULE_PAGE.read_text())
    modules = list(checked_modules(rule))
    graph = {path: module_edges(path) for path in modules}
    visiting, done, circles = [], set(), []

    def visit(path):
        if path in done:
            return
        if path in visiting:
            circles.append(" -> ".join(str(p.relative_to(ROOT)) for p in visiting[visiting.index(path):] + [path]))
            return
        visiting.append(path)
        for target in graph.get(path, ()):
            visit(target)
        visiting.pop()
        done.add(path)

    for path in modules:
        visit(path)
    assert graph[ROOT / "addon" / "viewport_draw.py"] == {ROOT / "addon" / "viewport.py"}
    assert not circles, "\n".join(circles)


def test_the_layout_names_every_module():
    layout = RULE_PAGE.read_text().split("## Layout")[1].split("## ")[0]
    listed = set(re.findall(r"^\s+(\w+\.py)\s", layout, re.MULTILINE))
    for folder in ("gpu", "corrections", "addon", "operators", "cli", "bench"):
        for path in (ROOT / folder).glob("*.py"):
            assert path.name == "__init__.py" or path.name in listed, f"docs/architecture.md lacks {folder}/{path.name}"
