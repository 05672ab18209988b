"""Start-up: a command imports what its work needs, and no more (the modules a process ends
with are read, never a clock).

* An unknown theorem id (of no module, or not defined by the module it names) is answered from
  the build cache and the ``list`` index, before sympy or the solving stack is imported, by the commands that take one theorem and check it first (``solve``, ``latex``,
  ``verify``, ``simulate``, ``derive-check``, ``reproduce --theorem``).
* ``lmidsl latex THEOREM`` needs sympy and the theorem, not scipy, the solvers or the pipeline.
* A theorem asked for by id is unpickled alone from its package's build-cache entry (the symbol
  metadata it restores is its own; the package's other theorems stay on disk), and the entry read
  alone is the one of the file as it is now.
"""
from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import pytest

from lmidsl.theorem import build_cache, registry

from conftest import ROOT

PROBE = '''
import sys
from lmidsl.cli import main
try:
    code = main(sys.argv[1:])
except SystemExit as exc:
    code = exc.code
print("EXIT", code, file=sys.stderr)
print("MODULES", " ".join(sorted(sys.modules)), file=sys.stderr)
'''

#: what the solving stack brings (scipy: scaling and the standard form; cvxpy, picos; clarabel,
#: 2 ms, comes with the solver options every command parses)
SOLVING = ("scipy", "cvxpy", "picos", "matplotlib", "dask", "control", "lmidsl.pipeline",
           "lmidsl.certify.analysis", "lmidsl.solver.plan")


def _env(tmp_path):
    env = {k: v for k, v in os.environ.items() if not k.startswith("LMIDSL_")}
    env["LMIDSL_CACHE_DIR"] = str(tmp_path / "cache")
    return env


def _run(env, *argv):
    """(exit code, stdout, stderr without the probe's lines, modules imported at the end)."""
    proc = subprocess.run([sys.executable, "-c", PROBE, *argv], cwd=ROOT, env=env, capture_output=True,
                          text=True, timeout=600)
    lines = proc.stderr.splitlines()
    code = int([l for l in lines if l.startswith("EXIT ")][-1].split()[1])
    modules = set([l for l in lines if l.startswith("MODULES ")][-1].split()[1:])
    err = "\n".join(l for l in lines if not l.startswith(("EXIT ", "MODULES ")))
    return code, proc.stdout, err, modules


def _imported(modules, names):
    return sorted(m for m in modules if m.split(".")[0] in names or m in names)


@pytest.fixture(scope="module")
def warm(tmp_path_factory):
    """A cache folder with the ``list`` index and every built-in package's entry written."""
    env = _env(tmp_path_factory.mktemp("startup"))
    code, out, err, _ = _run(env, "list")
    assert code == 0 and "textbook.brl_ct" in out, err
    return env


@pytest.mark.parametrize("argv", [["solve", "nosuch.thm"], ["latex", "nosuch.thm"], ["verify", "nosuch.thm"],
                                  ["simulate", "nosuch.thm"], ["derive-check", "nosuch.thm"],
                                  ["reproduce", "--theorem", "nosuch.thm"], ["solve", "textbook.brl_cx"],
                                  ["sweep", "--grid", "a=1:2:2", "nosuch.thm"], ["check", "nosuch.thm"],
                                  ["search", "--grid", "a=1:2:2", "nosuch.thm"], ["successive", "nosuch.thm"],
                                  ["export", "--format", "sdpa", "--output", "x.dat-s", "nosuch.thm"]],
                         ids=lambda a: " ".join(a))
def test_an_unknown_theorem_is_one_line_before_sympy_is_imported(warm, argv):
    """``textbook.brl_cx``: a module that exists, an id it does not define (its cache entry, valid
    for its files as they are, says so: nothing is unpickled)."""
    code, out, err, modules = _run(warm, *argv)
    theorem = argv[-1]
    assert code == 2 and out == ""
    assert err.startswith(f"error: unknown theorem '{theorem}'") and len(err.splitlines()) == 1, err
    assert theorem != "textbook.brl_cx" or "did you mean 'textbook.brl_ct'" in err
    assert not _imported(modules, ("sympy",) + SOLVING)


