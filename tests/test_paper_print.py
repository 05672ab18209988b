"""Printed as the paper prints it: a robust LMI alone (``latex --lmi``) in α with its quantifier,
indexed recoveries with their index and quantifier, scheduled recoveries in α, commands naming
the performance as the theorem does, and ``latex --pdf`` leaving the files beside it alone."""
from __future__ import annotations

import pytest

from lmidsl.cli import main
from lmidsl.render.latex_document import lmi_snippet, theorem_latex
from lmidsl.render.report import performance_label

from test_latex import needs_pdflatex


def test_lmi_of_a_robust_theorem_is_printed_in_alpha():
    text = lmi_snippet("textbook.hpd_sf_ct", "(dilated)")
    assert r"A(\alpha) G + G^{T} A(\alpha)^{T}" in text and r"A(\alpha)_i" not in text
    assert "for every vertex" not in text
    assert r"for all $\alpha \in \Lambda_{N}$, where" in text
    assert r"P(\alpha) = \sum_{|k| = g} \alpha^{k} P_{k}" in text


def test_rate_bounded_lmi_prints_the_derivative_and_the_rate_set():
    text = lmi_snippet("textbook.lpv_sf_ct", "(LPV-SF)")
    assert r"- \dot{Y}(\alpha,\dot{\alpha}) < 0" in text
    assert r"\dot{\alpha} \in b\,\mathcal{H}_{N}" in text
    assert r"\frac{\partial Y(\alpha)}{\partial \alpha_i}" in text


def test_recoveries_carry_their_index_and_quantifier():
    assert r"K_i = W_i Y_i^{-1},\quad \forall\, i \in \mathcal{N}" in theorem_latex("textbook.mjls_sf_ct")
    assert r"K(\alpha) = W(\alpha) Y(\alpha)^{-1},\quad \forall\, \alpha \in \Lambda_{N}." in \
        theorem_latex("textbook.lpv_sf_ct")


def test_commands_name_the_performance_as_the_theorem_does():
    assert performance_label("textbook.circle_sector") == "k"
    assert performance_label("textbook.saturated_ellipsoid") == "radius"
    assert performance_label("textbook.brl_ct") == "gamma"


@needs_pdflatex
def test_latex_pdf_keeps_a_log_file_that_was_there(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "doc.log").write_text("my own log\n")
    (tmp_path / "doc.aux").write_text("my own aux\n")
    assert main(["latex", "textbook.brl_ct", "-o", "doc.tex", "--pdf"]) == 0
    assert (tmp_path / "doc.pdf").stat().st_size > 1000
    assert (tmp_path / "doc.log").read_text() == "my own log\n"
    assert (tmp_path / "doc.aux").read_text() == "my own aux\n"
