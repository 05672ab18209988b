"""Switched linear systems under arbitrary switching: a common quadratic Lyapunov function.

ẋ = A_σ(t) x with σ switching arbitrarily among N subsystems is exponentially stable with rate
α when some P ≻ 0 satisfies He(PAᵢ) + 2αP ≺ 0 for every subsystem i (Liberzon, *Switching in
Systems and Control*, Birkhauser 2003, §2.1; Boyd et al., *Linear Matrix Inequalities in System
and Control Theory*, SIAM 1994, §5.1): then V = xᵀPx decays as e^{−2αt} whatever σ does, and
‖x(t)‖ ≤ √κ(P) e^{−αt} ‖x(0)‖.  The largest such α is found by bisection (α multiplies P:
a generalised eigenvalue problem); P ⪰ I fixes the scale.

Data ``{"subsystems": [{"A": …}, …]}``.  The polytopic decay rate of ``decay_rate.quadratic``
(per-vertex data) is the same statement with the vertices as the index set.
"""
from lmidsl import He, I, Source, Theorem

LIB = "Liberzon, Switching in Systems and Control, Birkhauser 2003"

switched_clf_ct = Theorem("textbook.switched_clf_ct",
                          "Switched system under arbitrary switching: common quadratic Lyapunov function",
                          Source("Liberzon 2003", "§2.1, common Lyapunov function; decay rate by bisection", LIB),
                          time="continuous",
                          description="max α s.t. He(PAᵢ) + 2αP ≺ 0 for every subsystem i, P ⪰ I")
n = switched_clf_ct.dim("n")
S = switched_clf_ct.index_set("subsystems", size="N", latex=r"\mathcal{S}")
i = S.indices("i")
A = switched_clf_ct.data("A", n, n, over=S, description="state matrix of subsystem i")
alpha = switched_clf_ct.param("alpha", latex=r"\alpha", description="decay rate (bisected)")
P = switched_clf_ct.var("P", n, kind="symmetric", description="common Lyapunov matrix")
switched_clf_ct.lmi("(CLF)", [[He(P * A[i]) + 2 * alpha * P]], forall=i)
switched_clf_ct.lmi("P >= I", [[P - I]], sense=">=")
switched_clf_ct.feasibility(performance=("alpha", alpha))
switched_clf_ct.bisect("alpha", lower=0.0, upper=10.0, tol=1e-5, goal="max",
                       performance="the largest decay rate a common quadratic Lyapunov function certifies")
switched_clf_ct.example("two-subsystems", {"subsystems": [{"A": [[-1.0, 2.0], [0.0, -3.0]]},
                                                          {"A": [[-2.0, 0.0], [1.5, -1.0]]}]},
                        params={"alpha": 0.5}, provenance="illustration",
                        provenance_note="the two vertices of decay_rate.quadratic's polytope example, "
                                        "as switched subsystems")

THEOREMS = [switched_clf_ct]