def test_latex_of_a_theorem_imports_sympy_and_the_theorem_only(warm):
    code, out, err, modules = _run(warm, "latex", "textbook.brl_ct")
    assert code == 0 and r"\begin{document}" in out, err
    assert "sympy" in modules
    assert not _imported(modules, SOLVING)
    assert "lmidsl.theorems.textbook" not in modules          # from the cache: the file did not run


def test_a_theorem_asked_for_by_id_is_unpickled_alone(warm):
    """Unpickling a theorem restores its symbols' metadata: after ``get_theorem`` only the asked
    theorem's is there, none of the 52 other theorems of its package."""
    script = textwrap.dedent('''
        from lmidsl.symbolic import symbols
        from lmidsl.theorem.registry import all_theorems, get_theorem
        thm = get_theorem("textbook.brl_ct")
        assert get_theorem("textbook.brl_ct") is thm            # one object per theorem in a process
        print(sorted({tag for tag, _ in symbols._METADATA}))
        print(sorted({tag for tag, _ in thm.__getstate__()["_symbol_metadata"]}))
        all_theorems()
        print(len({tag for tag, _ in symbols._METADATA if tag.startswith("textbook.")}))
        ''')
    proc = subprocess.run([sys.executable, "-c", script], cwd=ROOT, env=warm, capture_output=True, text=True,
                          timeout=600)
    assert proc.returncode == 0, proc.stderr
    alone, own, package = proc.stdout.splitlines()
    assert alone == own == "['textbook.brl_ct']"
    assert int(package) > 20                  # the whole package, read when every theorem is asked for


TWO = '''
from lmidsl import Theorem, Source
thms = []
for k, title in ((1, {one!r}), (2, "second")):
    thm = Theorem(f"pair.t{{k}}", title, Source("p", "eq", "c"))
    n = thm.dim("n")
    A = thm.data("A", n, n)
    P = thm.var("P", n, kind="symmetric")
    thm.lmi("(1)", [[A.T @ P + P @ A]])
    thm.positive(P)
    thms.append(thm)
THEOREMS = thms
'''


def test_one_theorem_read_alone_is_that_of_the_file_as_it_is_now(tmp_path, monkeypatch):
    monkeypatch.setenv("LMIDSL_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("LMIDSL_CACHE", raising=False)
    path = tmp_path / "pair.py"
    path.write_text(TWO.format(one="first"))
    label, files = registry._label("file", path), registry._location_files("file", path)
    assert build_cache.load_one(label, files, "pair.t1") is None          # nothing cached yet
    module = registry._import("file", path)
    build_cache.store(label, files, module, module.THEOREMS, [])
    one = build_cache.load_one(label, files, "pair.t1")
    assert one is not module.THEOREMS[0] and one.title == "first"
    assert build_cache.load_one(label, files, "pair.t2").title == "second"
    assert build_cache.load_one(label, files, "pair.t3") is build_cache.ABSENT      # not in the module
    path.write_text(TWO.format(one="edited"))                             # another key: not answered
    assert build_cache.load_one(label, files, "pair.t1") is None
    monkeypatch.setenv("LMIDSL_CACHE", "off")
    path.write_text(TWO.format(one="first"))
    assert build_cache.load_one(label, files, "pair.t1") is None


def test_get_theorem_reads_an_edited_user_file_again(tmp_path):
    """Through the registry, in fresh processes as a user runs them: the second run reads the
    theorem alone from the cache, and after an edit the third sees the edit."""
    (tmp_path / "thms").mkdir()
    path = tmp_path / "thms" / "pair.py"
    env = {**_env(tmp_path), "LMIDSL_THEOREM_PATH": str(tmp_path / "thms")}
    script = ("import sys; from lmidsl.theorem.registry import get_theorem; "
              "print(get_theorem('pair.t1').title, any(m.startswith('lmidsl_user_theorems_pair') for m in sys.modules))")
    titles = []
    for one in ("first", "first", "edited"):
        path.write_text(TWO.format(one=one))
        proc = subprocess.run([sys.executable, "-c", script], cwd=ROOT, env=env, capture_output=True, text=True,
                              timeout=600)
        assert proc.returncode == 0, proc.stderr
        titles.append(proc.stdout.split())
    assert titles == [["first", "True"], ["first", "False"], ["edited", "True"]]
