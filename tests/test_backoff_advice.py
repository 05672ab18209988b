"""The advice to back off is given only where the back-off was not tried: a recovery that fails
(forced here, as on plants whose X − Z is singular at the optimum) under the automatic back-off
names the ladder it tried instead of advising ``--backoff``."""
from __future__ import annotations

import numpy as np
import pytest

import lmidsl
import lmidsl.pipeline as pipeline
from lmidsl.numeric.factorization import balanced_split


@pytest.fixture
def failing_recovery(monkeypatch):
    def refuse(*args, **kwargs):        # the library's own error for a singular I − X Z⁻¹
        balanced_split(np.zeros((2, 2)), "I - X Z^-1")
    monkeypatch.setattr(pipeline, "recover_design", refuse)


def _reasons(sol) -> str:
    return " ".join([sol.message, sol.verdict.why, *sol.verdict.reasons])


def test_no_backoff_advice_after_the_automatic_backoff(failing_recovery):
    sol = lmidsl.solve("textbook.hinf_filter_ct", "random-3")
    assert not sol.verdict.certified
    text = _reasons(sol)
    assert "--backoff" not in text
    assert "automatic back-off" in text and "gave no certified design" in text


def test_backoff_advised_when_it_was_not_tried(failing_recovery):
    sol = lmidsl.solve("textbook.hinf_filter_ct", "random-3", backoff=None)
    assert not sol.verdict.certified
    assert "--backoff" in _reasons(sol)
