"""The theorem build cache (:mod:`lmidsl.theorem.build_cache`): a theorem loaded from the cache is
the theorem its file builds (the same LaTeX, the same compiled problem for every example, its
symbols' metadata restored), and an entry is never used once anything it was built from changed."""
from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from lmidsl.pipeline import make_instance
from lmidsl.render.notebook import theorem_display_latex
from lmidsl.solver.backends.direct_backend import DirectModel
from lmidsl.symbolic import symbols
from lmidsl.theorem import build_cache, registry

from conftest import ROOT

BUILTIN = sorted(registry._module_locations(()))


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("LMIDSL_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("LMIDSL_CACHE", raising=False)
    return tmp_path / "cache" / "theorems"


def _store_and_load(kind, where):
    """Build the module (or take it as imported), write its entry, read it back."""
    label, files = registry._label(kind, where), registry._location_files(kind, where)
    module = registry._import(kind, where)
    build_cache.store(label, files, module, list(module.THEOREMS), [])
    return module.THEOREMS, label, files


def _compiled(theorem, example):
    try:
        instance = make_instance(theorem, example)
    except Exception as exc:          # the same refusal is expected from the cached theorem
        return type(exc).__name__
    problem = DirectModel(instance).problem
    return problem.A.toarray(), problem.b, problem.q


@pytest.mark.parametrize("module_name", BUILTIN)
def test_a_cached_theorem_is_the_theorem_its_file_builds(cache, module_name):
    fresh, label, files = _store_and_load("builtin", module_name)
    latex = {t.id: theorem_display_latex(t) for t in fresh}
    problems = {(t.id, e): _compiled(t, e) for t in fresh for e in t.examples}
    tags = {t.id for t in fresh} | {f"{t.id}#derivation" for t in fresh}
    for key in [k for k in symbols._METADATA if k[0] in tags]:     # the cache must bring them back
        del symbols._METADATA[key]
    cached = build_cache.load(label, files)
    assert cached is not None and [t.id for t in cached] == [t.id for t in fresh]
    assert all(c is not f for c, f in zip(cached, fresh))
    for thm in cached:
        assert theorem_display_latex(thm) == latex[thm.id], thm.id
        for example in thm.examples:
            want, got = problems[(thm.id, example)], _compiled(thm, example)
            if isinstance(want, str):
                assert got == want, (thm.id, example)
            else:
                for a, b in zip(want, got):
                    np.testing.assert_array_equal(a, b, err_msg=f"{thm.id} {example}")


GOOD = '''
from lmidsl import Theorem, Source
from helper_{stamp} import TITLE
thm = Theorem("mine.t1", TITLE, Source("p", "eq", "c"))
n = thm.dim("n")
A = thm.data("A", n, n)
P = thm.var("P", n, kind="symmetric")
thm.lmi("(1)", [[A.T * P + P * A]])
thm.positive(P)
thm.example("one", {{"A": [[-1.0]]}})
THEOREMS = [thm]
'''


def _user_file(tmp_path, monkeypatch, title: str, stamp: str):
    """A user theorem file whose title comes from a helper module elsewhere on sys.path."""
    (tmp_path / "lib").mkdir(exist_ok=True)
    (tmp_path / "lib" / f"helper_{stamp}.py").write_text(f"TITLE = {title!r}\n")
    monkeypatch.syspath_prepend(str(tmp_path / "lib"))
    (tmp_path / "thms").mkdir(exist_ok=True)
    path = tmp_path / "thms" / "mine.py"
    path.write_text(GOOD.format(stamp=stamp))
    return path


def test_a_changed_file_or_helper_module_is_rebuilt(cache, tmp_path, monkeypatch):
    path = _user_file(tmp_path, monkeypatch, "first", "a")
    label, files = registry._label("file", path), registry._location_files("file", path)
    modules_before = set(sys.modules)
    module = registry._import("file", path)
    build_cache.store(label, files, module, module.THEOREMS,
                      [m for m in sys.modules if m not in modules_before])
    cached = build_cache.load(label, files)
    assert cached is not None and cached[0].title == "first"
    # the helper changes: the entry records it as a dependency
    (tmp_path / "lib" / "helper_a.py").write_text("TITLE = 'second'\n")
    assert build_cache.load(label, files) is None
    (tmp_path / "lib" / "helper_a.py").write_text("TITLE = 'first'\n")
    assert build_cache.load(label, files) is not None
    # the file changes: another key
    path.write_text(path.read_text() + "\n# edited\n")
    assert build_cache.load(label, files) is None


def test_a_damaged_entry_is_removed_and_rebuilt(cache):
    _, label, files = _store_and_load("builtin", "decay_rate")
    [entry] = list(cache.glob("*.pickle"))
    entry.write_bytes(entry.read_bytes()[:100])
    assert build_cache.load(label, files) is None
    assert not entry.exists()


def test_the_cache_can_be_turned_off(cache, monkeypatch):
    monkeypatch.setenv("LMIDSL_CACHE", "off")
    _store_and_load("builtin", "decay_rate")
    assert not cache.exists() or not list(cache.glob("*.pickle"))


PROBE = '''
import sys
from lmidsl.cli import main
try:
    main(sys.argv[1:])
except SystemExit:
    pass
print("THEOREM FILE RAN", "lmidsl.theorems.wang_l2linf.theorems" in sys.modules, file=sys.stderr)
'''


def test_a_second_solve_does_not_run_the_theorem_file(tmp_path):
    env = {k: v for k, v in os.environ.items() if not k.startswith("LMIDSL_")}
    env["LMIDSL_CACHE_DIR"] = str(tmp_path / "cache")
    runs = []
    for _ in range(2):
        proc = subprocess.run([sys.executable, "-c", PROBE, "solve", "wang_l2linf.thm3", "--example",
                               "paper-full", "--json"], cwd=ROOT, env=env, capture_output=True,
                              text=True, timeout=600)
        assert proc.returncode == 0, proc.stderr
        ran = [l for l in proc.stderr.splitlines() if l.startswith("THEOREM FILE RAN")][-1]
        out = json.loads(proc.stdout)
        out.pop("times")
        runs.append((ran.endswith("True"), out))
    assert runs[0][0] and not runs[1][0]
    assert runs[0][1] == runs[1][1]


def test_user_functions_are_pickled_by_value(cache, tmp_path):
    """A theorem file's own functions (a simulator) come back without importing the file."""
    path = tmp_path / "simfile.py"
    path.write_text(textwrap.dedent('''
        from lmidsl import Theorem, Source
        def simulate(x):
            return 2 * x
        thm = Theorem("simfile.t1", "t", Source("p", "eq", "c"))
        n = thm.dim("n")
        P = thm.var("P", n, kind="symmetric")
        thm.positive(P)
        thm.helper = simulate
        THEOREMS = [thm]
        '''))
    label, files = registry._label("file", path), registry._location_files("file", path)
    module = registry._import("file", path)
    build_cache.store(label, files, module, module.THEOREMS, [])
    del sys.modules[module.__name__]
    [thm] = build_cache.load(label, files)
    assert thm.helper(21) == 42
    assert module.__name__ not in sys.modules


def test_old_entries_are_evicted(cache, monkeypatch):
    """At most MAX_ENTRIES entries: the oldest go (moved or deleted theorem files leave entries
    that no key asks for again)."""
    monkeypatch.setattr(build_cache, "MAX_ENTRIES", 2)
    for i, name in enumerate(("decay_rate", "wang_l2linf", "li_delay_dropout")):
        _store_and_load("builtin", name)
        for entry in cache.glob(f"lmidsl.theorems.{name}-*.pickle"):   # distinct times on any file system
            os.utime(entry, (1_000_000 + i, 1_000_000 + i))
    kept = sorted(p.name.split("-")[0] for p in cache.glob("*.pickle"))
    assert kept == ["lmidsl.theorems.li_delay_dropout", "lmidsl.theorems.wang_l2linf"]


def test_a_pickled_theorem_carries_the_metadata_of_another_theorems_symbols():
    """A theorem whose LMI uses another theorem's variable (a printed form written with the solved
    theorem's P) brings that symbol's LaTeX name along when pickled alone."""
    import pickle

    from lmidsl import Source, Theorem

    owner = Theorem("pickletest.owner", "o", Source("p", "eq", "c"))
    n = owner.dim("n")
    P = owner.var("P", n, kind="symmetric", latex=r"\mathcal{P}")
    owner.positive(P)
    user = Theorem("pickletest.user", "u", Source("p", "eq", "c"))
    user.lmi("(1)", [[-P]])
    data = pickle.dumps(user)
    del symbols._METADATA[("pickletest.owner", "P")]
    assert P.latex_name is None
    pickle.loads(data)
    assert P.latex_name == r"\mathcal{P}"
