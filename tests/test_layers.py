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
LAZY_OK = ("matplotlib", "cvxpy", "picos", "scipy", "importlib", "distributed", "dask", "control",
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


# -- judge once (issue 34): the verdict is built in certify/, points come from the plan, a status is
# a solver's word, a theorem file sees only the public face ---------------------------------------
THEOREMS = ROOT / "theorems"

#: the modules that may solve a compiled model without the plan, each with its one-line reason
OFF_THE_ROAD = {
    ("solver", "plan"): "the road itself",
    ("solver", "margin"): "the plan's margin escalation, which the plan calls",
    ("solver", "fallback"): "the plan's closed forms and routes",
    ("solver", "feasibility"): "the feasp diagnosis solves its own problem, not the theorem's",
    ("solver", "backoff"): "the condition-minimising search solves its own (t, κ) problems; its point is judged like any other",
    ("certify", "dual_bound"): "a proof re-solves shifted duals, not the theorem",
    ("certify", "infeasibility"): "a proof solves the alternative's SDP, not the theorem",
    ("studies", "export"): "export --check solves the compiled model as written: the file states that SDP",
}


def _calls(path: Path):
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            func = node.func
            name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
            yield node.lineno, name, func


@pytest.mark.parametrize("path,parts", list(modules()), ids=lambda x: str(x) if isinstance(x, Path) else "")
def test_only_certify_builds_a_verdict(path, parts):
    """Every result is judged by one module: a Verdict is built in certify/ only."""
    if parts[0] == "certify":
        return
    for lineno, name, _ in _calls(path):
        assert name not in ("Verdict", "decide"), f"{path}:{lineno} builds a verdict outside certify/"


@pytest.mark.parametrize("path,parts", list(modules()), ids=lambda x: str(x) if isinstance(x, Path) else "")
def test_every_point_comes_from_the_plan(path, parts):
    """No study, pipeline or command solves a compiled model itself (``solve_model``,
    ``model.solve``): each asks the plan, except the modules of :data:`OFF_THE_ROAD`, each with
    its reason."""
    if tuple(parts[:2]) in OFF_THE_ROAD or parts[0] == "solver" and parts[1] == "backends":
        return
    for lineno, name, func in _calls(path):
        receiver = func.value.id if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name) else ""
        assert name != "solve_model", f"{path}:{lineno} calls solve_model: ask the plan (solver/plan.py)"
        assert not (name == "solve" and "model" in receiver), \
            f"{path}:{lineno} calls {receiver}.solve: ask the plan (solver/plan.py)"


def test_a_status_is_a_solver_termination_word():
    """``Solution.status`` is assigned only by backends (their termination word) or from the
    plan's own solutions; no module writes a feasp or verdict word into it."""
    for path, parts in modules():
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.Assign):
                for target in node.targets:
                    if isinstance(target, ast.Attribute) and target.attr == "status" and \
                            isinstance(target.value, ast.Name) and target.value.id in ("solution", "sol", "new", "found"):
                        raise AssertionError(f"{path}:{node.lineno} rewrites a solution's status")


def test_status_words_are_termination_words():
    from lmidsl.solver import status

    words = {v for k, v in vars(status).items() if k.isupper() and isinstance(v, str)}
    assert words == set(status.TERMINATION_WORDS)


def theorem_files():
    return sorted(p for p in THEOREMS.rglob("*.py") if "__pycache__" not in p.parts)


@pytest.mark.parametrize("path", theorem_files(), ids=lambda p: str(p.relative_to(THEOREMS)))
def test_a_theorem_file_imports_only_the_public_face(path):
    """A theorem file imports ``lmidsl`` (the public face), its own paper's modules and third-party
    packages; never a module below the face (``lmidsl.theorem.robust``), never through importlib."""
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and not node.level:
            module = node.module or ""
            assert not module.startswith("lmidsl."), f"{path}:{node.lineno} imports {module}: use `from lmidsl import ...`"
        elif isinstance(node, ast.Import):
            for alias in node.names:
                assert not alias.name.startswith("lmidsl."), f"{path}:{node.lineno} imports {alias.name}"
                assert alias.name != "importlib", f"{path}:{node.lineno} imports importlib"


def test_the_package_imports_nothing_through_importlib_but_the_public_face_and_the_registry():
    """``importlib.import_module`` hides an import from the layer check: only the package's face
    (PEP 562 lazy names), the theorem registry (it loads theorem files), the build cache, the backend
    registry (optional modelling layers), the command line (one command's module when it runs) and
    the notebook display (IPython, when present), a Dask worker's warm-up (the modules it
    preloads, by name) and certify's face (its own modules, when a name is first used)."""
    allowed = {("__init__",), ("theorem", "registry"), ("theorem", "build_cache"), ("solver", "backends", "__init__"),
               ("render", "notebook"), ("cli", "__init__"), ("studies", "parallel"), ("certify", "__init__")}
    for path, parts in modules():
        for lineno, name, func in _calls(path):
            if name == "import_module":
                assert tuple(parts) in allowed, f"{path}:{lineno} imports through importlib"


def test_the_architecture_names_every_module():
    """docs/architecture.md has a row for every module (``cli/*_cmd.py`` by its wildcard)."""
    import re

    doc = (ROOT / "docs" / "architecture.md").read_text()
    rows = [line.split(" | ")[0] for line in doc.splitlines() if line.startswith("| `")]
    named = {m for row in rows for m in re.findall(r"`([^`]+\.py)`", row)}
    for path, parts in modules():
        rel = "/".join(parts) + ".py"
        folder = "/".join(parts[:-1]) + "/" if len(parts) > 1 else ""
        if rel in named or (parts[0] == "cli" and rel.endswith("_cmd.py")):
            continue
        assert any(row.startswith(f"| `{folder}") and f"`{parts[-1]}.py`" in row for row in rows), \
            f"docs/architecture.md does not name {rel}"
