"""Decay rate by bisection: max α s.t. AᵢᵀP + PAᵢ + 2αP ≺ 0 at every vertex, P ⪰ I.

Boyd, El Ghaoui, Feron, Balakrishnan, *Linear Matrix Inequalities in System and Control
Theory* (SIAM 1994), §5.1.1: the decay rate is a generalised eigenvalue problem (α multiplies
the variable P), quasi-convex, solved by bisection on α.  P ⪰ I fixes the scale of the
homogeneous condition.  For one system the supremum is −max Re λ(A) (not attained: the
bisection brackets it from below); for a polytope it is the rate a common quadratic Lyapunov
function certifies, at most the smallest vertex rate.

Not one of the five papers: an illustration of ``Theorem.bisect`` (``lmidsl solve`` bisects).
"""
from lmidsl import He, I, Source, Theorem

decay = Theorem("decay_rate.quadratic", "Decay rate by a common quadratic Lyapunov function (GEVP)",
                Source("Boyd et al., LMIs in System and Control Theory", "§5.1.1 (decay rate)",
                       "Boyd, El Ghaoui, Feron, Balakrishnan, Linear Matrix Inequalities in System "
                       "and Control Theory, SIAM 1994"),
                description="max α s.t. AᵢᵀP + PAᵢ + 2αP < 0 at every vertex, P ≥ I; bisection on α.",
                time="continuous", provenance="illustration",
                provenance_note="a textbook GEVP, not from the five papers: the example of Theorem.bisect")
n = decay.dim("n")
A = decay.data("A", n, n, per_vertex=True, description="state matrix (per vertex)")
alpha = decay.param("alpha", latex=r"\alpha", description="decay rate (bisected)")
P = decay.var("P", n, kind="symmetric")
decay.lmi("(decay)", [[He(P * A) + 2 * alpha * P]])
decay.lmi("P >= I", [[P - I]], sense=">=")
decay.feasibility(performance=("alpha", alpha))
decay.bisect("alpha", lower=0.0, upper=10.0, tol=1e-6, goal="max")
decay.example("single", {"A": [[-1.0, 2.0], [0.0, -3.0]]}, params={"alpha": 0.5},
              provenance="illustration", provenance_note="a 2x2 upper-triangular A, eigenvalues −1, −3",
              description="one system: the decay rate is −max Re λ(A) = 1")
decay.example("polytope", {}, params={"alpha": 0.5},
              vertices=[{"A": [[-1.0, 2.0], [0.0, -3.0]]}, {"A": [[-2.0, 0.0], [1.5, -1.0]]}],
              provenance="illustration", provenance_note="two 2x2 vertices chosen for the illustration",
              description="two vertices: the rate of a common quadratic Lyapunov function")

THEOREMS = [decay]
