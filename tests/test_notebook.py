"""Notebook display (issue 28): ``_repr_latex_`` of every theorem and LMI is valid LaTeX (pdflatex
compiles it) and MathJax-safe (no macro or ``$`` inside ``\\text``); the HTML of a Solution, a
Verification and a sweep shows the verdict, γ and the design; IPython gets the renderers by
class name, so no result class imports the render layer."""
from __future__ import annotations

import re
import shutil
import subprocess
import types

import numpy as np
import pytest

import lmidsl
from lmidsl.render import notebook
from lmidsl.theorem.registry import all_theorems, get_theorem

PDFLATEX = shutil.which("pdflatex")


def text_arguments(latex: str) -> list[str]:
    return re.findall(r"\\text\{([^{}]*)\}", latex)


@pytest.mark.skipif(PDFLATEX is None, reason="pdflatex is not installed")
def test_every_theorem_and_lmi_repr_latex_compiles(tmp_path):
    pieces = []
    for tid in sorted(all_theorems()):
        thm = get_theorem(tid)
        pieces.append(thm._repr_latex_())
        pieces += [lmi._repr_latex_() for lmi in thm.lmis[:2]]
    for piece in pieces:
        assert piece.startswith("$$") and piece.endswith("$$") and "$" not in piece[2:-2], piece[:200]
        for arg in text_arguments(piece):
            assert "\\" not in arg and "_" not in arg and "^" not in arg, arg
    doc = ("\\documentclass{article}\\usepackage{amsmath,amssymb}\\setcounter{MaxMatrixCols}{30}"
           "\\begin{document}\n" + "\n\n".join(pieces) + "\n\\end{document}\n")
    (tmp_path / "nb.tex").write_text(doc)
    proc = subprocess.run([PDFLATEX, "-interaction=nonstopmode", "-halt-on-error", "nb.tex"], cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    errors = [l for l in proc.stdout.splitlines() if l.startswith("!")]
    assert proc.returncode == 0 and not errors, errors[:3]


def test_solution_html_shows_verdict_gamma_and_design():
    control = pytest.importorskip("control")
    sol = lmidsl.solve("textbook.hinf_sf_ct")
    page = notebook.html(sol)
    record = sol.verdict
    assert record.line() in page.replace("&#x27;", "'") and record.word.upper() in page
    for level in record.levels.values():                 # the bracket: optimum, back-off, analysis
        if level is not None:
            assert format(level, ".8g") in page
    assert "K = " in page and f"{np.asarray(sol.design['K'])[0, 0]:.5g}" in page
    # the γ shown bounds the closed loop's H∞ norm (python-control); the optimum is below the norm
    norm = control.norm(sol.closed_loop(), "inf")
    shown = {k: float(v) for k, v in re.findall(r"(\w+) ([\d.e+-]+)(?:,|</td>)", page.split("levels")[1].split("</tr>")[0])}
    assert record.certified and norm <= record.gamma * (1 + 1e-7), (norm, record.gamma)
    assert shown["optimum"] <= norm * (1 + 1e-6), (shown, norm)


def test_sweep_html_has_one_row_per_point():
    from lmidsl.studies.sweep import sweep
    from lmidsl.studies.defaults import parse_grid
    result = sweep("wang_l2linf.thm3", [parse_grid("rbar=0.1,0.5", 10)])
    page = notebook.html(result)
    assert page.count("<tr>") == 1 + len(result.points)
    for p in result.points:
        assert format(p.gamma, ".6g") in page


def test_ipython_gets_the_renderers_by_name():
    registered = []
    formatter = types.SimpleNamespace(for_type_by_name=lambda module, name, f: registered.append((module, name, f)))
    shell = types.SimpleNamespace(display_formatter=types.SimpleNamespace(formatters={"text/html": formatter}))
    assert notebook.register_ipython(shell) == ["Solution", "Verification", "SweepResult"]
    modules = {m for m, _, _ in registered}
    assert modules == {"lmidsl.solver.solution", "lmidsl.studies.verify", "lmidsl.studies.sweep"}
    for module, name, _ in registered:                       # the names are right
        assert hasattr(__import__(module, fromlist=[name]), name)


def test_verification_html_shows_the_bracket():
    v = lmidsl.verify("wang_l2linf.thm3", example="paper-full")
    page = notebook.html(v)
    assert v.verdict.word.upper() in page and v.verdict.certified == v.certified
    assert format(v.analysis_gamma, ".8g") in page and format(v.exact.value, ".8g") in page
    # the exact figure of the recovered filter is below the analysis bound, which is below the claim
    assert v.exact.value <= v.analysis_gamma <= v.claimed_gamma * (1 + 1e-6)
    assert "Af = " in page
