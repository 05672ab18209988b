"""The architecture of docs/architecture.md, checked on the source with ``ast`` (nothing is run).

Each folder of ``src/lmidsl/`` is a layer and imports only the layers below it (or its own);
there is no import cycle; ``src/lmidsl/`` has at most 12 entries; paper models live in
``theorems/<paper>/``, never in the library; no import hides inside a function except of the
optional heavy dependencies listed here.
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "lmidsl"

#: bottom to top; a module may import its own layer and the layers before it
LAYERS = ["errors", "symbolic", "theorem", "numeric", "solver", "certify", "pipeline", "studies",
          "render", "cli"]
#: the package's face and entry point may import any layer
ANY_LAYER = {"__init__", "__main__"}
#: may be imported inside a function: heavy, optional or used by one command only
LAZY_OK = ("tqdm", "matplotlib", "cvxpy", "picos", "scipy", "importlib", "distributed", "dask", "control",
           "cloudpickle", "threadpoolctl", "slycot")
PAPER_MODELS = ("impulsive", "interconnected", "sim_delay_dropout", "netsim", "quantizer", "delta")


def modules():
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE).with_suffix("").parts
        yield path, parts


def imported(path: Path, parts: tuple):
    """(lineno, absolute module, inside a function?) of every import of ``path``."""
    package = ["lmidsl", *parts[:-1]] if parts[-1] != "__init__" else ["lmidsl", *parts[:-1]]
    tree = ast.parse(path.read_text())
    inner = {id(n) for f in ast.walk(tree) if isinstance(f, (ast.FunctionDef, ast.AsyncFunctionDef))
             for n in ast.walk(f)}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[:len(package) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            yield node.lineno, target, id(node) in inner
        elif isinstance(node, ast.Import):
            for alias in node.names:
                yield node.lineno, alias.name, id(node) in inner


def layer_of(parts: tuple) -> str:
    return parts[0]


def test_top_level_has_at_most_twelve_entries_and_no_paper_model():
    entries = [p.name for p in PACKAGE.iterdir() if not p.name.startswith((".", "__pycache__"))]
    assert len(entries) <= 12, sorted(entries)
    stems = {Path(e).stem for e in entries}
    assert not stems & set(PAPER_MODELS)
    for _, parts in modules():
        assert parts[-1] not in PAPER_MODELS, parts


@pytest.mark.parametrize("path,parts", list(modules()), ids=lambda x: str(x) if isinstance(x, Path) else "")
def test_each_layer_imports_only_the_layers_below(path, parts):
    name = layer_of(parts).removesuffix(".py")
    for lineno, target, _ in imported(path, parts):
        if not target.startswith("lmidsl.") or name in ANY_LAYER:
            continue
        other = target.split(".")[1]
        assert other != "theorems", f"{path}:{lineno} imports a paper ({target})"
        assert other in LAYERS, f"{path}:{lineno}: unknown layer {other}"
        assert LAYERS.index(other) <= LAYERS.index(name), \
            f"{path}:{lineno}: layer {name} imports {target}, a layer above it"


def test_no_import_inside_a_function_except_heavy_optional_ones():
    """...and a command's own study, which the command line imports when the command runs (the
    layer check above sees those imports too)."""
    hidden = [f"{path.relative_to(ROOT)}:{lineno} {target}" for path, parts in modules()
              for lineno, target, inner in imported(path, parts)
              if inner and not target.startswith(LAZY_OK) and not (parts[0] == "cli" and target.startswith("lmidsl."))]
    assert not hidden, hidden


def test_no_import_cycle():
    graph = {}
    names = {".".join(["lmidsl", *p[:-1]] if p[-1] == "__init__" else ["lmidsl", *p]): (path, p)
             for path, p in modules()}
    for name, (path, parts) in names.items():
        deps = set()
        for _, target, _ in imported(path, parts):
            while target and target not in names:
                target = target.rsplit(".", 1)[0] if "." in target else ""
            if target and target != name and not name.startswith(target + "."):
                deps.add(target)
        graph[name] = deps
    state, cycles = {}, []

    def visit(u, stack):
        state[u] = 1
        stack.append(u)
        for v in sorted(graph[u]):
            if state.get(v) == 1:
                cycles.append(stack[stack.index(v):] + [v])
            elif not state.get(v):
                visit(v, stack)
        stack.pop()
        state[u] = 2

    for u in sorted(graph):
        if not state.get(u):
            visit(u, [])
    assert not cycles, cycles


def test_theorem_files_import_only_lmidsl_and_their_own_paper():
    for path in sorted((ROOT / "theorems").rglob("*.py")):
        for lineno, target, _ in imported(path, ("theorems",) + path.relative_to(ROOT / "theorems").with_suffix("").parts):
            if path.name in ("theorems.py", "__init__.py") and target.startswith("lmidsl"):
                assert target == "lmidsl" or target.startswith("lmidsl.theorems."), \
                    f"{path.relative_to(ROOT)}:{lineno} imports {target}: a theorem file imports only lmidsl"
