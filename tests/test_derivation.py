"""`lmidsl derive-check`: a stated derivation (congruence, Schur complement, change of
variables) checked in exact rational arithmetic at random points, the recovery included."""
from __future__ import annotations

import importlib

import pytest

from lmidsl import I, Source, Theorem
from lmidsl.cli import main
from lmidsl.studies.derivation import check_derivation, check_theorem
from lmidsl.theorem.registry import get_theorem


@pytest.mark.parametrize("theorem_id", ["wang_l2linf.thm2", "wang_l2linf.thm3", "wang_l2linf.cor1"])
def test_wang_derivations_are_exact(theorem_id):
    results = check_theorem(theorem_id)
    assert results and all(r.verdict == "exact" and r.holds for r in results), \
        [r.as_dict() for r in results]
    for r in results:
        assert r.points >= 3
        assert all(rec["verdict"] == "exact" for rec in r.recovery)


def test_theorem3_checked_at_full_and_reduced_order():
    r = check_theorem("wang_l2linf.thm3")[0]
    assert sorted(d["k"] for d in r.dims) == [1, 2]
    assert {rec["name"] for rec in r.recovery} == {"Af", "Bf", "Cf"}


def _wang():
    get_theorem("wang_l2linf.thm3")              # makes sure the package is loaded
    import lmidsl.theorem.registry as registry
    for name in ("lmidsl.theorems.wang_l2linf.theorems", "theorems.wang_l2linf.theorems"):
        try:
            return importlib.import_module(name)
        except ImportError:
            continue
    raise ImportError(registry)


def test_corrupted_copy_fails_with_the_block_named():
    """A copy of Theorem 3 with one sign flipped in block (5,1) of (30): r̄B̂fC -> -r̄B̂fC."""
    wang = _wang()
    bad = Theorem("test.thm3_corrupt", "Theorem 3 with one sign flipped", Source("test", "(30)"))
    wang._synthesis(bad, False, ("(30)", "(31)"))
    sym = {n: d.symbol for n, d in {**bad.data_decl, **bad.var_decl, **bad.param_decl}.items()}
    lmi = next(l for l in bad.lmis if l.label == "(30)")
    lmi.spec.lower[4][0] = sym["V3"].T * sym["A"] - sym["rbar"] * sym["Bf_hat"] * sym["C"]
    bad.example("paper-full", {**wang.PLANT, "E": [[1.0, 0.0], [0.0, 1.0]]}, params={"rbar": 0.8})
    wang._state_theorem3_proof(bad, wang.thm2)
    first, second = check_theorem(bad)
    assert first.verdict == "differs" and first.block == (5, 1), first.as_dict()
    assert first.target_expr == "(-rbar)*Bf_hat*C + V3.T*A"
    assert first.derived_expr and first.entry["target"] != first.entry["derived"]
    assert second.verdict == "exact"                 # (31) is untouched


def test_recovery_without_the_similarity_is_reported():
    """recover ∘ substitute is the identity only up to S = G22⁻¹M: without ``recovers`` the
    check says so (Af, Bf differ; Cf = Ĉf = Cf G22⁻¹M differs too)."""
    wang = _wang()
    d = get_theorem("wang_l2linf.thm3").derivations[0]
    from dataclasses import replace
    result = check_derivation("wang_l2linf.thm3", replace(d, recovers={}))
    assert result.verdict == "exact" and not result.holds
    assert {r["name"]: r["verdict"] for r in result.recovery} == \
        {"Af": "differs", "Bf": "differs", "Cf": "differs"}
    assert wang.thm3.derivations[0].recovers


def test_schur_step():
    """(s) = −P + CᵀC is the Schur complement of [[−P], [C, −I]] in its block 2."""
    src = Theorem("test.schur_src", "source", Source("test", "(a)"))
    n, p = src.dim("n p")
    C = src.data("C", p, n)
    P = src.var("P", n, kind="symmetric")
    src.lmi("(a)", [[-P], [C, -I]])
    tgt = Theorem("test.schur_tgt", "target", Source("test", "(s)"))
    n, p = tgt.dim("n p")
    C2 = tgt.data("C", p, n)
    P2 = tgt.var("P", n, kind="symmetric")
    tgt.lmi("(s)", [[-P2 + C2.T * C2]])
    tgt.derived_from(src, "(a)", "(s)", schur=[2])
    assert check_derivation(tgt, tgt.derivations[0], dims={"n": 3, "p": 2}).verdict == "exact"
    tgt.lmi("(s')", [[-P2 + 2 * C2.T * C2]])
    tgt.derived_from(src, "(a)", "(s')", schur=[2])
    wrong = check_derivation(tgt, tgt.derivations[1], dims={"n": 3, "p": 2})
    assert wrong.verdict == "differs" and wrong.block == (1, 1)


def test_declaration_errors():
    thm = get_theorem("wang_l2linf.thm3")
    with pytest.raises(Exception, match="no LMI"):
        thm.derived_from(get_theorem("wang_l2linf.thm2"), "(99)", "(30)")


def test_cli_exit_codes(capsys):
    assert main(["derive-check", "wang_l2linf.thm3"]) == 0
    assert "exact" in capsys.readouterr().out
    assert main(["derive-check", "wang_l2linf.thm1"]) == 2
    assert main(["derive-check", "wang_l2linf.thm3", "--dims", "n=x"]) == 2


def test_seed_001_printed_9_congruence_is_exact():
    """li_delay_dropout: thm1's (9) is the printed (9) (N = P⁻¹) under diag(I, I, P, P, P, P, I, I);
    σ1..σ4 (square roots) are drawn as free scalars; no example: generic dimension sets."""
    (r,) = check_theorem("li_delay_dropout.thm1")
    assert r.verdict == "exact" and r.holds, r.as_dict()
    assert r.free == ["sigma1", "sigma2", "sigma3", "sigma4"] and len(r.dims) == 2


def test_seed_001_wrong_congruence_is_named():
    from dataclasses import replace
    thm1 = get_theorem("li_delay_dropout.thm1")
    P = thm1.var_decl["P"].symbol
    bad = replace(thm1.derivations[0], congruence=(I, I, P, P, P, I, I, I))   # no P on block 6
    r = check_derivation(thm1, bad)
    assert r.verdict == "differs" and r.block == (6, 1) and r.target_expr.startswith("sigma3*P*")


def test_seed_001_theorem_2_from_printed_9_is_exact_with_identity_recovery():
    """(15) = (TD)ᵀ (9) (TD), T = diag(Σ2, I, Σ1, Σ1, Σ1, Σ1, I, I), D = diag(I, Z) per Λ block, with
    Âf = RAfSᵀZ, B̂f = RBf, Ĉf = CfSᵀZ, D̂f = Df: exact, and the recovery (with R, S defined by
    the derivation instead of rs_split) gives back Af, Bf, Cf, Df."""
    (r,) = check_theorem("li_delay_dropout.thm2")
    assert r.verdict == "exact" and r.holds, r.as_dict()
    assert {rec["name"]: rec["verdict"] for rec in r.recovery} == dict.fromkeys(["Af", "Bf", "Cf", "Df"], "exact")
    from dataclasses import replace
    thm2 = get_theorem("li_delay_dropout.thm2")
    d = thm2.derivations[0]
    bf_hat = thm2.var_decl["Bf_hat"].symbol
    wrong = dict(d.substitute)
    wrong[bf_hat] = 2 * wrong[bf_hat]                  # B̂f = 2RBf: the first Θ block with B̂f differs
    bad = check_derivation(thm2, replace(d, substitute=wrong))
    assert bad.verdict == "differs" and bad.block == (3, 1)
